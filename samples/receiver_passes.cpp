#include "caustix/sample/receiver_passes.h"

#include <epoxy/gl.h>

#include <string>

#include <glm/gtc/type_ptr.hpp>

namespace caustix::sample {
namespace {

const char* kMeshVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
void main() {
  v_world = (u_model * vec4(a_position, 1.0)).xyz;
  v_normal = transpose(inverse(mat3(u_model))) * a_normal;
  gl_Position = u_view_proj * vec4(v_world, 1.0);
})";

const char* kGBuffer = R"(#version 450 core
in vec3 v_world;
in vec3 v_normal;
uniform int u_object;
layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;
void main() { o_position = vec4(v_world, float(u_object)); o_normal = vec4(normalize(v_normal), 0.0); })";

const char* kForward = R"(
in vec3 v_world;
in vec3 v_normal;
out vec4 o;
void main() { o = vec4(caustix_irradiance(v_world, v_normal), 1.0); })";

const char* kFullScreen = R"(#version 450 core
void main() { gl_Position = vec4(vec2(gl_VertexID & 1, gl_VertexID >> 1) * 4.0 - 1.0, 0.0, 1.0); })";

const char* kDeferred = R"(
layout(binding = 0) uniform sampler2D g_position;
layout(binding = 1) uniform sampler2D g_normal;
out vec4 o;
void main() {
  vec4 p = texelFetch(g_position, ivec2(gl_FragCoord.xy), 0);
  if (p.w < 0.0) discard;
  o = vec4(caustix_irradiance_all(p.xyz, texelFetch(g_normal, ivec2(gl_FragCoord.xy), 0).xyz, int(p.w)), 1.0);
})";

gl::Texture target(GLenum format, int w, int h) {
  gl::Texture t = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(t.get(), 1, format, w, h);
  return t;
}

std::vector<float> read_rgba(GLuint texture, int w, int h) {
  std::vector<float> px(std::size_t(w) * std::size_t(h) * 4);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(texture, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * 4), px.data());
  return px;
}

}  // namespace

ReceiverPasses::ReceiverPasses(Engine& engine, int width, int height) : engine_(engine), width_(width), height_(height) {}

Result<std::unique_ptr<ReceiverPasses>> ReceiverPasses::create(Engine& engine, int width, int height) {
  std::unique_ptr<ReceiverPasses> p(new ReceiverPasses(engine, width, height));
  const std::string include = engine.glsl_include();
  const std::string forward = "#version 450 core\n" + include + kForward;
  const std::string deferred = "#version 450 core\n#define CAUSTIX_ALL_RECEIVERS\n" + include + kDeferred;
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs({{&p->gbuffer_, "receiver_gbuffer", kMeshVertex, kGBuffer},
                                              {&p->forward_, "receiver_forward", kMeshVertex, forward.c_str()},
                                              {&p->deferred_, "receiver_deferred", kFullScreen, deferred.c_str()}}));
  const SceneDesc& sc = engine.scene();
  for (std::uint32_t oi = 0; oi < sc.objects.size(); ++oi) {
    if (!transmits(sc.objects[oi].role)) p->receivers_.push_back(oi);
  }
  p->position_ = target(GL_RGBA32F, width, height);
  p->normal_ = target(GL_RGBA32F, width, height);
  p->depth_ = target(GL_DEPTH_COMPONENT32F, width, height);
  p->color_ = target(GL_RGBA32F, width, height);
  p->gbuffer_fbo_ = gl::make_framebuffer();
  glNamedFramebufferTexture(p->gbuffer_fbo_.get(), GL_COLOR_ATTACHMENT0, p->position_.get(), 0);
  glNamedFramebufferTexture(p->gbuffer_fbo_.get(), GL_COLOR_ATTACHMENT1, p->normal_.get(), 0);
  glNamedFramebufferTexture(p->gbuffer_fbo_.get(), GL_DEPTH_ATTACHMENT, p->depth_.get(), 0);
  const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(p->gbuffer_fbo_.get(), 2, both);
  p->target_fbo_ = gl::make_framebuffer();
  glNamedFramebufferTexture(p->target_fbo_.get(), GL_COLOR_ATTACHMENT0, p->color_.get(), 0);
  glNamedFramebufferTexture(p->target_fbo_.get(), GL_DEPTH_ATTACHMENT, p->depth_.get(), 0);
  p->empty_vao_ = gl::make_vertex_array();
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("receiver passes"));
  return p;
}

