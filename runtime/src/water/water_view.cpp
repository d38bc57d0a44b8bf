#include "water_view.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "pass_timer.h"
#include "shader_text.h"
#include "view_spectrum.h"

namespace caustix::runtime {

WaterCameras water_cameras(const ViewCamera& main, float fov_y_deg, float aspect, float near_plane, float far_plane,
                           const Water& water, const WaterLook& look) {
  WaterCameras c;
  const float level = water.level;
  float crest = 1e-3f;  // "a little bit" beyond the rest level: the highest crest
  for (const Wave& w : water.waves) crest += std::fabs(w.amplitude);
  c.under = main.eye.y < level;

  const glm::mat4 widen = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / look.fov_ext, 1.0f / look.fov_ext, 1.0f));
  const glm::mat4 proj = widen * glm::perspective(glm::radians(fov_y_deg), aspect, near_plane, far_plane);
  const glm::mat4 mirror = glm::translate(glm::mat4(1.0f), glm::vec3(0, level, 0)) *
                           glm::scale(glm::mat4(1.0f), glm::vec3(1, -1, 1)) *
                           glm::translate(glm::mat4(1.0f), glm::vec3(0, -level, 0));
  c.reflection = {main.view * mirror, proj, glm::vec3(mirror * glm::vec4(main.eye, 1.0f))};
  c.refraction = {main.view, proj, main.eye};

  if (!c.under && look.refraction) {
    // Eq. 1: O, where the bottom ray of the frustum (I) meets the water.
    const glm::mat3 to_world = glm::transpose(glm::mat3(main.view));
    const glm::vec3 i = glm::normalize(to_world * glm::vec3(0.0f, -std::tan(glm::radians(fov_y_deg) * 0.5f), -1.0f));
    if (i.y < -1e-4f) {
      const glm::vec3 o = main.eye + i * ((level - main.eye.y) / i.y);
      const glm::vec3 r = glm::refract(i, glm::vec3(0, 1, 0), 1.0f / water.ior);  // eq. 2
      const glm::vec3 axis = glm::cross(i, r);
      const float s = glm::length(axis);
      if (s > 1e-6f) {
        const glm::mat4 rot = glm::translate(glm::mat4(1.0f), o) * glm::rotate(glm::mat4(1.0f), std::atan2(s, glm::dot(i, r)), axis / s) *
                              glm::translate(glm::mat4(1.0f), -o);
        c.refraction.view = main.view * glm::inverse(rot);
        c.refraction.eye = glm::vec3(rot * glm::vec4(main.eye, 1.0f));
      }
    }
  }
  const glm::vec4 keep_below(0, -1, 0, level + crest), keep_above(0, 1, 0, -(level - crest));
  c.refraction_clip = c.under ? keep_above : keep_below;
  c.reflection_clip = c.under ? keep_below : keep_above;
  return c;
}

WaterView::Target WaterView::make_target(int w, int h, GLuint depth) {
  // Colour filtered (bent lookups fall between texels), depth read exactly.
  auto texture = [&](GLenum format, GLenum filter) {
    gl::Texture t = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(t.get(), 1, format, w, h);
    gl::set_sampling(t.get(), filter);
    return t;
  };
  Target t;
  t.fbo = gl::make_framebuffer();
  t.color = texture(kColorFormat, GL_LINEAR);
  if (depth == 0) {
    t.depth = texture(GL_DEPTH_COMPONENT32F, GL_NEAREST);
    depth = t.depth.get();
  }
  glNamedFramebufferTexture(t.fbo.get(), GL_COLOR_ATTACHMENT0, t.color.get(), 0);
  glNamedFramebufferTexture(t.fbo.get(), GL_DEPTH_ATTACHMENT, depth, 0);
  return t;
}

