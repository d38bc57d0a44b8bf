#include "albedo_textures.h"

#include <algorithm>
#include <bit>

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

AlbedoTextures upload_albedo_textures(const SceneDesc& scene) {
  AlbedoTextures out;
  out.of_object.assign(scene.objects.size(), 0);
  // Rows of 4-byte texels from the start of client memory, whatever the
  // application left in the unpack state.
  GLint saved[5] = {};
  const GLenum names[5] = {GL_UNPACK_ALIGNMENT, GL_UNPACK_ROW_LENGTH, GL_UNPACK_SKIP_ROWS, GL_UNPACK_SKIP_PIXELS, GL_PIXEL_UNPACK_BUFFER_BINDING};
  for (int i = 0; i < 5; ++i) glGetIntegerv(names[i], &saved[i]);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
  glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  const bool anisotropic = epoxy_gl_version() >= 46 || epoxy_has_gl_extension("GL_ARB_texture_filter_anisotropic") ||
                           epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic");

  std::vector<std::uint8_t> rgba;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const auto& t = scene.objects[i].material.albedo_texture;
    if (!t || t->image >= scene.images.size()) continue;
    const auto key = std::tuple{t->image, t->wrap_s, t->wrap_t};
    auto it = out.textures.find(key);
    if (it == out.textures.end()) {
      const TextureImage& im = scene.images[t->image];
      const auto w = static_cast<GLsizei>(im.width), h = static_cast<GLsizei>(im.height);
      const GLsizei levels = static_cast<GLsizei>(std::bit_width(static_cast<std::uint32_t>(std::max(w, h))));
      rgba.resize(std::size_t{im.width} * im.height * 4);
      for (std::size_t p = 0; p < rgba.size() / 4; ++p) {
        std::copy_n(im.rgb.data() + 3 * p, 3, rgba.data() + 4 * p);
        rgba[4 * p + 3] = 255;
      }
      gl::Texture tex = gl::make_texture(GL_TEXTURE_2D);
      const GLuint id = tex.get();
      glTextureStorage2D(id, levels, GL_SRGB8_ALPHA8, w, h);
      glTextureSubImage2D(id, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
      glGenerateTextureMipmap(id);
      glTextureParameteri(id, GL_TEXTURE_WRAP_S, gl_wrap(t->wrap_s));
      glTextureParameteri(id, GL_TEXTURE_WRAP_T, gl_wrap(t->wrap_t));
      glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      if (anisotropic) glTextureParameterf(id, GL_TEXTURE_MAX_ANISOTROPY, 8.0f);
      // The mip chain: 4/3 of the base level.
      out.gpu_bytes += std::uint64_t{im.width} * im.height * 4 * 4 / 3;
      it = out.textures.emplace(key, std::move(tex)).first;
    }
    out.of_object[i] = it->second.get();
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, saved[0]);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, saved[1]);
  glPixelStorei(GL_UNPACK_SKIP_ROWS, saved[2]);
  glPixelStorei(GL_UNPACK_SKIP_PIXELS, saved[3]);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(saved[4]));
  return out;
}

}  // namespace caustix::runtime
