#include "caustix/bake/texture_import.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

namespace caustix::bake {
namespace {

// sRGB transfer function (IEC 61966-2-1), linear -> encoded, in [0, 1].
float linear_to_srgb(float c) {
  c = std::clamp(std::isfinite(c) ? c : 0.0f, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

Result<TextureImage> read_texture(const ImageSource& src, std::uint32_t max_size) {
  const std::string who = (src.where.empty() ? "" : src.where + ": ") + "image '" + src.name + "'";
  auto fail = [&](const std::string& msg) { return make_error(ErrorCode::kInput, who + ": " + msg); };

  // Embedded bytes are read through a memory proxy; the extension tells
  // OpenImageIO which reader to use.
  OIIO::Filesystem::IOMemReader memory(src.bytes.data(), src.bytes.size());
  std::string open_name = src.path;
  OIIO::ImageSpec config;
  if (src.path.empty()) {
    if (src.mime_type == "image/png") open_name = "embedded.png";
    else if (src.mime_type == "image/jpeg") open_name = "embedded.jpg";
    else return fail("embedded image of type '" + src.mime_type + "' (glTF allows image/png and image/jpeg)");
    OIIO::Filesystem::IOProxy* proxy = &memory;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  }
  auto in = OIIO::ImageInput::open(open_name, &config);
  if (!in) return fail("cannot be read: " + OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.width > 65536 || spec.height > 65536 || spec.nchannels < 1) {
    return fail("is " + std::to_string(spec.width) + " x " + std::to_string(spec.height) + " with " +
                std::to_string(spec.nchannels) + " channel(s); 1..65536 a side and at least one channel expected");
  }
  const bool linear = spec.format.is_floating_point();
  std::vector<float> px(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) * static_cast<std::size_t>(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data())) return fail("cannot be decoded: " + in->geterror());
  in->close();

  // RGB floats (grey replicated, alpha dropped), then fitted to max_size.
  OIIO::ImageBuf rgb(OIIO::ImageSpec(spec.width, spec.height, 3, OIIO::TypeDesc::FLOAT));
  {
    std::vector<float> three(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) * 3);
    const auto nc = static_cast<std::size_t>(spec.nchannels);
    for (std::size_t i = 0; i < three.size() / 3; ++i) {
      for (std::size_t k = 0; k < 3; ++k) three[3 * i + k] = px[nc * i + (nc >= 3 ? k : 0)];
    }
    rgb.set_pixels(OIIO::ROI(0, spec.width, 0, spec.height, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, three.data());
  }
  int w = spec.width, h = spec.height;
  const int limit = static_cast<int>(std::clamp<std::uint32_t>(max_size, 1, kMaxTextureSize));
  if (w > limit || h > limit) {
    const double f = static_cast<double>(limit) / std::max(w, h);
    w = std::max(1, static_cast<int>(std::lround(w * f)));
    h = std::max(1, static_cast<int>(std::lround(h * f)));
    OIIO::ImageBuf fitted;
    if (!OIIO::ImageBufAlgo::resize(fitted, rgb, "", 0, OIIO::ROI(0, w, 0, h, 0, 1, 0, 3))) {
      return fail("cannot be resized: " + fitted.geterror());
    }
    rgb = std::move(fitted);
  }
  std::vector<float> values(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  if (!rgb.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, values.data())) return fail("cannot be converted");

  TextureImage out;
  out.source = src.name;
  out.width = static_cast<std::uint32_t>(w);
  out.height = static_cast<std::uint32_t>(h);
  out.rgb.resize(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    float v = values[i];
    if (!std::isfinite(v)) return fail("holds a value that is not a finite number");
    if (linear) v = linear_to_srgb(v);
    out.rgb[i] = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
  }
  return out;
}

}  // namespace caustix::bake