void ReceiverPasses::begin_target(GLuint framebuffer) const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width_, height_);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_CULL_FACE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const float zero[4] = {0, 0, 0, 0};
  if (framebuffer == target_fbo_.get()) glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, zero);
}

Status ReceiverPasses::draw_gbuffer(const glm::mat4& view_proj) {
  begin_target(gbuffer_fbo_.get());
  const float empty[4] = {0, 0, 0, -1};
  glClearNamedFramebufferfv(gbuffer_fbo_.get(), GL_COLOR, 0, empty);
  glClearNamedFramebufferfv(gbuffer_fbo_.get(), GL_COLOR, 1, empty);
  glClearNamedFramebufferfi(gbuffer_fbo_.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  gbuffer_.use();
  gbuffer_.set("u_view_proj", view_proj);
  for (std::uint32_t oi : receivers_) {
    gbuffer_.set("u_model", glm::make_mat4(engine_.scene().objects[oi].transform.data()));
    gbuffer_.set("u_object", static_cast<int>(oi));
    CAUSTIX_RETURN_IF_ERROR(engine_.draw_object(oi));
  }
  return gl::check_gl("G-buffer");
}

Status ReceiverPasses::shade_per_pair(const glm::mat4& view_proj, bool level0) {
  begin_target(target_fbo_.get());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_EQUAL);  // the G-buffer's depth: each pixel shaded once per light
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);  // lights add up (Tipprasert 2006 eq. 4-20)
  forward_.use();
  forward_.set("u_view_proj", view_proj);
  for (std::uint32_t li = 0; li < engine_.scene().lights.size(); ++li) {
    for (std::uint32_t oi : receivers_) {
      forward_.set("u_model", glm::make_mat4(engine_.scene().objects[oi].transform.data()));
      CAUSTIX_RETURN_IF_ERROR(engine_.bind(oi, li));
      if (!level0) {
        CAUSTIX_RETURN_IF_ERROR(engine_.draw_object(oi));
        continue;
      }
      auto r = engine_.lighting(oi, li);
      if (!r) return r.error();
      const GLuint mipmapped[4] = {r->caustics, r->caustics_color, r->glass_illumination, r->caustic_map};
      for (GLuint t : mipmapped) {
        if (t) glTextureParameteri(t, GL_TEXTURE_MAX_LEVEL, 0);
      }
      CAUSTIX_RETURN_IF_ERROR(engine_.draw_object(oi));
      for (GLuint t : mipmapped) {
        if (t) glTextureParameteri(t, GL_TEXTURE_MAX_LEVEL, 1000);  // GL's default
      }
    }
  }
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  return gl::check_gl("per-pair shading");
}

Status ReceiverPasses::shade_through(const glm::mat4& view_proj, std::uint32_t object, std::uint32_t host) {
  begin_target(target_fbo_.get());
  glClearNamedFramebufferfi(target_fbo_.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  forward_.use();
  forward_.set("u_view_proj", view_proj);
  forward_.set("u_model", glm::make_mat4(engine_.scene().objects[object].transform.data()));
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);  // the pre-pass: its nearest surface
  CAUSTIX_RETURN_IF_ERROR(engine_.bind(host, 0));
  CAUSTIX_RETURN_IF_ERROR(engine_.draw_object(object));
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthFunc(GL_EQUAL);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  for (std::uint32_t li = 0; li < engine_.scene().lights.size(); ++li) {
    CAUSTIX_RETURN_IF_ERROR(engine_.bind(host, li));
    CAUSTIX_RETURN_IF_ERROR(engine_.draw_object(object));
  }
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  return gl::check_gl("shading through a host");
}

Status ReceiverPasses::shade_deferred() {
  begin_target(target_fbo_.get());
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  CAUSTIX_RETURN_IF_ERROR(engine_.bind_all());
  glBindTextureUnit(0, position_.get());
  glBindTextureUnit(1, normal_.get());
  glBindVertexArray(empty_vao_.get());
  deferred_.use();
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glEnable(GL_DEPTH_TEST);
  return gl::check_gl("deferred shading");
}

std::vector<float> ReceiverPasses::read_irradiance() const { return read_rgba(color_.get(), width_, height_); }

std::vector<int> ReceiverPasses::read_objects() const {
  const std::vector<float> px = read_rgba(position_.get(), width_, height_);
  std::vector<int> objects(px.size() / 4);
  for (std::size_t i = 0; i < objects.size(); ++i) objects[i] = static_cast<int>(px[4 * i + 3]);
  return objects;
}

}  // namespace caustix::sample
