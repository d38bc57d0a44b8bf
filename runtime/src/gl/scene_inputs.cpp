#include "scene_inputs.h"

#include <array>
#include <cstdio>

#include "shader_text.h"

namespace caustix::runtime::gl {
namespace {

GLint level_param(GLuint texture, GLenum pname) {
  GLint v = 0;
  glGetTextureLevelParameteriv(texture, 0, pname, &v);
  return v;
}

struct NamedFormat {
  GLenum format;
  const char* name;
};
constexpr NamedFormat kFormatNames[] = {
    {GL_RGBA32F, "GL_RGBA32F"},
    {GL_RGBA16F, "GL_RGBA16F"},
    {GL_RGB32F, "GL_RGB32F"},
    {GL_RGB16F, "GL_RGB16F"},
    {GL_R11F_G11F_B10F, "GL_R11F_G11F_B10F"},
    {GL_RGB9_E5, "GL_RGB9_E5"},
    {GL_RGBA8, "GL_RGBA8"},
    {GL_SRGB8_ALPHA8, "GL_SRGB8_ALPHA8"},
    {GL_RGB8, "GL_RGB8"},
    {GL_SRGB8, "GL_SRGB8"},
    {GL_RGB10_A2, "GL_RGB10_A2"},
    {GL_RGBA16, "GL_RGBA16"},
    {GL_RGBA8UI, "GL_RGBA8UI"},
    {GL_RGBA32UI, "GL_RGBA32UI"},
    {GL_RGBA32I, "GL_RGBA32I"},
    {GL_R32F, "GL_R32F"},
    {GL_R32UI, "GL_R32UI"},
    {GL_DEPTH_COMPONENT16, "GL_DEPTH_COMPONENT16"},
    {GL_DEPTH_COMPONENT24, "GL_DEPTH_COMPONENT24"},
    {GL_DEPTH_COMPONENT32, "GL_DEPTH_COMPONENT32"},
    {GL_DEPTH_COMPONENT32F, "GL_DEPTH_COMPONENT32F"},
    {GL_DEPTH24_STENCIL8, "GL_DEPTH24_STENCIL8"},
    {GL_DEPTH32F_STENCIL8, "GL_DEPTH32F_STENCIL8"},
    {GL_STENCIL_INDEX8, "GL_STENCIL_INDEX8"},
};

// Whether a colour format's components read as floats in a sampler2D: not
// an integer format (whose components are GL_INT or GL_UNSIGNED_INT).
bool reads_as_float(GLuint texture) {
  for (GLenum pname : {GL_TEXTURE_RED_TYPE, GL_TEXTURE_GREEN_TYPE, GL_TEXTURE_BLUE_TYPE, GL_TEXTURE_ALPHA_TYPE}) {
    const GLint type = level_param(texture, pname);
    if (type == GL_INT || type == GL_UNSIGNED_INT) return false;
  }
  return level_param(texture, GL_TEXTURE_RED_TYPE) != GL_NONE;
}

}  // namespace

std::string format_name(GLenum format) {
  for (const NamedFormat& f : kFormatNames) {
    if (f.format == format) return f.name;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "format 0x%04X", static_cast<unsigned>(format));
  return buf;
}

Result<SceneTexture> describe_scene_texture(const char* call, GLuint texture, SceneTextureKind kind, const char* what) {
  const std::string prefix = std::string(call) + ": " + what + " " + std::to_string(texture);
  const bool color = kind == SceneTextureKind::kColor;
  const char* accepted = color ? "a 2D or 2D multisample texture of a floating-point or normalised colour format "
                                 "(GL_RGBA16F, GL_R11F_G11F_B10F, GL_RGBA8, GL_SRGB8_ALPHA8, GL_RGB10_A2, GL_RGBA32F, ...)"
                               : "a 2D or 2D multisample texture of a depth or depth-stencil format (GL_DEPTH_COMPONENT16, "
                                 "GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT32F, GL_DEPTH24_STENCIL8, GL_DEPTH32F_STENCIL8)";
  if (texture == 0 || !glIsTexture(texture)) {
    return make_error(ErrorCode::kUsage, prefix + " is not a GL texture; expected " + accepted);
  }
  SceneTexture t;
  t.name = texture;
  GLint target = 0;
  glGetTextureParameteriv(texture, GL_TEXTURE_TARGET, &target);
  t.target = static_cast<GLenum>(target);
  if (t.target != GL_TEXTURE_2D && t.target != GL_TEXTURE_2D_MULTISAMPLE) {
    return make_error(ErrorCode::kUsage, prefix + " is not a 2D texture; expected " + accepted);
  }
  t.width = level_param(texture, GL_TEXTURE_WIDTH);
  t.height = level_param(texture, GL_TEXTURE_HEIGHT);
  t.format = static_cast<GLenum>(level_param(texture, GL_TEXTURE_INTERNAL_FORMAT));
  if (t.width <= 0 || t.height <= 0) return make_error(ErrorCode::kUsage, prefix + " has no storage at level 0");
  const bool has_depth = level_param(texture, GL_TEXTURE_DEPTH_SIZE) > 0;
  const bool has_stencil = level_param(texture, GL_TEXTURE_STENCIL_SIZE) > 0;
  if (color ? (has_depth || has_stencil || !reads_as_float(texture)) : !has_depth) {
    return make_error(ErrorCode::kUsage, prefix + " is " + format_name(t.format) + "; expected " + accepted);
  }
  if (!color && has_stencil) {
    GLint mode = GL_DEPTH_COMPONENT;
    glGetTextureParameteriv(texture, GL_DEPTH_STENCIL_TEXTURE_MODE, &mode);
    if (mode != GL_DEPTH_COMPONENT) {
      return make_error(ErrorCode::kUsage, prefix + " (" + format_name(t.format) +
                                               ") is read as stencil (GL_DEPTH_STENCIL_TEXTURE_MODE); set GL_DEPTH_COMPONENT");
    }
  }
  return t;
}

struct SceneReader::Impl {
  // Variants by (colour multisampled, depth multisampled).
  std::array<Program, 4> programs;
  std::array<bool, 4> built{};
  Framebuffer fbo;
  VertexArray vao;
  Sampler nearest;
  Texture color, depth;
  int w = 0, h = 0;

