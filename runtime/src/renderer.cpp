#include "caustix/runtime/renderer.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "caustics.h"
#include "glass.h"
#include "caustix/formats/frame.h"
#include "caustix_shaders.h"
#include "gl_program.h"
#include "gpu_mesh.h"
#include "water_surface.h"
#include "water_view.h"

namespace caustix::runtime {
namespace {

constexpr int kShadowSize = 2048;
constexpr int kShadowCubeSize = 1024;
constexpr float kAmbient = 0.12f;

glm::vec3 to_glm(const Vec3f& v) { return {v[0], v[1], v[2]}; }
glm::mat4 to_glm(const Mat4f& m) { return glm::make_mat4(m.data()); }

// A colour + depth render target of a given size.
struct Target {
  gl::Framebuffer fbo;
  gl::Texture color;
  gl::Texture depth;
  int width = 0, height = 0;
  GLenum format = 0;

  void ensure(int w, int h, GLenum color_format, bool with_depth) {
    if (w == width && h == height && color_format == format && fbo.get()) return;
    width = w;
    height = h;
    format = color_format;
    fbo = gl::make_framebuffer();
    color = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(color.get(), 1, color_format, w, h);
    glTextureParameteri(color.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(color.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
    if (with_depth) {
      depth = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(depth.get(), 1, GL_DEPTH_COMPONENT32F, w, h);
      glNamedFramebufferTexture(fbo.get(), GL_DEPTH_ATTACHMENT, depth.get(), 0);
    }
  }
};

// Fragment shaders that use lighting.glsl are assembled behind one #version.
std::string with_lighting(const char* main_src) {
  return std::string("#version 450 core\n") + shaders::k_optics_glsl + shaders::k_lighting_glsl + main_src;
}

// One camera's receiver passes: where they go and how they are cut (the
// main view, or seed 001's refraction and reflection textures).
struct PassView {
  GLuint fbo = 0;
  int width = 0, height = 0;
  glm::mat4 view_proj{1.0f};
  std::optional<glm::vec4> clip;  // world plane, a.x + b >= 0 kept
  bool mirrored = false;          // reflection camera: winding flips
  bool fog = false;               // seed 001 eq. 10, distance from fog_eye
  glm::vec3 fog_eye{0.0f};
  glm::vec3 clear{0.0f};
};

// The light's direction of travel below flat water (eq. 2-8 with normal +y).
glm::vec3 refracted_flat(const glm::vec3& l, float ior) { return glm::refract(l, glm::vec3(0, 1, 0), 1.0f / ior); }

}  // namespace

struct Renderer::Impl {
  SceneDesc scene;
  std::vector<LevelMap> level_maps;  // owned: the caustics engine points into it
  std::vector<std::vector<std::array<double, 3>>> world_vertices;  // per object, for re-deriving frames
  std::vector<TriangleMesh> cpu_meshes;                             // object space, for moving objects
  std::vector<GpuMesh> meshes;
  std::vector<float> object_min_y;  // world
  glm::vec3 lo{0}, hi{0};

  gl::Program receiver, irradiance, shadow, water_program, present;
  std::optional<WaterView> water_view;  // seed 001 surface (scenes with water)
  gl::VertexArray empty_vao;

  // Shadow maps: created only for the light kinds the scene has.
  gl::Texture shadow_2d, shadow_cube;
  gl::Framebuffer shadow_fbo;

  std::optional<WaterSurface> water;
  std::unique_ptr<CausticsEngine> caustics;
  std::unique_ptr<GlassEngine> glass;  // scenes with transparent objects
  gl::Texture glass_shadow_2d, glass_shadow_cube;  // the glass's own shadow maps (1x1 without glass)
  gl::Texture dummy_array, dummy_2d;               // valid samplers for receivers without glass light
  glm::mat4 shadow_matrix{1.0f};                   // of the light being prepared
  float shadow_far = 1.0f;

  Target hdr, display, irradiance_target;
  float exposure = 1.0f;

  void draw_object(std::uint32_t i) const { meshes[scene.objects[i].mesh_index].draw(); }
  glm::mat4 model_of(std::uint32_t i) const { return to_glm(scene.objects[i].transform); }

  void set_model(const gl::Program& p, std::uint32_t i) const {
    const glm::mat4 model = model_of(i);
    p.set("u_model", model);
    p.set("u_normal_matrix", glm::mat3(glm::transpose(glm::inverse(model))));
  }

  float scene_radius() const { return 0.5f * glm::length(hi - lo) + 1e-3f; }
  glm::vec3 scene_center() const { return 0.5f * (lo + hi); }

