#include "surface_textures.h"

#include <algorithm>
#include <bit>

#include "gl_state.h"

namespace caustix::runtime {
namespace {

GLint gl_wrap(TextureWrap w) {
  switch (w) {
    case TextureWrap::kClamp: return GL_CLAMP_TO_EDGE;
    case TextureWrap::kMirror: return GL_MIRRORED_REPEAT;
    case TextureWrap::kRepeat: break;
  }
  return GL_REPEAT;
}

}  // namespace

SurfaceTextures upload_surface_textures(const SceneDesc& scene) {
  SurfaceTextures out;
  out.albedo.assign(scene.objects.size(), 0);
  out.maps.assign(scene.objects.size(), {0, 0, 0, 0});
  // Rows of 4-byte texels from the start of client memory, whatever the
  // application left in the unpack state.
  const gl::ClientUnpack unpack(4);
  const bool anisotropic = epoxy_gl_version() >= 46 || epoxy_has_gl_extension("GL_ARB_texture_filter_anisotropic") ||
                           epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic");

  std::vector<std::uint8_t> rgba;
  const auto upload = [&](const MapTexture& t, bool data) -> GLuint {
    if (t.image >= scene.images.size()) return 0;
    const auto key = std::tuple{t.image, data, t.wrap_s, t.wrap_t};
    auto it = out.textures.find(key);
    if (it == out.textures.end()) {
      const TextureImage& im = scene.images[t.image];
      const auto w = static_cast<GLsizei>(im.width), h = static_cast<GLsizei>(im.height);
      const GLsizei levels = static_cast<GLsizei>(std::bit_width(static_cast<std::uint32_t>(std::max(w, h))));
      rgba.resize(std::size_t{im.width} * im.height * 4);
      const bool alpha = !data && im.alpha.size() == rgba.size() / 4;
      for (std::size_t p = 0; p < rgba.size() / 4; ++p) {
        std::copy_n(im.rgb.data() + 3 * p, 3, rgba.data() + 4 * p);
        rgba[4 * p + 3] = alpha ? im.alpha[p] : 255;
      }
      gl::Texture tex = gl::make_texture(GL_TEXTURE_2D);
      const GLuint id = tex.get();
      glTextureStorage2D(id, levels, data ? GL_RGBA8 : GL_SRGB8_ALPHA8, w, h);
      glTextureSubImage2D(id, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
      glGenerateTextureMipmap(id);
      glTextureParameteri(id, GL_TEXTURE_WRAP_S, gl_wrap(t.wrap_s));
      glTextureParameteri(id, GL_TEXTURE_WRAP_T, gl_wrap(t.wrap_t));
      glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      if (anisotropic) glTextureParameterf(id, GL_TEXTURE_MAX_ANISOTROPY, 8.0f);
      // The mip chain: 4/3 of the base level.
      out.gpu_bytes += std::uint64_t{im.width} * im.height * 4 * 4 / 3;
      it = out.textures.emplace(key, std::move(tex)).first;
    }
    return it->second.get();
  };
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Material& m = scene.objects[i].material;
    if (m.albedo_texture) out.albedo[i] = upload(*m.albedo_texture, false);
    if (!m.maps) continue;
    const std::array<std::pair<const std::optional<MapTexture>*, bool>, 4> slots{
        {{&m.maps->metallic_roughness, true}, {&m.maps->normal, true}, {&m.maps->occlusion, true}, {&m.maps->emissive, false}}};
    for (std::size_t k = 0; k < slots.size(); ++k) {
      if (*slots[k].first) out.maps[i][k] = upload(**slots[k].first, slots[k].second);
    }
  }
  return out;
}

}  // namespace caustix::runtime