  // The variant for these inputs, built on first use.
  Status program(bool color_ms, bool depth_ms, const Program*& out) {
    const auto k = static_cast<std::size_t>((color_ms ? 1 : 0) + (depth_ms ? 2 : 0));
    if (!built[k]) {
      std::string defines;
      if (color_ms) defines += "#define CAUSTIX_COLOR_MS\n";
      if (depth_ms) defines += "#define CAUSTIX_DEPTH_MS\n";
      const std::string frag = insert_after_version(shaders::k_scene_read_frag_glsl, defines);
      CAUSTIX_RETURN_IF_ERROR(build_programs({{&programs[k], "scene_read", shaders::k_fullscreen_vert_glsl, frag.c_str()}}));
      built[k] = true;
    }
    out = &programs[k];
    return Status::success();
  }

  // The full-screen pass over the bound framebuffer's [0, w) x [0, h).
  Status draw(const SceneTexture& c, const SceneTexture& d, int x0, int y0, int width, int height) {
    const Program* p = nullptr;
    CAUSTIX_RETURN_IF_ERROR(program(c && c.multisampled(), d && d.multisampled(), p));
    if (!vao.get()) {
      vao = make_vertex_array();
      nearest = make_nearest_sampler();
    }
    p->use();
    p->set("u_has_color", c ? 1 : 0);
    p->set("u_has_depth", d ? 1 : 0);
    glProgramUniform2i(p->id(), p->loc("u_offset"), x0, y0);
    glBindTextureUnit(0, c.name);
    glBindTextureUnit(1, d.name);
    glBindSampler(0, nearest.get());  // whatever the caller's own filtering or comparison mode
    glBindSampler(1, nearest.get());
    glViewport(0, 0, width, height);
    if (d) {
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_ALWAYS);
      glDepthMask(GL_TRUE);
    } else {
      glDisable(GL_DEPTH_TEST);
    }
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glBindVertexArray(vao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindSampler(0, 0);
    glBindSampler(1, 0);
    glBindTextureUnit(0, 0);
    glBindTextureUnit(1, 0);
    glDepthFunc(GL_LESS);
    return check_gl("reading the scene's colour and depth");
  }
};

SceneReader::SceneReader() : impl_(new Impl) {}
SceneReader::~SceneReader() { delete impl_; }

Status SceneReader::read(const SceneTexture& color, const SceneTexture& depth, bool copy_color, bool copy_depth) {
  Impl& s = *impl_;
  copy_color = color && (copy_color || color.multisampled());
  copy_depth = depth && (copy_depth || depth.multisampled());
  color_ = copy_color ? 0 : color.name;
  depth_ = copy_depth ? 0 : depth.name;
  if (!copy_color && !copy_depth) return Status::success();
  const SceneTexture& sized = copy_depth ? depth : color;
  if (sized.width != s.w || sized.height != s.h || (copy_color && !s.color.get()) || (copy_depth && !s.depth.get())) {
    s.w = sized.width;
    s.h = sized.height;
    s.fbo = make_framebuffer();
    s.color = make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(s.color.get(), 1, GL_RGBA32F, s.w, s.h);
    set_sampling(s.color.get(), GL_NEAREST);
    s.depth = make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(s.depth.get(), 1, GL_DEPTH_COMPONENT32F, s.w, s.h);
    set_sampling(s.depth.get(), GL_NEAREST);
    glNamedFramebufferTexture(s.fbo.get(), GL_COLOR_ATTACHMENT0, s.color.get(), 0);
    glNamedFramebufferTexture(s.fbo.get(), GL_DEPTH_ATTACHMENT, s.depth.get(), 0);
  }
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, s.fbo.get());
  const GLenum buffer = copy_color ? GL_COLOR_ATTACHMENT0 : GL_NONE;
  glNamedFramebufferDrawBuffers(s.fbo.get(), 1, &buffer);
  CAUSTIX_RETURN_IF_ERROR(s.draw(copy_color ? color : SceneTexture{}, copy_depth ? depth : SceneTexture{}, 0, 0, s.w, s.h));
  if (copy_color) color_ = s.color.get();
  if (copy_depth) depth_ = s.depth.get();
  return Status::success();
}