  bool light_above_water(const Light& l) const {
    return scene.water && (l.type == LightType::kDirectional || l.position[1] > scene.water->level);
  }
  // The direction light travels when it reaches underwater receivers.
  glm::vec3 shadow_direction(const Light& l) const {
    const glm::vec3 dir = glm::normalize(to_glm(l.direction));
    if (scene.water && dir.y < 0) return refracted_flat(dir, scene.water->ior);
    return dir;
  }

  // Opaque objects, or (glass = true) the transparent ones.
  void draw_casters(const gl::Program& p, bool glass_only = false) const {
    for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
      if (is_transparent(scene.objects[i].role) != glass_only) continue;
      set_model(p, i);
      draw_object(i);
    }
  }

  // Renders the directional shadow map along `dir`; returns world -> shadow texture.
  glm::mat4 render_directional_shadow(const glm::vec3& dir, GLuint target, bool glass_only) {
    const float r = scene_radius();
    const glm::vec3 c = scene_center();
    const glm::vec3 up = std::fabs(dir.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::mat4 view = glm::lookAt(c - dir * (2.0f * r), c, up);
    const glm::mat4 proj = glm::ortho(-r, r, -r, r, 0.01f * r, 4.0f * r);
    glNamedFramebufferTexture(shadow_fbo.get(), GL_DEPTH_ATTACHMENT, target, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo.get());
    glViewport(0, 0, kShadowSize, kShadowSize);
    glClear(GL_DEPTH_BUFFER_BIT);
    shadow.use();
    shadow.set("u_view_proj", proj * view);
    shadow.set("u_linear_depth", 0);
    draw_casters(shadow, glass_only);
    const glm::mat4 bias = glm::translate(glm::mat4(1), glm::vec3(0.5f)) * glm::scale(glm::mat4(1), glm::vec3(0.5f));
    return bias * proj * view;
  }

  float render_point_shadow(const Light& light, GLuint target, bool glass_only) {
    const glm::vec3 pos = to_glm(light.position);
    const float far = glm::length(pos - scene_center()) + 2.0f * scene_radius();
    const glm::mat4 proj = glm::perspective(glm::radians(90.0f), 1.0f, 0.01f, far);
    // Cube face orientations (GL convention: +X, -X, +Y, -Y, +Z, -Z).
    const glm::vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    shadow.use();
    shadow.set("u_linear_depth", 1);
    shadow.set("u_light_position", pos);
    shadow.set("u_far", far);
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo.get());
    glViewport(0, 0, kShadowCubeSize, kShadowCubeSize);
    for (int f = 0; f < 6; ++f) {
      glNamedFramebufferTextureLayer(shadow_fbo.get(), GL_DEPTH_ATTACHMENT, target, 0, f);
      glClear(GL_DEPTH_BUFFER_BIT);
      shadow.set("u_view_proj", proj * glm::lookAt(pos, pos + dirs[f], ups[f]));
      draw_casters(shadow, glass_only);
    }
    return far;
  }

  // Everything one light needs before receivers can be lit by it: its
  // shadow map, and its caustics maps. Leaves the light's uniforms set on
  // `p` (receiver or irradiance program).
  Status prepare_light(std::uint32_t li, const CausticsOptions& co, const gl::Program& p) {
    const Light& light = scene.lights[li];
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    shadow_matrix = glm::mat4(1.0f);
    shadow_far = 1.0f;
    if (light.type == LightType::kDirectional) {
      shadow_matrix = render_directional_shadow(shadow_direction(light), shadow_2d.get(), false);
      if (glass) render_directional_shadow(shadow_direction(light), glass_shadow_2d.get(), true);
    } else {
      shadow_far = render_point_shadow(light, shadow_cube.get(), false);
      if (glass) render_point_shadow(light, glass_shadow_cube.get(), true);
    }
    if (caustics) CAUSTIX_RETURN_IF_ERROR(caustics->update_light(li, light, co));
    set_light_uniforms(p, li);
    glBindTextureUnit(0, shadow_2d.get());
    glBindTextureUnit(1, shadow_cube.get());
    if (glass && co.method != CausticsMethod::kNone) {
      CAUSTIX_RETURN_IF_ERROR(glass->update_light(scene, li, co, world_vertices, [&](const gl::Program& q) { set_light_uniforms(q, li); }));
    }
    p.set("u_glass_shadows", glass ? 1 : 0);
    glBindTextureUnit(0, shadow_2d.get());  // again: the glass passes use unit 0
    glBindTextureUnit(1, shadow_cube.get());
    glBindTextureUnit(6, glass_shadow_2d.get());
    glBindTextureUnit(7, glass_shadow_cube.get());
    return Status::success();
  }

