#include "shadow_maps.h"

#include <cmath>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "caustix_shaders.h"
#include "pass_timer.h"

namespace caustix::runtime {
namespace {

glm::vec3 to_glm(const Vec3f& v) { return {v[0], v[1], v[2]}; }

gl::Texture make_shadow_texture(GLenum target, int size) {
  gl::Texture t = gl::make_texture(target);
  // 16 bits: the depth range is the scene's (4 r along the light, or the
  // point light's far plane), so a step is 4 r / 65535 (0.2 mm in a 3 m
  // scene), far below a texel (2 r / 2048) and the include's bias.
  glTextureStorage2D(t.get(), 1, GL_DEPTH_COMPONENT16, size, size);
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t.get(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTextureParameteri(t.get(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  return t;
}

gl::Texture make_moments_texture(int size) {
  gl::Texture t = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(t.get(), 1, GL_RG32F, size, size);
  gl::set_sampling(t.get(), GL_LINEAR);
  return t;
}

}  // namespace

Result<ShadowMaps> ShadowMaps::create(const SceneDesc& scene, std::function<void(std::uint32_t)> draw_object) {
  ShadowMaps s;
  s.draw_object_ = std::move(draw_object);
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs({{&s.program_, "shadow", shaders::k_mesh_vert_glsl, shaders::k_shadow_frag_glsl},
                                              {&s.vsm_program_, "shadow_vsm", shaders::k_shadow_vsm_comp_glsl}}));
  for (const Object& o : scene.objects) s.glass_ = s.glass_ || transmits(o.role);
  s.fbo_ = gl::make_framebuffer();
  glNamedFramebufferDrawBuffer(s.fbo_.get(), GL_NONE);
  // Samplers of both kinds must be valid textures even where a light has
  // only one (an unbound shadow sampler is undefined).
  s.dummy_2d_ = make_shadow_texture(GL_TEXTURE_2D, 1);
  s.dummy_cube_ = make_shadow_texture(GL_TEXTURE_CUBE_MAP, 1);
  s.dummy_vsm_ = make_moments_texture(1);
  const float far[4] = {1, 1, 0, 0};
  glClearTexImage(s.dummy_vsm_.get(), 0, GL_RG, GL_FLOAT, far);
  for (const Light& l : scene.lights) {
    PerLight p;
    p.point = l.type == LightType::kPoint;
    const bool dir = l.type == LightType::kDirectional;
    const int size = dir ? kSize : kCubeSize;
    const GLenum target = dir ? GL_TEXTURE_2D : GL_TEXTURE_CUBE_MAP;
    const std::uint64_t bytes = std::uint64_t{2} * static_cast<std::uint64_t>(size) * static_cast<std::uint64_t>(size) * (dir ? 1 : 6);
    p.opaque = make_shadow_texture(target, size);
    s.bytes_ += bytes;
    if (s.glass_) {
      p.glass = make_shadow_texture(target, size);
      s.bytes_ += bytes;
    }
    s.lights_.push_back(std::move(p));
  }
  s.made_.resize(scene.lights.size());
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("shadow maps set-up"));
  return s;
}

glm::vec3 ShadowMaps::travel_direction(const SceneDesc& scene, const Light& l) {
  const glm::vec3 dir = glm::normalize(to_glm(l.direction));
  // Eq. 2-8 with normal +y: the light's direction of travel below flat water.
  if (scene.water && dir.y < 0) return glm::refract(dir, glm::vec3(0, 1, 0), 1.0f / scene.water->ior);
  return dir;
}

void ShadowMaps::draw_casters(const SceneDesc& scene, bool glass_only) const {
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    if (transmits(scene.objects[i].role) != glass_only) continue;
    program_.set("u_model", glm::make_mat4(scene.objects[i].transform.data()));
    draw_object_(i);
  }
}

glm::mat4 ShadowMaps::render_directional(const SceneDesc& scene, const glm::vec3& dir, GLuint target, bool glass_only,
                                         const glm::vec3& c, float r) {
  const glm::vec3 up = std::fabs(dir.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  const glm::mat4 view = glm::lookAt(c - dir * (2.0f * r), c, up);
  const glm::mat4 proj = glm::ortho(-r, r, -r, r, 0.01f * r, 4.0f * r);
  glNamedFramebufferTexture(fbo_.get(), GL_DEPTH_ATTACHMENT, target, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get());
  glViewport(0, 0, kSize, kSize);
  glClear(GL_DEPTH_BUFFER_BIT);
  program_.use();
  program_.set("u_view_proj", proj * view);
  program_.set("u_linear_depth", 0);
  draw_casters(scene, glass_only);
  const glm::mat4 bias = glm::translate(glm::mat4(1), glm::vec3(0.5f)) * glm::scale(glm::mat4(1), glm::vec3(0.5f));
  return bias * proj * view;
}

float ShadowMaps::render_point(const SceneDesc& scene, const Light& light, GLuint target, bool glass_only,
                               const glm::vec3& c, float r) {
  const glm::vec3 pos = to_glm(light.position);
  const float far = glm::length(pos - c) + 2.0f * r;
  const glm::mat4 proj = glm::perspective(glm::radians(90.0f), 1.0f, 0.01f, far);
  // Cube face orientations (GL convention: +X, -X, +Y, -Y, +Z, -Z).
  const glm::vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  program_.use();
  program_.set("u_linear_depth", 1);
  program_.set("u_light_position", pos);
  program_.set("u_far", far);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get());
  glViewport(0, 0, kCubeSize, kCubeSize);
  for (int f = 0; f < 6; ++f) {
    glNamedFramebufferTextureLayer(fbo_.get(), GL_DEPTH_ATTACHMENT, target, 0, f);
    glClear(GL_DEPTH_BUFFER_BIT);
    program_.set("u_view_proj", proj * glm::lookAt(pos, pos + dirs[f], ups[f]));
    draw_casters(scene, glass_only);
  }
  return far;
}

void ShadowMaps::filter_moments(GLuint depth, GLuint moments, std::uint32_t width) {
  const gl::Program& p = vsm_program_;
  p.use();
  p.set("u_radius", static_cast<int>(width / 2));
  // The depth map compares by default; the pass reads depths.
  glTextureParameteri(depth, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  const GLuint groups = (kSize + 7) / 8;
  for (int pass = 0; pass < 2; ++pass) {
    p.set("u_pass", pass);
    glBindTextureUnit(0, depth);
    glBindTextureUnit(1, vsm_scratch_.get());
    glBindImageTexture(0, pass == 0 ? vsm_scratch_.get() : moments, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
    glDispatchCompute(groups, groups, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
  glTextureParameteri(depth, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
}

void ShadowMaps::render(const SceneDesc& scene, std::uint32_t li, const glm::vec3& center, float radius, const ShadowOptions& options,
                        const SceneVersions& versions, bool due, EffectWork& work) {
  const Key key{SceneVersions{versions.light, versions.transforms, 0}, options};  // not the water's
  if (made_.decide(li, key, due, work) != Refresh::kRemake) return;
  made_.made(li, key);
  std::optional<gl::TimedPass> timed;
  timed.emplace("shadow maps", gl::PassKind::kRaster);
  const Light& light = scene.lights[li];
  PerLight& p = lights_[li];
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_TRUE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  if (light.type == LightType::kDirectional) {
    const glm::vec3 dir = travel_direction(scene, light);
    p.world_to_shadow = render_directional(scene, dir, p.opaque.get(), false, center, radius);
    if (glass_) render_directional(scene, dir, p.glass.get(), true, center, radius);
    p.texel = 2.0f * radius / kSize;
    p.vsm = options.filter == ShadowFilter::kVsm;
    timed.reset();
    if (p.vsm) {
      const gl::TimedPass moments("shadow maps: moments (VSM)", gl::PassKind::kCompute);
      const std::uint64_t bytes = std::uint64_t{8} * kSize * kSize;
      if (!vsm_scratch_.get()) {
        vsm_scratch_ = make_moments_texture(kSize);
        bytes_ += bytes;
      }
      if (!p.opaque_vsm.get()) {
        p.opaque_vsm = make_moments_texture(kSize);
        bytes_ += bytes;
        if (glass_) {
          p.glass_vsm = make_moments_texture(kSize);
          bytes_ += bytes;
        }
      }
      filter_moments(p.opaque.get(), p.opaque_vsm.get(), options.vsm_filter);
      if (glass_) filter_moments(p.glass.get(), p.glass_vsm.get(), options.vsm_filter);
    }
  } else {
    p.far = render_point(scene, light, p.opaque.get(), false, center, radius);
    if (glass_) render_point(scene, light, p.glass.get(), true, center, radius);
  }
}

ShadowMaps::Maps ShadowMaps::maps(std::uint32_t li) const {
  const PerLight& p = lights_[li];
  Maps m{dummy_2d_.get(), dummy_cube_.get(), dummy_2d_.get(), dummy_cube_.get(), dummy_vsm_.get(), dummy_vsm_.get(), false,
         p.world_to_shadow, p.far, p.texel};
  if (p.vsm) {
    m.vsm = true;
    m.opaque_vsm = p.opaque_vsm.get();
    if (glass_) m.glass_vsm = p.glass_vsm.get();
  }
  if (p.point) {
    m.opaque_cube = p.opaque.get();
    if (glass_) m.glass_cube = p.glass.get();
  } else {
    m.opaque_2d = p.opaque.get();
    if (glass_) m.glass_2d = p.glass.get();
  }
  return m;
}

Status ShadowMaps::check(const ShadowOptions& so) {
  if (so.vsm_filter < 1 || so.vsm_filter > 63 || so.vsm_filter % 2 == 0) {
    return make_error(ErrorCode::kUsage, "shadow options: vsm_filter must be odd, 1..63 texels, got " + std::to_string(so.vsm_filter));
  }
  if (!(so.vsm_bleeding >= 0.0f && so.vsm_bleeding <= 0.95f)) {
    return make_error(ErrorCode::kUsage, "shadow options: vsm_bleeding must be in [0, 0.95]");
  }
  return Status::success();
}

std::uint64_t ShadowMaps::gpu_bytes() const { return bytes_; }

}  // namespace caustix::runtime
