// The view through the glass (Engine::draw_glass): the glass drawn into a
// target over its rectangle of the frame, reading the caller's scene, then
// copied into the caller's framebuffer. Rays through the light-transport
// table (Iwasaki et al. §3) or nearby-geometry refraction off the glass's back
// faces (timofy 2009), and thin-walled sheets over both.
#include "glass_impl.h"

namespace caustix::runtime {

void GlassEngine::Impl::ensure_window(int w, int h, bool back) {
  auto fits = [&](int aw, int ah) { return aw >= w && ah >= h && std::int64_t{aw} * ah <= 4 * std::int64_t{std::max(w, 64)} * std::max(h, 64); };
  auto round = [](int v) { return (v + 63) / 64 * 64; };
  if (!fits(window_w, window_h)) {
    window_w = round(w);
    window_h = round(h);
    window_color = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(window_color.get(), 1, GL_RGBA32F, window_w, window_h);
    window_depth = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(window_depth.get(), 1, GL_DEPTH_COMPONENT32F, window_w, window_h);
    window_fbo = gl::make_framebuffer();
    glNamedFramebufferTexture(window_fbo.get(), GL_COLOR_ATTACHMENT0, window_color.get(), 0);
    glNamedFramebufferTexture(window_fbo.get(), GL_DEPTH_ATTACHMENT, window_depth.get(), 0);
  }
  if (!back || fits(back_w, back_h)) return;
  back_w = round(w);
  back_h = round(h);
  back_position = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(back_position.get(), 1, GL_RGBA32F, back_w, back_h);
  back_normal = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(back_normal.get(), 1, GL_RGBA16F, back_w, back_h);
  back_depth = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(back_depth.get(), 1, GL_DEPTH_COMPONENT32F, back_w, back_h);
  for (GLuint tex : {back_position.get(), back_normal.get()}) gl::set_sampling(tex, GL_NEAREST);
  back_fbo = gl::make_framebuffer();
  glNamedFramebufferTexture(back_fbo.get(), GL_COLOR_ATTACHMENT0, back_position.get(), 0);
  glNamedFramebufferTexture(back_fbo.get(), GL_COLOR_ATTACHMENT1, back_normal.get(), 0);
  glNamedFramebufferTexture(back_fbo.get(), GL_DEPTH_ATTACHMENT, back_depth.get(), 0);
  const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(back_fbo.get(), 2, bufs);
}

void GlassEngine::Impl::draw_back_faces(const SceneDesc& scene, const glm::mat4& view_proj, const glm::vec4& ndc_window, int w, int h) {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, back_fbo.get());
  glViewport(0, 0, w, h);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_BLEND);
  const float zero[4] = {0, 0, 0, 0}, far = 1.0f;
  glClearNamedFramebufferfv(back_fbo.get(), GL_COLOR, 0, zero);
  glClearNamedFramebufferfv(back_fbo.get(), GL_COLOR, 1, zero);
  glClearNamedFramebufferfv(back_fbo.get(), GL_DEPTH, 0, &far);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_FRONT);
  back_faces.use();
  back_faces.set("u_view_proj", view_proj);
  back_faces.set("u_ndc_window", ndc_window);
  back_faces.set("u_clip_plane", glm::vec4(0, 0, 0, 1));
  for (const Glass& g : glass) {
    set_mesh_pose(back_faces, scene.objects[g.object]);
    g.mesh->draw();
  }
  glCullFace(GL_BACK);
}

void GlassEngine::Impl::draw_thin(const SceneDesc& scene, const glm::mat4& view_proj, const glm::vec4& ndc_window, const glm::vec3& eye,
               const glm::vec3& sky, unsigned environment) const {
  thin_view.use();
  thin_view.set("u_view_proj", view_proj);
  thin_view.set("u_ndc_window", ndc_window);
  thin_view.set("u_clip_plane", glm::vec4(0, 0, 0, 1));
  thin_view.set("u_eye", eye);
  thin_view.set("u_sky", sky);
  thin_view.set("u_has_environment", environment != 0 ? 1 : 0);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_SRC1_COLOR);
  glEnable(GL_CULL_FACE);
  for (const GLenum cull : {GL_FRONT, GL_BACK}) {
    glCullFace(cull);
    for (const Thin& t : thin) {
      const Material& m = scene.objects[t.object].material;
      set_mesh_pose(thin_view, scene.objects[t.object]);
      thin_view.set("u_ior", m.ior);
      thin_view.set("u_tint", glm::vec3(m.tint[0], m.tint[1], m.tint[2]));
      t.mesh->draw();
    }
  }
  glCullFace(GL_BACK);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
}