  // The uniforms of lighting.glsl that describe light `li` (and its shadow
  // maps, rendered by prepare_light) on program `p`.
  void set_light_uniforms(const gl::Program& p, std::uint32_t li) const {
    const Light& light = scene.lights[li];
    const bool dir = light.type == LightType::kDirectional;
    p.set("u_light_type", dir ? 1 : 2);
    p.set("u_light_direction", glm::normalize(to_glm(light.direction)));
    p.set("u_light_position", to_glm(light.position));
    p.set("u_light_color", to_glm(light.color));
    p.set("u_light_power", dir ? light.irradiance : light.intensity);
    p.set("u_shadow_matrix", shadow_matrix);
    p.set("u_shadow_far", shadow_far);
    p.set("u_shadow_texel", 2.0f * scene_radius() / kShadowSize);
    if (scene.water) {
      p.set("u_water_level", scene.water->level);
      p.set("u_water_ior", scene.water->ior);
      p.set("u_absorption", to_glm(scene.water->absorption));
      p.set("u_refracted", refracted_flat(glm::normalize(to_glm(light.direction)), scene.water->ior));
    } else {
      p.set("u_water_level", -1e30f);
      p.set("u_absorption", glm::vec3(0));
    }
  }

  // Per (object, light): caustics casting, flat-water transmission, or
  // direct light (lighting.glsl's modes).
  void set_object_light(const gl::Program& p, std::uint32_t oi, std::uint32_t li, const CausticsOptions& co) const {
    const Light& light = scene.lights[li];
    std::optional<CausticsEngine::Binding> b;
    if (caustics && co.method != CausticsMethod::kNone) b = caustics->binding(oi, li);
    if (b) {
      const BoundingFrame& f = b->map->frame;
      p.set("u_light_mode", 2);
      p.set("u_frame_origin", glm::vec3(static_cast<float>(f.origin[0]), static_cast<float>(f.origin[1]), static_cast<float>(f.origin[2])));
      p.set("u_frame_U", to_glm(f.u));
      p.set("u_frame_V", to_glm(f.v));
      p.set("u_frame_W", to_glm(f.w));
      p.set("u_frame_half", to_glm(f.half));
      p.set("u_self_tolerance", b->self_tolerance);
      const float n = static_cast<float>(b->map->map_size);
      p.set("u_position_half_diagonal", 0.5f * std::hypot(2.0f * f.half[0] / n, 2.0f * f.half[2] / n));
      glBindTextureUnit(2, b->caustics);
      glBindTextureUnit(3, b->position_map);
      return;
    }
    const bool under = scene.water && object_min_y[oi] < scene.water->level && light_above_water(light);
    p.set("u_light_mode", under ? 1 : 0);
    // Light through glass (lighting.glsl's glass_irradiance), for receivers lit directly.
    std::optional<GlassEngine::Binding> g;
    if (glass && !under && co.method != CausticsMethod::kNone) g = glass->binding(oi);
    p.set("u_glass_on", g ? 1 : 0);
    if (!g) {
      glBindTextureUnit(4, dummy_array.get());
      glBindTextureUnit(5, dummy_2d.get());
      return;
    }
    const BoundingFrame& f = g->frame;
    p.set("u_glass_origin", glm::vec3(static_cast<float>(f.origin[0]), static_cast<float>(f.origin[1]), static_cast<float>(f.origin[2])));
    p.set("u_glass_U", to_glm(f.u));
    p.set("u_glass_V", to_glm(f.v));
    p.set("u_glass_W", to_glm(f.w));
    p.set("u_glass_half", to_glm(f.half));
    p.set("u_glass_planes", static_cast<int>(g->plane_v.size()));
    glProgramUniform1fv(p.id(), p.loc("u_glass_plane_v"), static_cast<GLsizei>(g->plane_v.size()), g->plane_v.data());
    p.set("u_glass_tolerance", g->tolerance);
    glBindTextureUnit(4, g->illumination);
    glBindTextureUnit(5, g->target);
  }

