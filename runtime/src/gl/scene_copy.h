#pragma once
// Copies of the caller's scene colour (2D GL_RGBA32F) and depth (2D
// GL_DEPTH_COMPONENT32F), for passes that sample them while the originals
// may be attached to the bound framebuffer (draw_glass, draw_media).
// Internal to the runtime.

#include <epoxy/gl.h>

#include <cstdint>

#include "caustix/runtime/gl_objects.h"

namespace caustix::runtime::gl {

class SceneCopy {
 public:
  // Copies `depth`, and `color` unless it is 0 (same size), re-allocating
  // the copies when the size changes.
  void copy(GLuint color, GLuint depth) {
    GLint w = 0, h = 0;
    glGetTextureLevelParameteriv(depth, 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(depth, 0, GL_TEXTURE_HEIGHT, &h);
    if (w != w_ || h != h_) {
      color_ = make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(color_.get(), 1, GL_RGBA32F, w, h);
      depth_ = make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(depth_.get(), 1, GL_DEPTH_COMPONENT32F, w, h);
      for (GLuint tex : {color_.get(), depth_.get()}) {
        gl::set_sampling(tex, GL_NEAREST);
      }
      w_ = w;
      h_ = h;
    }
    if (color) glCopyImageSubData(color, GL_TEXTURE_2D, 0, 0, 0, 0, color_.get(), GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
    glCopyImageSubData(depth, GL_TEXTURE_2D, 0, 0, 0, 0, depth_.get(), GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
  }
  GLuint color() const { return color_.get(); }
  GLuint depth() const { return depth_.get(); }
  int width() const { return w_; }
  int height() const { return h_; }
  std::uint64_t gpu_bytes() const { return std::uint64_t(w_) * static_cast<std::uint64_t>(h_) * (16 + 4); }

 private:
  Texture color_, depth_;
  int w_ = 0, h_ = 0;
};

}  // namespace caustix::runtime::gl
