#pragma once
// Image files through OpenImageIO; the format follows the extension (.exr
// keeps linear float, .png/.jpg/.tif get 8-bit display values). Written
// atomically: a temporary file beside the output, renamed when complete.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "caustix/common/status.h"

namespace caustix::runtime {

// `pixels` is top row first, `channels` interleaved floats per pixel.
// `attributes` are written as string metadata (e.g. "caustix:region").
Status write_float_image(const std::string& path, int width, int height, int channels,
                         const std::vector<float>& pixels,
                         const std::vector<std::pair<std::string, std::string>>& attributes = {});
Status write_u8_image(const std::string& path, int width, int height, int channels,
                      const std::vector<std::uint8_t>& pixels);

// Whether the extension names a float format (EXR, HDR, float TIFF is not
// assumed): decides between linear and display output.
bool is_float_image_path(const std::string& path);

}  // namespace caustix::runtime
