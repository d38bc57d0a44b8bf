#include "gl_state.h"

#include <algorithm>
#include <iterator>

namespace caustix::runtime::gl {
namespace {

// Capabilities saved; the second list is also switched off for the call
// (the passes assume them off and never touch them).
constexpr GLenum kSavedCaps[] = {GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_CLIP_DISTANCE0, GL_PROGRAM_POINT_SIZE};
constexpr GLenum kOffCaps[] = {GL_SCISSOR_TEST,         GL_STENCIL_TEST,          GL_POLYGON_OFFSET_FILL,
                               GL_DEPTH_CLAMP,          GL_RASTERIZER_DISCARD,    GL_PRIMITIVE_RESTART,
                               GL_PRIMITIVE_RESTART_FIXED_INDEX, GL_SAMPLE_ALPHA_TO_COVERAGE, GL_FRAMEBUFFER_SRGB,
                               GL_COLOR_LOGIC_OP,       GL_MULTISAMPLE,           GL_SAMPLE_SHADING};

GLint get(GLenum e) {
  GLint v = 0;
  glGetIntegerv(e, &v);
  return v;
}

thread_local const StateGuard* t_innermost = nullptr;  // the calling thread's guards, innermost first

}  // namespace

void note_texture_deleted(GLuint name) {
  for (const StateGuard* g = t_innermost; g; g = g->outer_) g->deleted_.push_back(name);
}

GLuint StateGuard::alive(GLint texture) const {
  const auto name = static_cast<GLuint>(texture);
  return std::find(deleted_.begin(), deleted_.end(), name) == deleted_.end() ? name : 0;
}

StateGuard::~StateGuard() {
  restore();
  t_innermost = outer_;
}

StateGuard::StateGuard(const std::vector<GLuint>& units) : outer_(t_innermost) {
  t_innermost = this;
  draw_fbo_ = get(GL_DRAW_FRAMEBUFFER_BINDING);
  read_fbo_ = get(GL_READ_FRAMEBUFFER_BINDING);
  program_ = get(GL_CURRENT_PROGRAM);
  if (program_ != 0) {
    // A program the application deleted while current stays in use until
    // another replaces it, and then its name is gone: it cannot be made
    // current again, so the call leaves none current.
    GLint deleted = GL_FALSE;
    glGetProgramiv(static_cast<GLuint>(program_), GL_DELETE_STATUS, &deleted);
    if (deleted) program_ = 0;
  }
  vao_ = get(GL_VERTEX_ARRAY_BINDING);
  active_texture_ = get(GL_ACTIVE_TEXTURE);
  glGetIntegerv(GL_VIEWPORT, viewport_.data());
  glGetBooleanv(GL_COLOR_WRITEMASK, color_mask_.data());
  glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
  depth_func_ = get(GL_DEPTH_FUNC);
  cull_mode_ = get(GL_CULL_FACE_MODE);
  front_face_ = get(GL_FRONT_FACE);
  blend_src_rgb_ = get(GL_BLEND_SRC_RGB);
  blend_dst_rgb_ = get(GL_BLEND_DST_RGB);
  blend_src_a_ = get(GL_BLEND_SRC_ALPHA);
  blend_dst_a_ = get(GL_BLEND_DST_ALPHA);
  blend_eq_rgb_ = get(GL_BLEND_EQUATION_RGB);
  blend_eq_a_ = get(GL_BLEND_EQUATION_ALPHA);
  glGetIntegerv(GL_POLYGON_MODE, polygon_mode_.data());
  pack_alignment_ = get(GL_PACK_ALIGNMENT);
  unpack_alignment_ = get(GL_UNPACK_ALIGNMENT);
  array_buffer_ = get(GL_ARRAY_BUFFER_BINDING);
  pixel_pack_ = get(GL_PIXEL_PACK_BUFFER_BINDING);
  pixel_unpack_ = get(GL_PIXEL_UNPACK_BUFFER_BINDING);
  dispatch_indirect_ = get(GL_DISPATCH_INDIRECT_BUFFER_BINDING);
  draw_indirect_ = get(GL_DRAW_INDIRECT_BUFFER_BINDING);
  ssbo_generic_ = get(GL_SHADER_STORAGE_BUFFER_BINDING);
  ubo_generic_ = get(GL_UNIFORM_BUFFER_BINDING);
  copy_read_ = get(GL_COPY_READ_BUFFER_BINDING);
  copy_write_ = get(GL_COPY_WRITE_BUFFER_BINDING);
  const GLint max_ssbo = get(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS), max_ubo = get(GL_MAX_UNIFORM_BUFFER_BINDINGS);
  points_ = static_cast<GLuint>(std::max(0, std::min({static_cast<GLint>(kBufferPoints), max_ssbo, max_ubo})));
  for (GLuint i = 0; i < points_; ++i) {
    glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, i, &ssbo_[i].buffer);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, i, &ssbo_[i].start);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, i, &ssbo_[i].size);
    glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, i, &ubo_[i].buffer);
    glGetInteger64i_v(GL_UNIFORM_BUFFER_START, i, &ubo_[i].start);
    glGetInteger64i_v(GL_UNIFORM_BUFFER_SIZE, i, &ubo_[i].size);
  }
  for (GLuint i = 0; i < images_.size(); ++i) {
    Image& m = images_[i];
    glGetIntegeri_v(GL_IMAGE_BINDING_NAME, i, &m.name);
    glGetIntegeri_v(GL_IMAGE_BINDING_LEVEL, i, &m.level);
    glGetIntegeri_v(GL_IMAGE_BINDING_LAYER, i, &m.layer);
    glGetIntegeri_v(GL_IMAGE_BINDING_ACCESS, i, &m.access);
    glGetIntegeri_v(GL_IMAGE_BINDING_FORMAT, i, &m.format);
    glGetBooleani_v(GL_IMAGE_BINDING_LAYERED, i, &m.layered);
  }
  units_.reserve(units.size());
  for (GLuint u : units) {
    Unit s;
    s.unit = u;
    glActiveTexture(GL_TEXTURE0 + u);
    s.tex_2d = get(GL_TEXTURE_BINDING_2D);
    s.tex_2d_ms = get(GL_TEXTURE_BINDING_2D_MULTISAMPLE);
    s.tex_array = get(GL_TEXTURE_BINDING_2D_ARRAY);
    s.tex_cube = get(GL_TEXTURE_BINDING_CUBE_MAP);
    s.tex_3d = get(GL_TEXTURE_BINDING_3D);
    s.sampler = get(GL_SAMPLER_BINDING);
    units_.push_back(s);
  }
  for (GLenum c : kSavedCaps) caps_.emplace_back(c, glIsEnabled(c));
  for (GLenum c : kOffCaps) caps_.emplace_back(c, glIsEnabled(c));
  enter();
}

