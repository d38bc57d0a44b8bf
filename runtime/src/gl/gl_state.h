#pragma once
// Saves the OpenGL state the engine's passes touch and restores it on
// destruction, so that every public Engine call leaves the application's
// state as it found it (include/caustix/runtime/engine.h). It also puts the
// state the passes assume but never set (scissor, stencil, colour mask,
// polygon mode, samplers on the units they use...) into its defaults for
// the duration. Internal to the runtime.

#include <epoxy/gl.h>

#include <array>
#include <vector>

namespace caustix::runtime::gl {

class StateGuard {
 public:
  // `units`: the texture units the call may bind (their 2D, 2D multisample,
  // 2D array, cube-map and 3D bindings and sampler objects are saved).
  explicit StateGuard(const std::vector<GLuint>& units);
  ~StateGuard();
  // Puts back every value saved (what the destructor does); the call may
  // go on after it, with enter() (Engine::draw_water's callback runs with
  // the caller's state).
  void restore() const;
  // The state the passes assume, from the saved one: the caller's sampler
  // objects off the saved units, the capabilities the passes never touch
  // off, colour mask all, polygons filled, back faces culled when culling,
  // additive blend equation (what the constructor does after saving).
  void enter() const;
  StateGuard(const StateGuard&) = delete;
  StateGuard& operator=(const StateGuard&) = delete;

  // Indexed buffer bindings saved and restored (SSBO and uniform-buffer
  // points 0..kBufferPoints-1, or as many as the context has).
  static constexpr GLuint kBufferPoints = 16;

 private:
  struct Indexed {
    GLint buffer = 0;
    GLint64 start = 0, size = 0;
  };
  struct Unit {
    GLuint unit = 0;
    GLint tex_2d = 0, tex_2d_ms = 0, tex_array = 0, tex_cube = 0, tex_3d = 0, sampler = 0;
  };
  GLint draw_fbo_ = 0, read_fbo_ = 0, program_ = 0, vao_ = 0, active_texture_ = 0;
  std::array<GLint, 4> viewport_{};
  std::array<GLboolean, 4> color_mask_{};
  GLboolean depth_mask_ = GL_TRUE;
  GLint depth_func_ = 0, cull_mode_ = 0, front_face_ = 0;
  GLint blend_src_rgb_ = 0, blend_dst_rgb_ = 0, blend_src_a_ = 0, blend_dst_a_ = 0;
  GLint blend_eq_rgb_ = 0, blend_eq_a_ = 0;
  std::array<GLint, 2> polygon_mode_{};
  GLint pack_alignment_ = 0, unpack_alignment_ = 0;
  // Generic binding points.
  GLint array_buffer_ = 0, pixel_pack_ = 0, pixel_unpack_ = 0, dispatch_indirect_ = 0, draw_indirect_ = 0;
  GLint ssbo_generic_ = 0, ubo_generic_ = 0, copy_read_ = 0, copy_write_ = 0;
  std::array<Indexed, kBufferPoints> ssbo_{}, ubo_{};
  GLuint points_ = 0;  // those the context has
  // Image units 0 to 2 (the passes' compute shaders write through them).
  struct Image {
    GLint name = 0, level = 0, layer = 0, access = 0, format = 0;
    GLboolean layered = GL_FALSE;
  };
  std::array<Image, 3> images_{};
  std::vector<Unit> units_;
  std::vector<std::pair<GLenum, GLboolean>> caps_;
  // Textures deleted while this guard was alive (note_texture_deleted):
  // the caller's bindings of them are restored as 0.
  mutable std::vector<GLuint> deleted_;
  const StateGuard* outer_ = nullptr;  // the guard this one nests in, on this thread
  GLuint alive(GLint texture) const;
  friend void note_texture_deleted(GLuint name);
};

// Uploads from client memory, rows packed to `alignment` bytes, whatever
// the application left in the unpack state: sets it (alignment, no row
// length or skips, no unpack buffer) and puts the application's back on
// destruction.
class ClientUnpack {
 public:
  explicit ClientUnpack(GLint alignment);
  ~ClientUnpack();
  ClientUnpack(const ClientUnpack&) = delete;
  ClientUnpack& operator=(const ClientUnpack&) = delete;

 private:
  std::array<GLint, 5> saved_{};
};

// gl::delete_texture calls it: a texture an engine call deletes (a product
// reallocated, bind_all()'s arrays laid out anew) may be the caller's
// binding that a guard saved; binding a deleted name is an error, so the
// guards restore 0 there (what GL itself leaves where a bound texture is
// deleted).
void note_texture_deleted(GLuint name);

}  // namespace caustix::runtime::gl
