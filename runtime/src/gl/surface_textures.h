#pragma once
// Receivers' textures on the GPU: one GL texture per (image, colour or
// data, wrap s, wrap t) the scene uses, RGBA8 with a full mip chain (sRGB
// for colour: base colour and emission; linear for data: metallic-roughness,
// normal, occlusion), wrap and trilinear (and, where the context has it, 8x
// anisotropic) filtering set on the texture itself. A base colour's alpha
// is its image's (TextureImage::alpha), else 1. Internal to the runtime.

#include <array>
#include <map>
#include <tuple>
#include <vector>

#include "caustix/formats/scene.h"
#include "gl_objects.h"

namespace caustix::runtime {

struct SurfaceTextures {
  std::vector<GLuint> albedo;                // per object: its base colour texture, or 0
  std::vector<std::array<GLuint, 4>> maps;   // per object: metallic-roughness, normal, occlusion, emission (0: none)
  std::map<std::tuple<std::uint32_t, bool, TextureWrap, TextureWrap>, gl::Texture> textures;
  std::uint64_t gpu_bytes = 0;
};

// Uploads what `scene`'s receivers use. Leaves GL_UNPACK_* state as it
// found it.
SurfaceTextures upload_surface_textures(const SceneDesc& scene);

}  // namespace caustix::runtime
