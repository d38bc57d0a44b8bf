#pragma once
// Small RAII owners for GL objects and a shader program with checked
// compilation: the GL plumbing of the runtime's passes (library caustix_gl,
// not installed), which the sample renderer (samples/) shares as a GL
// utility. Not part of the public API.

#include <epoxy/gl.h>

#include <glm/glm.hpp>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "caustix/common/status.h"

namespace caustix::runtime::gl {

// Owns one GL name; `Deleter` frees it.
template <void (*Deleter)(GLuint)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(GLuint id) : id_(id) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  GLuint get() const { return id_; }
  void reset() {
    if (id_) Deleter(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

void delete_buffer(GLuint id);
void delete_vertex_array(GLuint id);
void delete_texture(GLuint id);
void delete_framebuffer(GLuint id);
void delete_program(GLuint id);
void delete_query(GLuint id);
void delete_sampler(GLuint id);

using Buffer = Handle<delete_buffer>;
using VertexArray = Handle<delete_vertex_array>;
using Texture = Handle<delete_texture>;
using Framebuffer = Handle<delete_framebuffer>;
using Query = Handle<delete_query>;
using Sampler = Handle<delete_sampler>;

Buffer make_buffer();
VertexArray make_vertex_array();
Texture make_texture(GLenum target);
// A view of `layers` layers and `levels` levels of texture `source`
// (immutable storage) as a texture of `target` (glTextureView): it shares
// the source's texels, and keeps them alive once the source is deleted.
Texture make_view(GLenum target, GLuint source, GLenum format, GLuint min_level, GLuint levels, GLuint min_layer, GLuint layers);
// `filter` for minification and magnification, clamped to the edge in s and t.
void set_sampling(GLuint texture, GLenum filter);
Framebuffer make_framebuffer();
Query make_query(GLenum target);
// A sampler object reading texel by texel (nearest, clamped to the edge,
// no comparison), whatever the bound texture's own parameters.
Sampler make_nearest_sampler();

class Program {
 public:
  // Compiles and links; the error (kGraphics) carries the driver's log and
  // the program's name.
  static Result<Program> build(const std::string& name, const char* vertex_src, const char* fragment_src);
  static Result<Program> build_compute(const std::string& name, const char* compute_src);
  GLuint id() const { return id_.get(); }
  void use() const;
  // The uniform's location (looked up once per name, then cached; -1 if
  // the program has no such active uniform).
  GLint loc(const char* uniform) const;
  void set(const char* u, int v) const;
  void set(const char* u, float v) const;
  void set(const char* u, const glm::vec2& v) const;
  void set(const char* u, const glm::vec3& v) const;
  void set(const char* u, const glm::vec4& v) const;
  void set(const char* u, const glm::mat3& m) const;
  void set(const char* u, const glm::mat4& m) const;
  void set(const char* u, unsigned v) const;

 private:
  friend Result<Program> link_program(const std::string&, std::initializer_list<GLuint>);
  Handle<delete_program> id_;
  struct NameHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
  };
  mutable std::unordered_map<std::string, GLint, NameHash, std::equal_to<>> locations_;
};

// A program to build: `source` is the vertex shader, or the compute shader
// when `fragment` is null.
struct ProgramSpec {
  Program* out;
  const char* name;
  const char* source;
  const char* fragment = nullptr;
};
// Builds each program into *out, in order; the first failure is returned.
Status build_programs(std::initializer_list<ProgramSpec> specs);

// Returns an error naming `what` if the GL error flag is set.
Status check_gl(const char* what);

}  // namespace caustix::runtime::gl