Result<WaterView> WaterView::create() {
  WaterView w;
  const std::string surface_fs = with_optics(shaders::k_water_frag_glsl);
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs(
      {{&w.surface_, "water_surface", shaders::k_water_vert_glsl, surface_fs.c_str()},
       {&w.highlight_, "glow_highlight", shaders::k_water_vert_glsl, shaders::k_glow_highlight_frag_glsl},
       {&w.glow_, "glow", shaders::k_fullscreen_vert_glsl, shaders::k_glow_frag_glsl},
       {&w.plain_, "water_plain", shaders::k_water_vert_glsl, shaders::k_water_plain_frag_glsl}}));
  w.empty_vao_ = gl::make_vertex_array();
  w.nearest_ = gl::make_nearest_sampler();
  return w;
}

void WaterView::ensure_targets(int size) {
  if (size == size_) return;
  // One depth buffer for both: the reflection is drawn first, and the
  // refraction's depth, which the surface reads, last.
  refraction_ = make_target(size, size);
  reflection_ = make_target(size, size, refraction_.depth.get());
  size_ = size;
}

void WaterView::draw_surface(const SurfaceParams& p, const WaterLook& look, const std::function<void()>& draw_water) const {
  const gl::TimedPass timed("water: surface view", gl::PassKind::kRaster);
  const WaterCameras& c = *p.cameras;
  const gl::Program& s = look.debug == WaterDebug::kExactLookup ? exact_surface_ : surface_;
  s.use();
  s.set("u_view_proj", p.view_proj);
  s.set("u_eye", p.eye);
  s.set("u_under", c.under ? 1 : 0);
  set_view_samples(s, p.waves);
  s.set("u_refr_view", c.refraction.view);
  s.set("u_refr_proj", c.refraction.proj);
  s.set("u_refr_depth_ab", glm::vec2(c.refraction.proj[2][2], c.refraction.proj[3][2]));
  s.set("u_refl_view_proj", c.reflection.proj * c.reflection.view);
  s.set("u_steps", look.steps);
  s.set("u_max_steps", look.max_steps);
  s.set("u_refraction", look.refraction ? 1 : 0);
  s.set("u_reflection", look.reflection ? 1 : 0);
  s.set("u_colour", look.colour ? 1 : 0);
  s.set("u_fresnel_exact", look.fresnel == FresnelMode::kExact ? 1 : 0);
  s.set("u_q", look.fresnel_q);
  s.set("u_c", look.reflect_scale);
  s.set("u_m", look.under_scale);
  s.set("u_k", p.k);
  s.set("u_water_color", p.water_color);
  s.set("u_sun_direction", p.sun_direction);
  s.set("u_sun_color", p.sun_color);
  s.set("u_debug", static_cast<int>(look.debug));
  glBindTextureUnit(0, refraction_.color.get());
  glBindTextureUnit(1, refraction_.depth.get());
  glBindTextureUnit(2, reflection_.color.get());
  draw_water();
}

void WaterView::draw_glow(const SurfaceParams& p, const WaterLook& look, GLuint target_fbo, const int viewport[4],
                          GLuint scene_depth, const std::function<void()>& draw_water) {
  const gl::TimedPass timed("water: glow", gl::PassKind::kRaster);
  const int width = viewport[2], height = viewport[3];
  const int w = std::max(1, width / 4), h = std::max(1, height / 4);
  if (w != glow_w_ || h != glow_h_) {
    glow_target_ = make_glow_target(w, h);
    glow_w_ = w;
    glow_h_ = h;
  }
  // The highlight in units of the sun's brightest channel, so that half
  // floats hold it whatever E0 (a real sun's W/m^2 times the specular peak
  // would pass 65504).
  const float scale = std::max({p.sun_color.r, p.sun_color.g, p.sun_color.b, 1e-30f});
  glBindFramebuffer(GL_FRAMEBUFFER, glow_target_.fbo.get());
  glViewport(0, 0, w, h);
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(glow_target_.fbo.get(), GL_COLOR, 0, zero);
  glDepthMask(GL_TRUE);  // before the clear, which obeys it: the caller's mask is off here
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_BLEND);
  highlight_.use();
  highlight_.set("u_view_proj", p.view_proj);
  highlight_.set("u_eye", p.eye);
  highlight_.set("u_sun_direction", p.sun_direction);
  highlight_.set("u_sun_color", p.sun_color / scale);
  highlight_.set("u_scene_depth_bound", scene_depth != 0 ? 1 : 0);
  highlight_.set("u_glow_size", glm::vec2(static_cast<float>(w), static_cast<float>(h)));
  highlight_.set("u_viewport", glm::vec4(static_cast<float>(viewport[0]), static_cast<float>(viewport[1]),
                                         static_cast<float>(width), static_cast<float>(height)));
  if (scene_depth != 0) {
    glBindTextureUnit(0, scene_depth);
    glBindSampler(0, nearest_.get());
  }
  draw_water();
  glBindSampler(0, 0);

  glBindFramebuffer(GL_FRAMEBUFFER, target_fbo);
  glViewport(viewport[0], viewport[1], width, height);
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  glow_.use();
  glow_.set("u_star", look.glow_star ? 1 : 0);
  glow_.set("u_scale", scale);
  glBindTextureUnit(0, glow_target_.color.get());
  glBindVertexArray(empty_vao_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
}

