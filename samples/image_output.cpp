#include "caustix/sample/image_output.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "caustix/formats/file_io.h"

namespace caustix::sample {
namespace {

Status no_writer(const std::string& path) {
  return make_error(ErrorCode::kOutput, path + ": no image writer for this extension (" + OIIO::geterror() + ")");
}

Status write_image(const std::string& path, int w, int h, int channels, OIIO::TypeDesc type, const void* data,
                   const std::vector<std::pair<std::string, std::string>>& attributes = {}) {
  if (w <= 0 || h <= 0 || channels <= 0) return make_error(ErrorCode::kInternal, path + ": empty image");
  auto temp = TempFile::create_beside(path);
  if (!temp) return temp.error();
  auto out = OIIO::ImageOutput::create(path);
  if (!out) return no_writer(path);
  OIIO::ImageSpec spec(w, h, channels, type);
  if (type == OIIO::TypeDesc::FLOAT) spec.attribute("compression", "zip");
  for (const auto& [name, value] : attributes) spec.attribute(name, value);
  if (!out->open(temp->path(), spec) || !out->write_image(type, data) || !out->close()) {
    return make_error(ErrorCode::kOutput, path + ": writing the image failed: " + out->geterror());
  }
  return temp->commit();
}

}  // namespace

Status check_image_writer(const std::string& path) {
  return OIIO::ImageOutput::create(path) ? Status{} : no_writer(path);
}

bool is_float_image_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".exr" || ext == ".hdr" || ext == ".pfm";
}

Status write_float_image(const std::string& path, int w, int h, int channels, const std::vector<float>& px,
                         const std::vector<std::pair<std::string, std::string>>& attributes) {
  if (px.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(channels)) {
    return make_error(ErrorCode::kInternal, path + ": pixel buffer size mismatch");
  }
  return write_image(path, w, h, channels, OIIO::TypeDesc::FLOAT, px.data(), attributes);
}

std::string RgbImage::attribute(const std::string& name) const {
  for (const auto& [key, value] : attributes) {
    if (key == name) return value;
  }
  return {};
}

std::optional<std::array<double, 4>> RgbImage::region() const {
  std::array<double, 4> r{};
  char extra = 0;
  if (std::sscanf(attribute("caustix:region").c_str(), "%lf,%lf,%lf,%lf%c", &r[0], &r[1], &r[2], &r[3], &extra) != 4) {
    return std::nullopt;
  }
  return r;
}

Result<RgbImage> read_rgb_image(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return make_error(ErrorCode::kInput, path + ": cannot read: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.width > 65536 || spec.height > 65536) {
    return make_error(ErrorCode::kInput, path + ": unsupported image size");
  }
  RgbImage out;
  out.width = spec.width;
  out.height = spec.height;
  const auto c = static_cast<std::size_t>(spec.nchannels);
  std::vector<float> px(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) * c);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data())) {
    return make_error(ErrorCode::kInput, path + ": read failed: " + in->geterror());
  }
  out.rgb.reserve(px.size() / c * 3);
  for (std::size_t i = 0; i < px.size(); i += c) {
    for (std::size_t k = 0; k < 3; ++k) out.rgb.push_back(px[i + std::min(k, c - 1)]);
  }
  for (const OIIO::ParamValue& p : spec.extra_attribs) {
    if (p.type() == OIIO::TypeDesc::STRING) out.attributes.emplace_back(p.name().string(), p.get_string());
  }
  return out;
}

Status write_u8_image(const std::string& path, int w, int h, int channels, const std::vector<std::uint8_t>& px) {
  if (px.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(channels)) {
    return make_error(ErrorCode::kInternal, path + ": pixel buffer size mismatch");
  }
  return write_image(path, w, h, channels, OIIO::TypeDesc::UINT8, px.data());
}

}  // namespace caustix::sample