auto GlassEngine::Impl::window_of(const SceneDesc& scene, const glm::mat4& view_proj, int width, int height) const -> std::optional<glm::ivec4> {
  glm::vec2 lo(1.0f), hi(-1.0f);
  std::vector<std::uint32_t> drawn;
  for (const Glass& g : glass) drawn.push_back(g.object);
  for (const Thin& t : thin) drawn.push_back(t.object);
  for (const std::uint32_t object : drawn) {
    const Object& o = scene.objects[object];
    const MeshInfo& mi = scene.meshes[o.mesh_index];
    const glm::mat4 mvp = view_proj * to_glm(o.transform);
    for (int c = 0; c < 8; ++c) {
      const glm::vec4 corner((c & 1) ? mi.bounds_max[0] : mi.bounds_min[0], (c & 2) ? mi.bounds_max[1] : mi.bounds_min[1],
                             (c & 4) ? mi.bounds_max[2] : mi.bounds_min[2], 1.0f);
      const glm::vec4 q = mvp * corner;
      if (!(q.w > 1e-6f)) return glm::ivec4(0, 0, width, height);
      lo = glm::min(lo, glm::vec2(q) / q.w);
      hi = glm::max(hi, glm::vec2(q) / q.w);
    }
  }
  lo = glm::clamp(lo, glm::vec2(-1.0f), glm::vec2(1.0f));
  hi = glm::clamp(hi, glm::vec2(-1.0f), glm::vec2(1.0f));
  const glm::vec2 size(static_cast<float>(width), static_cast<float>(height));
  const glm::ivec2 a = glm::max(glm::ivec2(glm::floor((lo * 0.5f + 0.5f) * size)) - 1, glm::ivec2(0));
  const glm::ivec2 b = glm::min(glm::ivec2(glm::ceil((hi * 0.5f + 0.5f) * size)) + 1, glm::ivec2(width, height));
  if (b.x <= a.x || b.y <= a.y) return std::nullopt;
  return glm::ivec4(a, b);
}