WaterView::Target WaterView::make_glow_target(int w, int h) {
  Target t;
  t.fbo = gl::make_framebuffer();
  t.color = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(t.color.get(), 1, GL_RGBA16F, w, h);
  gl::set_sampling(t.color.get(), GL_LINEAR);
  t.depth = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(t.depth.get(), 1, GL_DEPTH_COMPONENT16, w, h);  // only which water fragment is nearest
  glNamedFramebufferTexture(t.fbo.get(), GL_COLOR_ATTACHMENT0, t.color.get(), 0);
  glNamedFramebufferTexture(t.fbo.get(), GL_DEPTH_ATTACHMENT, t.depth.get(), 0);
  return t;
}

std::uint64_t WaterView::gpu_bytes() const {
  const std::uint64_t s = static_cast<std::uint64_t>(size_) * static_cast<std::uint64_t>(size_);
  const std::uint64_t g = static_cast<std::uint64_t>(glow_w_) * static_cast<std::uint64_t>(glow_h_);
  return s * (2 * kColorBytes + 4) + g * (8 + 2);  // two colours and a 32-bit depth; the glow's half floats and 16-bit depth
}

Status WaterView::draw(const Frame& f, const WaterLook& look, const std::function<void(const WaterPass&)>& draw_scene,
                       const gl::StateGuard& guard, gl::SceneReader& reader, const gl::SceneTexture& scene_depth,
                       const std::function<void()>& draw_grid) {
  const glm::mat4 view_proj = f.main.proj * f.main.view;
  const bool textured = look.textures && draw_scene;
  std::optional<WaterCameras> cams;
  if (textured) {
    // Mihalik 2008's two textures (§5.1-5.2), drawn by the application.
    cams = water_cameras(f.main, f.fov_y_deg, f.aspect, f.near_plane, f.far_plane, *f.water, look);
    int size = look.texture_size;
    if (size == 0) {  // auto: a texel per pixel across the extended field of view, within the limit
      const float pixels = look.fov_ext * static_cast<float>(std::max(f.viewport[2], f.viewport[3]));
      const int limit = look.max_texture_size > 0 ? look.max_texture_size : 4096;
      size = std::min(std::clamp((static_cast<int>(std::ceil(pixels)) + 63) / 64 * 64, 64, 4096), limit);
    }
    ensure_targets(size);
    const int n = size_;
    const glm::vec3 refr_clear = cams->under ? look.sky : f.medium.color;
    // From below, the mirrored texture shows the water's inside, fogged
    // along the mirrored camera's rays (§7.5).
    const glm::vec3 refl_clear = cams->under ? f.medium.color : look.sky;
    struct Pass {
      GLuint fbo;
      WaterPass p;
      glm::vec3 clear;
    };
    // The reflection first: the refraction's depth, drawn last into the
    // buffer both share, is the one the surface reads.
    const Pass passes[2] = {
        {reflection_fbo(),
         WaterPass{reflection_fbo(), n, cams->reflection.proj * cams->reflection.view, cams->reflection_clip, true, cams->under, cams->reflection.eye, f.medium.k, f.medium.color},
         refl_clear},
        {refraction_fbo(),
         WaterPass{refraction_fbo(), n, cams->refraction.proj * cams->refraction.view, cams->refraction_clip, false, false, cams->refraction.eye, f.medium.k, f.medium.color},
         refr_clear}};
    const gl::TimedPass timed("water: refraction and reflection textures (the application's passes)", gl::PassKind::kRaster);
    for (const Pass& p : passes) {
      glBindFramebuffer(GL_FRAMEBUFFER, p.fbo);
      glDepthMask(GL_TRUE);  // clears obey the write masks
      const float clear[4] = {p.clear.r, p.clear.g, p.clear.b, 0.0f};
      glClearNamedFramebufferfv(p.fbo, GL_COLOR, 0, clear);
      const float far_depth = 1.0f;
      glClearNamedFramebufferfv(p.fbo, GL_DEPTH, 0, &far_depth);
      // The callback runs with the caller's state (program, VAO, textures,
      // samplers, active unit, capabilities, ...) but for what WaterPass
      // lists (engine.h): the pass's framebuffer and viewport, depth test
      // LESS with writes, no blending or culling, the clip distance, the
      // winding.
      guard.restore();
      glBindFramebuffer(GL_FRAMEBUFFER, p.fbo);
      glViewport(0, 0, n, n);
      glDepthMask(GL_TRUE);
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      glDisable(GL_BLEND);
      glDisable(GL_CULL_FACE);
      glEnable(GL_CLIP_DISTANCE0);
      glFrontFace(p.p.mirrored ? GL_CW : GL_CCW);
      draw_scene(p.p);
      // The callback may have left anything: back to what the passes below assume.
      guard.enter();
      glDisable(GL_CLIP_DISTANCE0);
      glFrontFace(GL_CCW);
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      glDisable(GL_SCISSOR_TEST);
      glDisable(GL_STENCIL_TEST);
      glDisable(GL_CULL_FACE);
    }
  }

  // The glow reads the scene's depth as a single-sampled texture.
  GLuint depth_read = 0;
  if (scene_depth && textured && look.glow) {
    CAUSTIX_RETURN_IF_ERROR(reader.read(gl::SceneTexture{}, scene_depth, false, false));
    depth_read = reader.depth();
  }
  glBindFramebuffer(GL_FRAMEBUFFER, f.target_fbo);
  glViewport(f.viewport[0], f.viewport[1], f.viewport[2], f.viewport[3]);
  gl::encode_srgb_if_the_target_is_srgb();
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_LESS);
  if (textured) {
    glDisable(GL_BLEND);
    if (look.debug == WaterDebug::kExactLookup && !exact_surface_.id()) {
      const std::string fs = with_optics(shaders::k_water_frag_glsl);
      CAUSTIX_RETURN_IF_ERROR(gl::build_programs({{&exact_surface_, "water_surface (exact lookup)", shaders::k_water_vert_glsl,
                                                   insert_after_version(fs.c_str(), "#define CAUSTIX_EXACT_LOOKUP\n").c_str()}}));
    }
    const SurfaceParams sp{&*cams, view_proj, f.main.eye, f.waves, f.medium.color, f.medium.k, f.sun_direction, f.sun_color};
    draw_surface(sp, look, draw_grid);
    if (look.glow && look.debug == WaterDebug::kNone && !cams->under && f.sun_color != glm::vec3(0.0f)) {
      draw_glow(sp, look, f.target_fbo, f.viewport, depth_read, draw_grid);
    }
  } else {
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied
    plain_.use();
    plain_.set("u_view_proj", view_proj);
    plain_.set("u_eye", f.main.eye);
    plain_.set("u_sky", look.sky);
    plain_.set("u_ior", f.water->ior);
    plain_.set("u_sun_direction", f.sun_direction);
    plain_.set("u_sun_color", f.sun_color);
    draw_grid();
  }
  return Status::success();
}

}  // namespace caustix::runtime