void StateGuard::enter() const {
  for (const Unit& s : units_) {
    if (s.sampler) glBindSampler(s.unit, 0);  // the passes rely on their textures' own parameters
  }
  for (std::size_t k = std::size(kSavedCaps); k < caps_.size(); ++k) {
    if (caps_[k].second) glDisable(caps_[k].first);
  }
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glCullFace(GL_BACK);
  glBlendEquation(GL_FUNC_ADD);
}

void StateGuard::restore() const {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw_fbo_));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read_fbo_));
  glUseProgram(static_cast<GLuint>(program_));
  glBindVertexArray(static_cast<GLuint>(vao_));
  glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
  glColorMask(color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
  glDepthMask(depth_mask_);
  glDepthFunc(static_cast<GLenum>(depth_func_));
  glCullFace(static_cast<GLenum>(cull_mode_));
  glFrontFace(static_cast<GLenum>(front_face_));
  glBlendFuncSeparate(static_cast<GLenum>(blend_src_rgb_), static_cast<GLenum>(blend_dst_rgb_), static_cast<GLenum>(blend_src_a_),
                      static_cast<GLenum>(blend_dst_a_));
  glBlendEquationSeparate(static_cast<GLenum>(blend_eq_rgb_), static_cast<GLenum>(blend_eq_a_));
  glPolygonMode(GL_FRONT_AND_BACK, static_cast<GLenum>(polygon_mode_[0]));
  glPixelStorei(GL_PACK_ALIGNMENT, pack_alignment_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, unpack_alignment_);
  auto rebind_indexed = [](GLenum target, GLuint index, const Indexed& b) {
    if (b.buffer != 0 && b.size > 0) {
      glBindBufferRange(target, index, static_cast<GLuint>(b.buffer), static_cast<GLintptr>(b.start), static_cast<GLsizeiptr>(b.size));
    } else {
      glBindBufferBase(target, index, static_cast<GLuint>(b.buffer));
    }
  };
  for (GLuint i = 0; i < points_; ++i) {
    rebind_indexed(GL_SHADER_STORAGE_BUFFER, i, ssbo_[i]);
    rebind_indexed(GL_UNIFORM_BUFFER, i, ubo_[i]);
  }
  // After the indexed ones: binding an indexed point also sets the generic one.
  glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(array_buffer_));
  glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(pixel_pack_));
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(pixel_unpack_));
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, static_cast<GLuint>(dispatch_indirect_));
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, static_cast<GLuint>(draw_indirect_));
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(ssbo_generic_));
  glBindBuffer(GL_UNIFORM_BUFFER, static_cast<GLuint>(ubo_generic_));
  glBindBuffer(GL_COPY_READ_BUFFER, static_cast<GLuint>(copy_read_));
  glBindBuffer(GL_COPY_WRITE_BUFFER, static_cast<GLuint>(copy_write_));
  for (GLuint i = 0; i < images_.size(); ++i) {
    const Image& m = images_[i];
    glBindImageTexture(i, alive(m.name), m.level, m.layered, m.layer, static_cast<GLenum>(m.access),
                       static_cast<GLenum>(m.format ? m.format : GL_R8));
  }
  for (const Unit& s : units_) {
    glActiveTexture(GL_TEXTURE0 + s.unit);
    glBindTexture(GL_TEXTURE_2D, alive(s.tex_2d));
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, alive(s.tex_2d_ms));
    glBindTexture(GL_TEXTURE_2D_ARRAY, alive(s.tex_array));
    glBindTexture(GL_TEXTURE_CUBE_MAP, alive(s.tex_cube));
    glBindTexture(GL_TEXTURE_3D, alive(s.tex_3d));
    glBindSampler(s.unit, static_cast<GLuint>(s.sampler));
  }
  glActiveTexture(static_cast<GLenum>(active_texture_));
  for (const auto& [cap, on] : caps_) {
    if (on) {
      glEnable(cap);
    } else {
      glDisable(cap);
    }
  }
}

namespace {
constexpr std::array<GLenum, 5> kUnpack = {GL_UNPACK_ALIGNMENT, GL_UNPACK_ROW_LENGTH, GL_UNPACK_SKIP_ROWS, GL_UNPACK_SKIP_PIXELS,
                                           GL_PIXEL_UNPACK_BUFFER_BINDING};
}  // namespace

ClientUnpack::ClientUnpack(GLint alignment) {
  for (std::size_t i = 0; i < kUnpack.size(); ++i) glGetIntegerv(kUnpack[i], &saved_[i]);
  glPixelStorei(GL_UNPACK_ALIGNMENT, alignment);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
  glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
}

ClientUnpack::~ClientUnpack() {
  for (std::size_t i = 0; i + 1 < kUnpack.size(); ++i) glPixelStorei(kUnpack[i], saved_[i]);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(saved_.back()));
}

}  // namespace caustix::runtime::gl
