#include "gl_objects.h"

#include "gl_state.h"

#include <initializer_list>
#include <vector>

namespace caustix::runtime::gl {

void delete_buffer(GLuint id) { glDeleteBuffers(1, &id); }
void delete_vertex_array(GLuint id) { glDeleteVertexArrays(1, &id); }
void delete_texture(GLuint id) {
  note_texture_deleted(id);
  glDeleteTextures(1, &id);
}
void delete_framebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void delete_program(GLuint id) { glDeleteProgram(id); }
void delete_query(GLuint id) { glDeleteQueries(1, &id); }
void delete_sampler(GLuint id) { glDeleteSamplers(1, &id); }

Buffer make_buffer() { GLuint id = 0; glCreateBuffers(1, &id); return Buffer(id); }
VertexArray make_vertex_array() { GLuint id = 0; glCreateVertexArrays(1, &id); return VertexArray(id); }
Texture make_texture(GLenum target) { GLuint id = 0; glCreateTextures(target, 1, &id); return Texture(id); }
Texture make_view(GLenum target, GLuint source, GLenum format, GLuint min_level, GLuint levels, GLuint min_layer, GLuint layers) {
  GLuint id = 0;
  glGenTextures(1, &id);  // a view needs a name never bound, which glCreateTextures does not give
  glTextureView(id, target, source, format, min_level, levels, min_layer, layers);
  return Texture(id);
}

void set_sampling(GLuint texture, GLenum filter) {
  glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}
Framebuffer make_framebuffer() { GLuint id = 0; glCreateFramebuffers(1, &id); return Framebuffer(id); }
Query make_query(GLenum target) { GLuint id = 0; glCreateQueries(target, 1, &id); return Query(id); }
Sampler make_nearest_sampler() {
  GLuint id = 0;
  glCreateSamplers(1, &id);
  glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glSamplerParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return Sampler(id);
}

namespace {

Result<GLuint> compile(GLenum type, const char* src, const std::string& name) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
    std::vector<char> log(static_cast<std::size_t>(std::max(len, 1)));
    glGetShaderInfoLog(s, len, nullptr, log.data());
    glDeleteShader(s);
    const char* kind = type == GL_VERTEX_SHADER ? "' (vertex)" : type == GL_FRAGMENT_SHADER ? "' (fragment)" : "' (compute)";
    return make_error(ErrorCode::kGraphics, "shader '" + name + kind + " failed to compile: " + log.data());
  }
  return s;
}

}  // namespace

// Links compiled shaders into a program (and deletes the shaders).
Result<Program> link_program(const std::string& name, std::initializer_list<GLuint> shaders);

Result<Program> Program::build(const std::string& name, const char* vs, const char* fs) {
  auto v = compile(GL_VERTEX_SHADER, vs, name);
  if (!v) return v.error();
  auto f = compile(GL_FRAGMENT_SHADER, fs, name);
  if (!f) {
    glDeleteShader(*v);
    return f.error();
  }
  return link_program(name, {*v, *f});
}

Result<Program> Program::build_compute(const std::string& name, const char* cs) {
  auto c = compile(GL_COMPUTE_SHADER, cs, name);
  if (!c) return c.error();
  return link_program(name, {*c});
}

Status build_programs(std::initializer_list<ProgramSpec> specs) {
  for (const ProgramSpec& spec : specs) {
    auto p = spec.fragment ? Program::build(spec.name, spec.source, spec.fragment) : Program::build_compute(spec.name, spec.source);
    if (!p) return p.error();
    *spec.out = std::move(*p);
  }
  return Status::success();
}

Result<Program> link_program(const std::string& name, std::initializer_list<GLuint> shaders) {
  Program p;
  p.id_ = Handle<delete_program>(glCreateProgram());
  for (GLuint s : shaders) glAttachShader(p.id(), s);
  glLinkProgram(p.id());
  for (GLuint s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(p.id(), GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(p.id(), GL_INFO_LOG_LENGTH, &len);
    std::vector<char> log(static_cast<std::size_t>(std::max(len, 1)));
    glGetProgramInfoLog(p.id(), len, nullptr, log.data());
    return make_error(ErrorCode::kGraphics, "shader program '" + name + "' failed to link: " + log.data());
  }
  return p;
}

void Program::use() const { glUseProgram(id_.get()); }

GLint Program::loc(const char* uniform) const {
  const auto it = locations_.find(std::string_view(uniform));
  if (it != locations_.end()) return it->second;
  const GLint l = glGetUniformLocation(id_.get(), uniform);
  locations_.emplace(uniform, l);
  return l;
}

void Program::set(const char* u, int v) const { glProgramUniform1i(id(), loc(u), v); }
void Program::set(const char* u, float v) const { glProgramUniform1f(id(), loc(u), v); }
void Program::set(const char* u, const glm::vec2& v) const { glProgramUniform2fv(id(), loc(u), 1, &v[0]); }
void Program::set(const char* u, const glm::vec3& v) const { glProgramUniform3fv(id(), loc(u), 1, &v[0]); }
void Program::set(const char* u, const glm::vec4& v) const { glProgramUniform4fv(id(), loc(u), 1, &v[0]); }
void Program::set(const char* u, const glm::mat3& m) const { glProgramUniformMatrix3fv(id(), loc(u), 1, GL_FALSE, &m[0][0]); }
void Program::set(const char* u, const glm::mat4& m) const { glProgramUniformMatrix4fv(id(), loc(u), 1, GL_FALSE, &m[0][0]); }
void Program::set(const char* u, unsigned v) const { glProgramUniform1ui(id(), loc(u), v); }

Status check_gl(const char* what) {
  const GLenum e = glGetError();
  if (e == GL_NO_ERROR) return Status::success();
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%04X", e);
  return make_error(ErrorCode::kGraphics, std::string("OpenGL error ") + buf + " in " + what);
}

}  // namespace caustix::runtime::gl