  void draw_receivers(const gl::Program& p, int pass, std::uint32_t li, const CausticsOptions& co,
                      std::optional<std::uint32_t> only, bool cull_closed = false) const {
    for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
      if (only && *only != i) continue;
      if (is_transparent(scene.objects[i].role)) continue;  // drawn as glass (GlassEngine::draw_glass)
      if (cull_closed && meshes[scene.objects[i].mesh_index].closed) {
        glEnable(GL_CULL_FACE);
      } else {
        glDisable(GL_CULL_FACE);
      }
      set_model(p, i);
      p.set("u_albedo", to_glm(scene.objects[i].material.albedo));
      if (pass != 0) set_object_light(p, i, li, co);
      draw_object(i);
    }
  }

  // Receivers into one view: pass 0 clears and lays down ambient and depth,
  // pass 1 adds light `li` (prepare_light has run).
  void draw_view(const PassView& v, int pass, std::uint32_t li, const FrameParams& f,
                 const glm::vec3& water_color, const glm::vec3& k) const {
    glBindFramebuffer(GL_FRAMEBUFFER, v.fbo);
    glViewport(0, 0, v.width, v.height);
    glEnable(GL_DEPTH_TEST);
    if (pass == 0) {
      const float clear[4] = {v.clear.r, v.clear.g, v.clear.b, 0.0f};
      glClearNamedFramebufferfv(v.fbo, GL_COLOR, 0, clear);
      glDepthMask(GL_TRUE);
      glClear(GL_DEPTH_BUFFER_BIT);
      glDisable(GL_BLEND);
      glDepthFunc(GL_LESS);
    } else {
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE);
      glDepthMask(GL_FALSE);
      glDepthFunc(GL_LEQUAL);
    }
    if (v.clip) glEnable(GL_CLIP_DISTANCE0);
    glFrontFace(v.mirrored ? GL_CW : GL_CCW);
    const gl::Program& p = receiver;
    p.use();
    p.set("u_view_proj", v.view_proj);
    p.set("u_clip_plane", v.clip.value_or(glm::vec4(0.0f)));
    p.set("u_pass", pass);
    p.set("u_ambient", kAmbient * glm::vec3(kSkyColor[0], kSkyColor[1], kSkyColor[2]));
    p.set("u_fog", v.fog ? 1 : 0);
    p.set("u_fog_eye", v.fog_eye);
    p.set("u_fog_k", k);
    p.set("u_water_color", water_color);
    draw_receivers(p, pass, li, f.caustics, std::nullopt, v.clip.has_value());
    glDisable(GL_CLIP_DISTANCE0);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create(const RuntimeScene& scene) {
  std::unique_ptr<Renderer> r(new Renderer());
  Impl& s = *r->impl_;
  s.scene = scene.desc;

  const std::string receiver_fs = with_lighting(shaders::k_receiver_frag_glsl);
  const std::string irradiance_fs = with_lighting(shaders::k_irradiance_frag_glsl);
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs({{&s.receiver, "receiver", shaders::k_mesh_vert_glsl, receiver_fs.c_str()},
                                              {&s.irradiance, "irradiance", shaders::k_mesh_vert_glsl, irradiance_fs.c_str()},
                                              {&s.shadow, "shadow", shaders::k_mesh_vert_glsl, shaders::k_shadow_frag_glsl},
                                              {&s.present, "present", shaders::k_present_vert_glsl, shaders::k_present_frag_glsl}}));
  s.empty_vao = gl::make_vertex_array();
  for (const TriangleMesh& m : scene.meshes) s.meshes.push_back(upload_mesh(m));
  s.cpu_meshes = scene.meshes;
  for (const Object& o : s.scene.objects) {
    s.world_vertices.push_back(world_points(o.transform, scene.meshes[o.mesh_index].positions));
  }

  // World bounds (shadow frusta, default camera) and each object's lowest point.
  bool first = true;
  for (const Object& o : s.scene.objects) {
    const MeshInfo& mi = s.scene.meshes[o.mesh_index];
    const glm::mat4 model = to_glm(o.transform);
    float min_y = 1e30f;
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 corner((c & 1) ? mi.bounds_max[0] : mi.bounds_min[0], (c & 2) ? mi.bounds_max[1] : mi.bounds_min[1],
                             (c & 4) ? mi.bounds_max[2] : mi.bounds_min[2]);
      const glm::vec3 w = glm::vec3(model * glm::vec4(corner, 1.0f));
      s.lo = first ? w : glm::min(s.lo, w);
      s.hi = first ? w : glm::max(s.hi, w);
      min_y = std::min(min_y, w.y);
      first = false;
    }
    s.object_min_y.push_back(min_y);
  }