Status SceneReader::copy_region(const SceneTexture& color, const SceneTexture& depth, int x0, int y0, int w, int h) {
  return impl_->draw(color, depth, x0, y0, w, h);
}

std::uint64_t SceneReader::gpu_bytes() const {
  return impl_->color.get() ? std::uint64_t(impl_->w) * static_cast<std::uint64_t>(impl_->h) * (16 + 4) : 0;
}

bool attached_to_draw_framebuffer(GLuint texture) {
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

bool draws_only_into(GLuint texture) {
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

void encode_srgb_if_the_target_is_srgb() {
  GLint fbo = 0, first = GL_NONE;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fbo);
  if (fbo == 0) return;
  glGetIntegerv(GL_DRAW_BUFFER0, &first);
  if (first < static_cast<GLint>(GL_COLOR_ATTACHMENT0) || first > static_cast<GLint>(GL_COLOR_ATTACHMENT31)) return;
  GLint type = GL_NONE, encoding = GL_LINEAR;
  glGetNamedFramebufferAttachmentParameteriv(static_cast<GLuint>(fbo), static_cast<GLenum>(first), GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
  if (type == GL_NONE) return;
  glGetNamedFramebufferAttachmentParameteriv(static_cast<GLuint>(fbo), static_cast<GLenum>(first),
                                             GL_FRAMEBUFFER_ATTACHMENT_COLOR_ENCODING, &encoding);
  if (encoding == GL_SRGB) glEnable(GL_FRAMEBUFFER_SRGB);
}

}  // namespace caustix::runtime::gl
