#pragma once
// Receivers' textures (base colour and glTF's other maps): image files or glTF
// images read through OpenImageIO into what the .cxb stores (8-bit
// sRGB-encoded RGB, top row first; formats/scene.h TextureImage).
//
//  - 8-bit and 16-bit integer images are taken as sRGB-encoded (glTF's
//    baseColorTexture is sRGB by definition, and so are the PNGs and JPEGs
//    artists paint); float images (EXR, HDR) hold linear values and are
//    encoded to sRGB.
//  - Grey images give equal RGB; alpha is kept where asked
//    (ImageSource::keep_alpha), further channels are dropped.
//  - Data images (ImageSource::data: normals, roughness, occlusion) keep
//    their values, float ones too.
//  - An image larger than `max_size` texels a side is filtered down to fit
//    (aspect ratio kept; OpenImageIO's resize with its default filter).
//  - Images over 16384 texels a side are refused: their pixels are held in
//    their own type before filtering (1 GiB for 16384^2 8-bit RGBA).
//
// Errors (kInput) name the image and say where it was named from.

#include <cstdint>
#include <string>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"

namespace caustix::bake {

struct ImageSource {
  std::string name;                 // the file as the scene or glTF file names it, or the glTF image's pointer and name
  std::string path;                 // a file to read; empty when `bytes` holds the encoded image
  std::vector<std::uint8_t> bytes;  // an embedded image (glTF data URI or buffer view)
  std::string mime_type;            // of `bytes`: "image/png" or "image/jpeg" (glTF's two)
  std::string where;                // the place that named it ("scene.json:12:7: /objects/0/material/albedo_texture")
  // An image a glTF file names: if it cannot be read the baker warns and
  // its receivers keep their base colour factor (a texture changes a
  // receiver's colour, never the light). One scene.json names is an error.
  bool fall_back = false;
  // Data, not colour (glTF's metallic-roughness, normal and occlusion
  // textures): float images are stored as their values, not sRGB-encoded.
  bool data = false;
  // Keep the image's alpha (TextureImage::alpha; a base colour that masks
  // or blends): images without an alpha channel get none.
  bool keep_alpha = false;
};

inline constexpr std::uint32_t kDefaultMaxTextureSize = 2048;

Result<TextureImage> read_texture(const ImageSource& source, std::uint32_t max_size = kDefaultMaxTextureSize);

}  // namespace caustix::bake