  bool has_directional = false, has_point = false;
  for (const Light& l : s.scene.lights) {
    has_directional = has_directional || l.type == LightType::kDirectional;
    has_point = has_point || l.type == LightType::kPoint;
  }
  if (has_directional || has_point) {
    s.shadow_fbo = gl::make_framebuffer();
    glNamedFramebufferDrawBuffer(s.shadow_fbo.get(), GL_NONE);
  }
  auto shadow_params = [](GLuint tex) {
    glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(tex, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  };
  // Samplers of both kinds must be valid textures even where a scene has
  // only one light kind (an unbound shadow sampler is undefined).
  s.shadow_2d = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(s.shadow_2d.get(), 1, GL_DEPTH_COMPONENT32F, has_directional ? kShadowSize : 1, has_directional ? kShadowSize : 1);
  shadow_params(s.shadow_2d.get());
  s.shadow_cube = gl::make_texture(GL_TEXTURE_CUBE_MAP);
  glTextureStorage2D(s.shadow_cube.get(), 1, GL_DEPTH_COMPONENT32F, has_point ? kShadowCubeSize : 1, has_point ? kShadowCubeSize : 1);
  shadow_params(s.shadow_cube.get());

  bool has_glass = false;
  for (const Object& o : s.scene.objects) has_glass = has_glass || is_transparent(o.role);
  s.glass_shadow_2d = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(s.glass_shadow_2d.get(), 1, GL_DEPTH_COMPONENT32F, has_glass && has_directional ? kShadowSize : 1,
                     has_glass && has_directional ? kShadowSize : 1);
  shadow_params(s.glass_shadow_2d.get());
  s.glass_shadow_cube = gl::make_texture(GL_TEXTURE_CUBE_MAP);
  glTextureStorage2D(s.glass_shadow_cube.get(), 1, GL_DEPTH_COMPONENT32F, has_glass && has_point ? kShadowCubeSize : 1,
                     has_glass && has_point ? kShadowCubeSize : 1);
  shadow_params(s.glass_shadow_cube.get());
  s.dummy_array = gl::make_texture(GL_TEXTURE_2D_ARRAY);
  glTextureStorage3D(s.dummy_array.get(), 1, GL_RGBA32F, 1, 1, 1);
  glClearTexImage(s.dummy_array.get(), 0, GL_RGBA, GL_FLOAT, nullptr);
  s.dummy_2d = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(s.dummy_2d.get(), 1, GL_RGBA32F, 1, 1);
  glClearTexImage(s.dummy_2d.get(), 0, GL_RGBA, GL_FLOAT, nullptr);
  if (has_glass) {
    Impl* impl = &s;
    auto engine = GlassEngine::create(s.scene, scene.transport_tables, s.meshes, [impl](std::uint32_t i) { impl->draw_object(i); });
    if (!engine) return engine.error();
    s.glass = std::move(*engine);
  }

  if (s.scene.water) {
    auto water = WaterSurface::create(*s.scene.water);
    if (!water) return water.error();
    s.water.emplace(std::move(*water));
    auto wp = gl::Program::build("water_plain", shaders::k_water_vert_glsl, shaders::k_water_plain_frag_glsl);
    if (!wp) return wp.error();
    s.water_program = std::move(*wp);
    auto view = WaterView::create();
    if (!view) return view.error();
    s.water_view.emplace(std::move(*view));
    if (!scene.level_maps.empty()) {
      Impl* impl = &s;
      s.level_maps = scene.level_maps;
      auto engine = CausticsEngine::create(
          s.level_maps, *s.water, [impl](std::uint32_t i) { impl->draw_object(i); },
          [impl](std::uint32_t i) { return impl->model_of(i); });
      if (!engine) return engine.error();
      s.caustics = std::move(*engine);
    }
  }
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("renderer set-up"));
  return r;
}