Status GlassEngine::draw_glass(const SceneDesc& scene, const glm::mat4& view_proj, const glm::vec3& eye, const glm::vec3& sky,
                               const gl::SceneTexture& scene_color, const gl::SceneTexture& scene_depth, gl::SceneReader& reader,
                               float march_length, const GlassViewOptions& options, const ViewSpectrum& spectrum,
                               const std::vector<std::array<glm::vec3, 2>>& object_boxes) {
  Impl& s = *impl_;
  const gl::TimedPass timed("glass: view", gl::PassKind::kRaster);
  GLint caller_fbo = 0, vp[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &caller_fbo);
  glGetIntegerv(GL_VIEWPORT, vp);
  const auto rect = s.window_of(scene, view_proj, vp[2], vp[3]);
  if (!rect) return Status::success();  // no glass in view
  const int x0 = (*rect)[0], y0 = (*rect)[1], w = (*rect)[2] - x0, h = (*rect)[3] - y0;
  const bool nearby = options.method == GlassView::kNearby;
  s.ensure_window(w, h, nearby);
  // NDC of the window's rectangle onto its targets' [-1, 1].
  const glm::vec2 n0(2.0f * static_cast<float>(x0) / static_cast<float>(vp[2]) - 1.0f, 2.0f * static_cast<float>(y0) / static_cast<float>(vp[3]) - 1.0f);
  const glm::vec2 n1(2.0f * static_cast<float>(x0 + w) / static_cast<float>(vp[2]) - 1.0f,
                     2.0f * static_cast<float>(y0 + h) / static_cast<float>(vp[3]) - 1.0f);
  const glm::vec4 ndc_window(2.0f / (n1 - n0), -(n0 + n1) / (n1 - n0));
  if (nearby) s.draw_back_faces(scene, view_proj, ndc_window, w, h);

  // 1. The glass into the window, depth-tested against the scene's depth
  // there (copied in), reading the caller's colour and depth: in place
  // where they are single-sampled, else resolved (gl/scene_inputs.h).
  CAUSTIX_RETURN_IF_ERROR(reader.read(scene_color, scene_depth, false, false));
  const GLuint color_read = reader.color(), depth_read = reader.depth();
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, s.window_fbo.get());
  // Thin-walled sheets scale what lies behind them (blending): the
  // caller's scene under the window to start from. Where no glass is
  // drawn the composite writes back what was there (colour and depth).
  // Without them the window's colour starts cleared (alpha 0: nothing to
  // composite).
  CAUSTIX_RETURN_IF_ERROR(reader.copy_region(s.thin.empty() ? gl::SceneTexture{} : scene_color, scene_depth, x0, y0, w, h));
  glViewport(0, 0, w, h);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  const gl::Program& p = nearby ? s.nearby : s.surface;
  p.use();
  p.set("u_view_proj", view_proj);
  p.set("u_ndc_window", ndc_window);
  p.set("u_inv_view_proj", glm::inverse(view_proj));
  p.set("u_eye", eye);
  p.set("u_sky", sky);
  p.set("u_has_environment", options.environment != 0 ? 1 : 0);
  glBindTextureUnit(4, options.environment);  // sampled only with u_has_environment
  glBindTextureUnit(0, color_read);
  glBindTextureUnit(1, depth_read);
  glBindSampler(0, s.nearest.get());
  glBindSampler(1, s.nearest.get());
  if (nearby) {
    p.set("u_clip_plane", glm::vec4(0, 0, 0, 1));
    p.set("u_iterations", static_cast<int>(options.iterations));
    p.set("u_exit_iterations", static_cast<int>(options.exit_iterations));
    // Frame uv -> back-face texture coordinate: minus the window's corner,
    // over the textures' extent in frame uv.
    p.set("u_back_window", glm::vec4(static_cast<float>(x0) / static_cast<float>(vp[2]), static_cast<float>(y0) / static_cast<float>(vp[3]),
                                     static_cast<float>(s.back_w) / static_cast<float>(vp[2]),
                                     static_cast<float>(s.back_h) / static_cast<float>(vp[3])));
    glBindTextureUnit(2, s.back_position.get());
    glBindTextureUnit(3, s.back_normal.get());
  }
  p.set("u_march_length", march_length);
  for (const Impl::Glass& g : s.glass) {
    const Material& m = scene.objects[g.object].material;
    p.set("u_glass_transmit", Impl::transmit(m));
    if (nearby) {
      Impl::set_mesh_pose(p, scene.objects[g.object]);
      const Vec3f& k = g.shared->tables[g.shared->base].params.absorption;
      p.set("u_glass_absorption", glm::vec3(k[0], k[1], k[2]));
      set_view_samples(p, view_samples(spectrum, m.ior, m.dispersion));  // per pixel, per wavelength
    } else {
      Impl::set_table(p, g.shared->tables[g.shared->base]);  // the table view refracts at n_d (per vertex; docs/dispersion.md)
      s.set_pose(p, scene, g);
      p.set("u_ior", m.ior);
      // Whether a receiver's box meets the glass's: only then does the
      // surface look for what is inside it (glass_surface.frag).
      const auto& gb = object_boxes[g.object];
      bool holds = false;
      for (std::size_t oi = 0; oi < scene.objects.size() && !holds; ++oi) {
        const auto& b = object_boxes[oi];
        holds = !transmits(scene.objects[oi].role) && glm::all(glm::lessThanEqual(b[0], gb[1])) && glm::all(glm::lessThanEqual(gb[0], b[1]));
      }
      p.set("u_inside", holds ? 1 : 0);
    }
    g.mesh->draw();
  }
  if (!s.thin.empty()) s.draw_thin(scene, view_proj, ndc_window, eye, sky, options.environment);
  glDisable(GL_CULL_FACE);
  glBindSampler(0, 0);
  glBindSampler(1, 0);

  // 2. Where glass was drawn, its colour and depth into the caller's framebuffer.
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(caller_fbo));
  gl::encode_srgb_if_the_target_is_srgb();
  glViewport(vp[0] + x0, vp[1] + y0, w, h);
  glDepthFunc(GL_ALWAYS);  // tested against the scene's depth in the window already
  s.composite.use();
  glProgramUniform2i(s.composite.id(), s.composite.loc("u_origin"), vp[0] + x0, vp[1] + y0);
  glBindTextureUnit(0, s.window_color.get());
  glBindTextureUnit(1, s.window_depth.get());
  glBindVertexArray(s.empty_vao.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDepthFunc(GL_LESS);
  glViewport(vp[0], vp[1], vp[2], vp[3]);
  return Status::success();
}

std::uint64_t GlassEngine::view_bytes() const {
  const Impl& s = *impl_;
  return std::uint64_t(s.back_w) * static_cast<std::uint64_t>(s.back_h) * (16 + 8 + 4) +
         std::uint64_t(s.window_w) * static_cast<std::uint64_t>(s.window_h) * (16 + 4);
}

}  // namespace caustix::runtime
