#pragma once
// Copies of the caller's scene colour (2D GL_RGBA32F) and depth (2D
// GL_DEPTH_COMPONENT32F), for passes that sample them while the originals
// are attached to the bound framebuffer (draw_media), and the checks that
// tell when they are.
// Internal to the runtime.

#include <epoxy/gl.h>

#include <cstdint>

#include "caustix/runtime/gl_objects.h"

namespace caustix::runtime::gl {

class SceneCopy {
 public:
  // Copies `color` and `depth` (either may be 0; the same size), re-making
  // the copies when the size changes.
  void copy(GLuint color, GLuint depth) {
    const GLuint sized = depth != 0 ? depth : color;
    GLint w = 0, h = 0;
    glGetTextureLevelParameteriv(sized, 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(sized, 0, GL_TEXTURE_HEIGHT, &h);
    if (w != w_ || h != h_ || (color != 0 && !color_.get()) || (depth != 0 && !depth_.get())) {
      color_ = Texture();
      depth_ = Texture();
      if (color != 0) color_ = make(GL_RGBA32F, w, h);
      if (depth != 0) depth_ = make(GL_DEPTH_COMPONENT32F, w, h);
      w_ = w;
      h_ = h;
    }
    if (color) glCopyImageSubData(color, GL_TEXTURE_2D, 0, 0, 0, 0, color_.get(), GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
    if (depth) glCopyImageSubData(depth, GL_TEXTURE_2D, 0, 0, 0, 0, depth_.get(), GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
  }
  GLuint color() const { return color_.get(); }
  GLuint depth() const { return depth_.get(); }
  std::uint64_t gpu_bytes() const {
    return std::uint64_t(w_) * static_cast<std::uint64_t>(h_) * ((color_.get() ? 16 : 0) + (depth_.get() ? 4 : 0));
  }

 private:
  static Texture make(GLenum format, int w, int h) {
    Texture t = make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(t.get(), 1, format, w, h);
    set_sampling(t.get(), GL_NEAREST);
    return t;
  }
  Texture color_, depth_;
  int w_ = 0, h_ = 0;
};

// Whether `texture` is attached to the framebuffer bound for drawing (a
// pass that samples it while drawing there needs a copy of it).
inline bool attached_to_draw_framebuffer(GLuint texture) {
  GLint fbo = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fbo);
  if (fbo == 0 || texture == 0) return false;
  GLint colors = 0;
  glGetIntegerv(GL_MAX_COLOR_ATTACHMENTS, &colors);
  auto holds = [&](GLenum attachment) {
    GLint type = GL_NONE, name = 0;
    glGetNamedFramebufferAttachmentParameteriv(static_cast<GLuint>(fbo), attachment, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type != GL_TEXTURE) return false;
    glGetNamedFramebufferAttachmentParameteriv(static_cast<GLuint>(fbo), attachment, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    return static_cast<GLuint>(name) == texture;
  };
  if (holds(GL_DEPTH_ATTACHMENT) || holds(GL_STENCIL_ATTACHMENT)) return true;
  for (GLint i = 0; i < colors; ++i) {
    if (holds(static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i))) return true;
  }
  return false;
}

// Whether the bound draw framebuffer draws into `texture` alone: one draw
// buffer, with `texture` attached to it (what dual-source blending can
// composite over in place).
inline bool draws_only_into(GLuint texture) {
  GLint fbo = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fbo);
  if (fbo == 0 || texture == 0) return false;
  GLint first = GL_NONE, max_buffers = 1;
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &max_buffers);
  glGetIntegerv(GL_DRAW_BUFFER0, &first);
  for (GLint i = 1; i < max_buffers; ++i) {
    GLint b = GL_NONE;
    glGetIntegerv(static_cast<GLenum>(GL_DRAW_BUFFER0 + i), &b);
    if (b != GL_NONE) return false;
  }
  if (first < static_cast<GLint>(GL_COLOR_ATTACHMENT0) || first > static_cast<GLint>(GL_COLOR_ATTACHMENT31)) return false;
  GLint type = GL_NONE, name = 0;
  glGetNamedFramebufferAttachmentParameteriv(static_cast<GLuint>(fbo), static_cast<GLenum>(first), GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
  glGetNamedFramebufferAttachmentParameteriv(static_cast<GLuint>(fbo), static_cast<GLenum>(first), GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
  return type == GL_TEXTURE && static_cast<GLuint>(name) == texture;
}

}  // namespace caustix::runtime::gl
