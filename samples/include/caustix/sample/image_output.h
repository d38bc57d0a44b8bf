#pragma once
// Image files through OpenImageIO (written and read back); the format follows the extension (.exr
// keeps linear float, .png/.jpg/.tif get 8-bit display values). Written
// atomically: a temporary file beside the output, renamed when complete.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "caustix/common/status.h"

namespace caustix::sample {

// `pixels` is top row first, `channels` interleaved floats per pixel.
// `attributes` are written as string metadata (e.g. "caustix:region").
Status write_float_image(const std::string& path, int width, int height, int channels,
                         const std::vector<float>& pixels,
                         const std::vector<std::pair<std::string, std::string>>& attributes = {});
Status write_u8_image(const std::string& path, int width, int height, int channels,
                      const std::vector<std::uint8_t>& pixels);

// kOutput if OpenImageIO has no writer for the path's extension: lets a
// program refuse its output before the work that would fill it.
Status check_image_writer(const std::string& path);

// An image read back as linear RGB floats (grey images give equal RGB,
// extra channels such as alpha are dropped), with its string metadata.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // top row first
  std::vector<std::pair<std::string, std::string>> attributes;
  // The value of a string attribute, or "" if the image has none.
  std::string attribute(const std::string& name) const;
  // The world rectangle x0, z0, x1, z1 of an irradiance image
  // ("caustix:region"), if it carries a well-formed one.
  std::optional<std::array<double, 4>> region() const;
};
// Errors (kInput) name the file: unreadable, not an image, larger than
// 65536 pixels a side.
Result<RgbImage> read_rgb_image(const std::string& path);

// Whether the extension names a float format (EXR, HDR, float TIFF is not
// assumed): decides between linear and display output.
bool is_float_image_path(const std::string& path);

}  // namespace caustix::sample
