#include "caustix/runtime/image_output.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <filesystem>

#include "caustix/formats/file_io.h"

namespace caustix::runtime {
namespace {

Status write_image(const std::string& path, int w, int h, int channels, OIIO::TypeDesc type, const void* data,
                   const std::vector<std::pair<std::string, std::string>>& attributes = {}) {
  if (w <= 0 || h <= 0 || channels <= 0) return make_error(ErrorCode::kInternal, path + ": empty image");
  auto temp = TempFile::create_beside(path);
  if (!temp) return temp.error();
  auto out = OIIO::ImageOutput::create(path);
  if (!out) {
    return make_error(ErrorCode::kOutput, path + ": no image writer for this extension (" + OIIO::geterror() + ")");
  }
  OIIO::ImageSpec spec(w, h, channels, type);
  if (type == OIIO::TypeDesc::FLOAT) spec.attribute("compression", "zip");
  for (const auto& [name, value] : attributes) spec.attribute(name, value);
  if (!out->open(temp->path(), spec) || !out->write_image(type, data) || !out->close()) {
    return make_error(ErrorCode::kOutput, path + ": writing the image failed: " + out->geterror());
  }
  return temp->commit();
}

}  // namespace

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

Status write_u8_image(const std::string& path, int w, int h, int channels, const std::vector<std::uint8_t>& px) {
  if (px.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(channels)) {
    return make_error(ErrorCode::kInternal, path + ": pixel buffer size mismatch");
  }
  return write_image(path, w, h, channels, OIIO::TypeDesc::UINT8, px.data());
}

}  // namespace caustix::runtime