Status Renderer::render(const FrameParams& f) {
  Impl& s = *impl_;
  if (f.width <= 0 || f.height <= 0 || f.width > 16384 || f.height > 16384) {
    return make_error(ErrorCode::kUsage, "image size " + std::to_string(f.width) + "x" + std::to_string(f.height) +
                                             " is outside 1..16384");
  }
  const WaterLook& look = f.water;
  if (look.steps < 1 || look.steps > 64 || look.texture_size < 1 || look.texture_size > 8192 ||
      !(look.fov_ext >= 1.0f && look.fov_ext <= 4.0f)) {
    return make_error(ErrorCode::kUsage, "water look: steps must be 1..64, texture size 1..8192, FOV_ext 1..4");
  }
  s.hdr.ensure(f.width, f.height, GL_RGBA32F, true);
  if (s.caustics) s.caustics->reset_stats();
  if (s.water) s.water->update(f.time);

  ViewCamera main;
  main.eye = to_glm(f.camera.position);
  main.view = glm::lookAt(main.eye, to_glm(f.camera.target), to_glm(f.camera.up));
  const float aspect = static_cast<float>(f.width) / static_cast<float>(f.height);
  main.proj = glm::perspective(glm::radians(f.camera.fov_y_deg), aspect, f.camera.near_plane, f.camera.far_plane);
  const glm::mat4 view_proj = main.proj * main.view;
  const glm::vec3 sky(kSkyColor[0], kSkyColor[1], kSkyColor[2]);

  // The sun (first directional light): highlight, glow, and with the
  // ambient sky the light that enters the water and gives it its colour.
  glm::vec3 sun_dir(0.0f), sun_color(0.0f);
  glm::vec3 light_in_water = kAmbient * sky;
  for (const Light& l : s.scene.lights) {
    if (l.type != LightType::kDirectional) continue;
    const glm::vec3 d = glm::normalize(to_glm(l.direction));
    if (sun_color == glm::vec3(0.0f)) {
      sun_dir = d;
      sun_color = to_glm(l.color) * l.irradiance;
    }
    if (s.scene.water && d.y < 0.0f) {
      const double t = fresnel_transmittance(-d.y, 1.0 / s.scene.water->ior);
      light_in_water += to_glm(l.color) * (l.irradiance * -d.y * static_cast<float>(t));
    }
  }
  const glm::vec3 water_color = look.water_color * light_in_water;
  const glm::vec3 k = look.attenuation ? *look.attenuation : (s.scene.water ? to_glm(s.scene.water->absorption) : glm::vec3(0.0f));

  // Views: the main camera, and with water seed 001's two textures (§5.1-5.2).
  const bool textured = s.water && look.textures;
  std::optional<WaterCameras> cams;
  std::vector<PassView> views;
  views.push_back(PassView{s.hdr.fbo.get(), f.width, f.height, view_proj, std::nullopt, false, false, main.eye, sky});
  if (textured) {
    cams = water_cameras(main, f.camera.fov_y_deg, aspect, f.camera.near_plane, f.camera.far_plane, *s.scene.water, look);
    s.water_view->ensure_targets(look.texture_size);
    const int n = s.water_view->size();
    PassView& m = views[0];
    if (cams->under) {  // eq. 10 on everything the camera sees directly; the deep background is water
      m.fog = true;
      m.clear = water_color;
    }
    const glm::vec3 refr_clear = cams->under ? sky : water_color;
    views.push_back(PassView{s.water_view->refraction_fbo(), n, n, cams->refraction.proj * cams->refraction.view,
                             cams->refraction_clip, false, false, cams->refraction.eye, refr_clear});
    // From below, the mirrored texture shows the water's inside, fogged
    // along the mirrored camera's rays (§7.5).
    views.push_back(PassView{s.water_view->reflection_fbo(), n, n, cams->reflection.proj * cams->reflection.view,
                             cams->reflection_clip, true, cams->under, cams->reflection.eye, cams->under ? water_color : sky});
  }

  glDisable(GL_CULL_FACE);
  for (const PassView& v : views) s.draw_view(v, 0, 0, f, water_color, k);
  // One additive pass per light and view: I_o = sum_lights I_c I_d + I_a (eq. 4-19, 4-20).
  for (std::uint32_t li = 0; li < s.scene.lights.size(); ++li) {
    CAUSTIX_RETURN_IF_ERROR(s.prepare_light(li, f.caustics, s.receiver));
    for (const PassView& v : views) s.draw_view(v, 1, li, f, water_color, k);
  }

  if (s.glass) {
    s.glass->draw_glass(s.scene, view_proj, main.eye, sky, s.hdr.color.get(), s.hdr.depth.get(), 2.0f * s.scene_radius());
  }
  if (s.water) {
    glBindFramebuffer(GL_FRAMEBUFFER, s.hdr.fbo.get());
    glViewport(0, 0, f.width, f.height);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LESS);
    if (textured) {
      glDisable(GL_BLEND);
      const WaterView::SurfaceParams sp{&*cams, view_proj, main.eye, s.scene.water->ior, water_color, k, sun_dir, sun_color};
      s.water_view->draw_surface(sp, look, [&]() { s.water->draw(); });
      if (look.glow && look.debug == WaterDebug::kNone && !cams->under && sun_color != glm::vec3(0.0f)) {
        s.water_view->draw_glow(sp, s.hdr.fbo.get(), f.width, f.height, [&]() { s.water->draw(); });
      }
    } else {
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied
      s.water_program.use();
      s.water_program.set("u_view_proj", view_proj);
      s.water_program.set("u_eye", main.eye);
      s.water_program.set("u_sky", sky);
      s.water_program.set("u_ior", s.scene.water->ior);
      s.water_program.set("u_sun_direction", sun_dir);
      s.water_program.set("u_sun_color", sun_color);
      s.water->draw();
    }
  }
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glBindVertexArray(0);
  return gl::check_gl("frame");
}

