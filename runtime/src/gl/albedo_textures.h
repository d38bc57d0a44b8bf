#pragma once
// Receivers' albedo textures on the GPU: one GL texture per
// (image, wrap s, wrap t) the scene uses, sRGB8_ALPHA8 with a full mip
// chain, wrap and trilinear (and, where the context has it, 8x anisotropic)
// filtering set on the texture itself. Internal to the runtime.

#include <map>
#include <tuple>
#include <vector>

#include "caustix/formats/scene.h"
#include "gl_objects.h"

namespace caustix::runtime {

struct AlbedoTextures {
  std::vector<GLuint> of_object;  // per object: its texture, or 0
  std::map<std::tuple<std::uint32_t, TextureWrap, TextureWrap>, gl::Texture> textures;
  std::uint64_t gpu_bytes = 0;
};

// Uploads what `scene`'s receivers use. Leaves GL_UNPACK_* state as it
// found it.
AlbedoTextures upload_albedo_textures(const SceneDesc& scene);

}  // namespace caustix::runtime
