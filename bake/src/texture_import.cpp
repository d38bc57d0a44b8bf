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
  const std::string who = (src.where.empty() ? "" : src.where + ": ") + "image '" + (src.path.empty() ? src.name : src.path) + "'";
  auto fail = [&](const std::string& msg) { return make_error(ErrorCode::kInput, who + ": " + msg); };

  // Embedded bytes are read through a memory proxy; the extension tells
  // OpenImageIO which reader to use.
  OIIO::Filesystem::IOMemReader memory(src.bytes.data(), src.bytes.size());
  std::string open_name = src.path;
  if (src.path.empty()) {
    if (src.mime_type == "image/png") open_name = "embedded.png";
    else if (src.mime_type == "image/jpeg") open_name = "embedded.jpg";
    else return fail("embedded image of type '" + src.mime_type + "' (glTF allows image/png and image/jpeg)");
  }
  OIIO::ImageBuf in(open_name, 0, 0, nullptr, nullptr, src.path.empty() ? &memory : nullptr);
  const OIIO::ImageSpec spec = in.spec();  // the header only
  if (in.has_error() || spec.width < 1 || spec.height < 1 || spec.nchannels < 1) {
    const std::string why = in.geterror();
    return fail("cannot be read: " + (why.empty() ? std::string("not an image") : why));
  }
  // The pixels are held in their own type (8 bits: one byte a channel), so
  // the largest image this reads is 16384^2 x 4 channels, 1 GiB.
  if (spec.width > 16384 || spec.height > 16384) {
    return fail("is " + std::to_string(spec.width) + " x " + std::to_string(spec.height) + " texels; at most 16384 a side is read");
  }
  const bool linear = spec.format.is_floating_point() && !src.data;
  if (!in.read(0, 0, /*force=*/true)) return fail("cannot be decoded: " + in.geterror());

  // RGB (grey replicated), then alpha where asked and present (OpenImageIO
  // names it: the 4th of RGBA, the 2nd of grey-alpha), further channels
  // dropped; then fitted to max_size.
  const int grey = spec.nchannels < 3 ? 0 : 1;
  const int alpha = src.keep_alpha ? spec.alpha_channel : -1;
  const int channels = alpha >= 0 ? 4 : 3;
  const int order[4] = {0, grey, 2 * grey, alpha};
  OIIO::ImageBuf rgb = OIIO::ImageBufAlgo::channels(in, channels, order);
  if (rgb.has_error()) return fail("cannot be converted: " + rgb.geterror());
  int w = spec.width, h = spec.height;
  const int limit = static_cast<int>(std::clamp<std::uint32_t>(max_size, 1, kMaxTextureSize));
  if (w > limit || h > limit) {
    const double f = static_cast<double>(limit) / std::max(w, h);
    w = std::max(1, static_cast<int>(std::lround(w * f)));
    h = std::max(1, static_cast<int>(std::lround(h * f)));
    OIIO::ImageBuf fitted;
    if (!OIIO::ImageBufAlgo::resize(fitted, rgb, "", 0, OIIO::ROI(0, w, 0, h, 0, 1, 0, channels))) {
      return fail("cannot be resized: " + fitted.geterror());
    }
    rgb = std::move(fitted);
  }
  const auto c = static_cast<std::size_t>(channels);
  std::vector<float> values(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * c);
  if (!rgb.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, channels), OIIO::TypeDesc::FLOAT, values.data())) return fail("cannot be converted");

  TextureImage out;
  out.source = src.name;
  out.width = static_cast<std::uint32_t>(w);
  out.height = static_cast<std::uint32_t>(h);
  const std::size_t texels = values.size() / c;
  out.rgb.resize(texels * 3);
  if (alpha >= 0) out.alpha.resize(texels);
  const auto byte = [](float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float v = values[i];
    if (!std::isfinite(v)) return fail("holds a value that is not a finite number");
    const std::size_t p = i / c, k = i % c;
    if (k == 3) out.alpha[p] = byte(v);  // alpha is linear whatever the colour's encoding
    else out.rgb[3 * p + k] = byte(linear ? linear_to_srgb(v) : v);
  }
  // An alpha channel that is everywhere 1 changes nothing.
  if (std::all_of(out.alpha.begin(), out.alpha.end(), [](std::uint8_t a) { return a == 255; })) out.alpha.clear();
  return out;
}

}  // namespace caustix::bake