Result<IrradianceImage> Renderer::render_irradiance(const IrradianceRequest& q) {
  Impl& s = *impl_;
  std::optional<std::uint32_t> receiver;
  for (std::uint32_t i = 0; i < s.scene.objects.size(); ++i) {
    if (s.scene.objects[i].name == q.receiver) receiver = i;
  }
  if (!receiver) return make_error(ErrorCode::kUsage, "no object named '" + q.receiver + "' in the scene");
  if (is_transparent(s.scene.objects[*receiver].role)) {
    return make_error(ErrorCode::kUsage, "'" + q.receiver + "' is transparent; irradiance images are of diffuse receivers");
  }
  if (q.width <= 0 || q.height <= 0 || q.width > 16384 || q.height > 16384 || !(q.x1 > q.x0) || !(q.z1 > q.z0) ||
      !std::isfinite(q.x0) || !std::isfinite(q.x1) || !std::isfinite(q.z0) || !std::isfinite(q.z1)) {
    return make_error(ErrorCode::kUsage, "irradiance region must have x1 > x0, z1 > z0 and a size in 1..16384");
  }
  IrradianceImage img;
  img.width = q.width;
  img.height = q.height;
  for (const Light& l : s.scene.lights) {
    if (l.type == LightType::kDirectional) {
      img.e0 = l.irradiance;
      break;
    }
  }
  if (!(img.e0 > 0)) img.e0 = 1.0f;
  s.irradiance_target.ensure(q.width, q.height, GL_RGBA32F, true);
  if (s.caustics) s.caustics->reset_stats();
  if (s.water) s.water->update(q.time);

  // Straight down: clip x from world x, clip y from world z (GL row 0 at z0),
  // clip z from height (higher is nearer).
  const float ylo = s.lo.y - 1.0f, yhi = s.hi.y + 1.0f;
  glm::mat4 m(0.0f);
  m[0][0] = 2.0f / (q.x1 - q.x0);
  m[3][0] = -(q.x1 + q.x0) / (q.x1 - q.x0);
  m[2][1] = 2.0f / (q.z1 - q.z0);
  m[3][1] = -(q.z1 + q.z0) / (q.z1 - q.z0);
  m[1][2] = -2.0f / (yhi - ylo);
  m[3][2] = (yhi + ylo) / (yhi - ylo);
  m[3][3] = 1.0f;

  auto begin_pass = [&]() {
    glBindFramebuffer(GL_FRAMEBUFFER, s.irradiance_target.fbo.get());
    glViewport(0, 0, q.width, q.height);
    s.irradiance.use();
    s.irradiance.set("u_view_proj", m);
    s.irradiance.set("u_inv_e0", 1.0f / img.e0);
  };
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  begin_pass();
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(s.irradiance_target.fbo.get(), GL_COLOR, 0, zero);
  glClear(GL_DEPTH_BUFFER_BIT);
  s.irradiance.set("u_pass", 0);
  s.draw_receivers(s.irradiance, 0, 0, q.caustics, receiver);
  for (std::uint32_t li = 0; li < s.scene.lights.size(); ++li) {
    CAUSTIX_RETURN_IF_ERROR(s.prepare_light(li, q.caustics, s.irradiance));
    begin_pass();
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LEQUAL);
    s.irradiance.set("u_pass", 1);
    s.draw_receivers(s.irradiance, 1, li, q.caustics, receiver);
  }
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("irradiance"));

  std::vector<float> rgba(static_cast<std::size_t>(q.width) * static_cast<std::size_t>(q.height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(s.irradiance_target.color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.size() * 4), rgba.data());
  img.rgb.reserve(rgba.size() / 4 * 3);
  for (std::size_t i = 0; i < rgba.size(); i += 4) img.rgb.insert(img.rgb.end(), {rgba[i], rgba[i + 1], rgba[i + 2]});
  return img;
}

void Renderer::finish() { glFinish(); }

const SceneDesc& Renderer::scene() const { return impl_->scene; }

Status Renderer::set_light(std::uint32_t index, const Light& light) {
  Impl& s = *impl_;
  if (index >= s.scene.lights.size() || light.type != s.scene.lights[index].type) {
    return make_error(ErrorCode::kUsage, "no light " + std::to_string(index) + " of that type");
  }
  Light l = light;
  SceneDesc probe;
  probe.lights = {l};
  normalize_scene(probe);
  s.scene.lights[index] = probe.lights[0];
  if (s.caustics) return s.caustics->rederive(index, std::nullopt, s.scene.lights, s.scene.water, s.world_vertices);
  return Status::success();
}

Status Renderer::set_object_transform(std::uint32_t index, const Mat4f& t) {
  Impl& s = *impl_;
  if (index >= s.scene.objects.size()) return make_error(ErrorCode::kUsage, "no object " + std::to_string(index));
  SceneDesc probe = s.scene;
  probe.objects[index].transform = t;
  if (auto issue = validate_scene(probe, false)) {
    return make_error(ErrorCode::kUsage, issue->pointer + ": " + issue->message);
  }
  s.scene.objects[index].transform = t;
  s.world_vertices[index] = world_points(t, s.cpu_meshes[s.scene.objects[index].mesh_index].positions);
  float min_y = 1e30f;
  for (const auto& w : s.world_vertices[index]) min_y = std::min(min_y, static_cast<float>(w[1]));
  s.object_min_y[index] = min_y;
  if (s.caustics) return s.caustics->rederive(std::nullopt, index, s.scene.lights, s.scene.water, s.world_vertices);
  return Status::success();
}

void Renderer::set_wave_scale(float scale) {
  if (impl_->water) impl_->water->set_amplitude_scale(scale);
}

CausticsStats Renderer::caustics_stats(bool read_gpu_counters) {
  CausticsStats st = impl_->caustics ? impl_->caustics->stats(read_gpu_counters) : CausticsStats{};
  if (impl_->glass) st.gpu_bytes += impl_->glass->gpu_bytes();  // tables, rays, targets, illumination textures
  if (impl_->water_view) st.gpu_bytes += impl_->water_view->gpu_bytes();  // refraction, reflection, glow targets
  return st;
}

void Renderer::present(unsigned framebuffer, int width, int height) {
  Impl& s = *impl_;
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  s.present.use();
  s.present.set("u_exposure", s.exposure);
  glBindTextureUnit(0, s.hdr.color.get());
  glBindVertexArray(s.empty_vao.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glEnable(GL_DEPTH_TEST);
}

namespace {

template <typename T>
void flip_rows(std::vector<T>& px, int width, int height, int channels) {
  const std::size_t row = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
  for (int y = 0; y < height / 2; ++y) {
    std::swap_ranges(px.begin() + static_cast<std::ptrdiff_t>(y * row), px.begin() + static_cast<std::ptrdiff_t>((y + 1) * row),
                     px.begin() + static_cast<std::ptrdiff_t>((height - 1 - y) * row));
  }
}

}  // namespace

std::vector<float> Renderer::read_hdr() {
  Impl& s = *impl_;
  std::vector<float> px(static_cast<std::size_t>(s.hdr.width) * static_cast<std::size_t>(s.hdr.height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(s.hdr.color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  flip_rows(px, s.hdr.width, s.hdr.height, 4);
  return px;
}

std::vector<std::uint8_t> Renderer::read_display() {
  Impl& s = *impl_;
  s.display.ensure(s.hdr.width, s.hdr.height, GL_RGBA8, false);
  present(s.display.fbo.get(), s.hdr.width, s.hdr.height);
  std::vector<std::uint8_t> px(static_cast<std::size_t>(s.hdr.width) * static_cast<std::size_t>(s.hdr.height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(s.display.color.get(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(px.size()), px.data());
  flip_rows(px, s.hdr.width, s.hdr.height, 4);
  return px;
}

Camera Renderer::default_camera() const {
  if (impl_->scene.camera) return *impl_->scene.camera;
  Camera c;
  const glm::vec3 center = impl_->scene_center();
  const float r = impl_->scene_radius();
  const glm::vec3 eye = center + glm::normalize(glm::vec3(0.6f, 0.7f, 1.0f)) * (2.8f * r);
  c.position = {eye.x, eye.y, eye.z};
  c.target = {center.x, center.y, center.z};
  c.near_plane = 0.01f * r;
  c.far_plane = 10.0f * r;
  return c;
}

glm::vec3 Renderer::bounds_min() const { return impl_->lo; }
glm::vec3 Renderer::bounds_max() const { return impl_->hi; }

}  // namespace caustix::runtime
