#include "caustix/runtime/engine.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "caustics.h"
#include "caustics_effect.h"
#include "caustix/formats/frame.h"
#include "gl_objects.h"
#include "gl_calls.h"
#include "gl_state.h"
#include "scene_inputs.h"
#include "pass_timer.h"
#include "receiver_table.h"
#include "causticmap.h"
#include "causticmap_effect.h"
#include "glass.h"
#include "glass_effect.h"
#include "surface_textures.h"
#include "gpu_mesh.h"
#include "light_effect.h"
#include "shader_text.h"
#include "shadow_effect.h"
#include "shadow_maps.h"
#include "water_surface.h"
#include "volume.h"
#include "volume_effect.h"
#include "view_spectrum.h"
#include "water_view.h"

namespace caustix::runtime {
namespace {

glm::vec3 to_glm(const Vec3f& v) { return {v[0], v[1], v[2]}; }
glm::vec3 to_glm(const Vec3d& v) { return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])}; }
glm::vec4 vec4_of(const Vec3d& v, float w) { return glm::vec4(to_glm(v), w); }
glm::vec4 vec4_of(const Vec3f& v, float w) { return glm::vec4(to_glm(v), w); }

// World -> (s, t, v, 1) of a frame's maps: s = 0.5 (u / half_u + 1),
// t = 0.5 (w / half_w + 1), v along V (caustix.glsl's uv and c.y).
glm::mat4 frame_matrix(const BoundingFrame& f) {
  const glm::vec3 origin = to_glm(f.origin);
  const glm::vec3 rows[3] = {to_glm(f.u) * (0.5f / f.half[0]), to_glm(f.w) * (0.5f / f.half[2]), to_glm(f.v)};
  const float offsets[3] = {0.5f, 0.5f, 0.0f};
  glm::mat4 m(0.0f);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[c][r] = rows[r][c];
    m[3][r] = offsets[r] - glm::dot(rows[r], origin);
  }
  m[3][3] = 1.0f;
  return m;
}

Error usage(const std::string& what) { return make_error(ErrorCode::kUsage, what); }

}  // namespace

glm::mat4 View::projection() const {
  return glm::perspective(glm::radians(fov_y_deg), aspect, near_plane, far_plane);
}

glm::vec3 View::eye() const { return glm::vec3(glm::inverse(view)[3]); }

const char* glsl_include_source() { return shaders::k_caustix_glsl; }

struct Engine::Impl {
  SceneDesc scene;
  Bindings bindings;
  std::vector<GLuint> units;  // texture units any call may bind (StateGuard)
  std::vector<LevelMap> level_maps;  // owned: the caustics engine points into it
  std::vector<std::vector<std::array<double, 3>>> world_vertices;  // per object, for re-deriving frames
  std::vector<TriangleMesh> cpu_meshes;                             // object space, for moving objects
  std::vector<GpuMesh> meshes;
  SurfaceTextures textures;  // receivers' textures
  std::vector<float> object_min_y;  // world
  glm::vec3 lo{0}, hi{0};

  std::optional<ShadowMaps> shadows;
  std::optional<WaterSurface> water;
  std::optional<WaterView> water_view;
  std::unique_ptr<CausticsEngine> caustics;
  std::unique_ptr<GlassEngine> glass;
  std::unique_ptr<CausticMapEngine> caustic_maps;  // created on the first update that needs it
  std::vector<std::array<glm::vec3, 2>> object_boxes;  // world (min, max) per object
  std::vector<bool> out_of_view;  // per object, this update (FrameUpdate::camera; empty without one)
  std::unique_ptr<VolumeEngine> volume;  // scenes where something scatters
  // The light-side effects over the objects above, in the order update()
  // runs them for each light (light_effect.h).
  std::vector<std::unique_ptr<LightEffect>> effects;
  VolumeOptions volume_options;           // of the last update()
  gl::Texture dummy_array, dummy_2d;  // valid samplers where a receiver has no caustics or glass light
  // The caller's scene colour and depth as the view-side draws read them
  // (copies where they are multisampled or attached where a pass draws).
  gl::SceneReader scene_reader;

  // Engine::bind_all()'s table, built at its first call, then kept current
  // by update(): it copies the products whose versions moved.
  ReceiverTable table;
  // The options of the last update(), checked: new ones may reallocate
  // any product (and GL may hand a freed texture's name to its
  // successor), so the table copies everything again after an update
  // with other options.
  std::optional<CausticsOptions> options;
  Status refresh_table(bool everything) {
    std::vector<ReceiverTable::Pair> pairs(lighting.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      pairs[i].lighting = &lighting[i];
      pairs[i].receiver = !transmits(scene.objects[i / std::max<std::size_t>(scene.lights.size(), 1)].role);
    }
    std::vector<ReceiverTable::Versions> versions(scene.lights.size(), ReceiverTable::Versions{});
    for (std::uint32_t li = 0; li < versions.size(); ++li) {
      for (const auto& e : effects) e->product_versions(li, versions[li]);
    }
    CAUSTIX_RETURN_IF_ERROR(table.refresh(pairs, versions, everything));
    work.table_copies += table.copies;
    work.table_copied_bytes += table.copied_bytes;
    return gl::check_gl("the all-receivers table");
  }

  // One LightBlock per (object, light), at object * lights + light.
  std::vector<ReceiverLighting> lighting;
  gl::Buffer blocks;
  std::size_t stride = 0;
  bool updated = false;
  std::uint64_t frame = 0;  // update() calls so far
  // What the light side depends on, numbered (gl/made_from.h): each light,
  // and the objects' transforms; the water numbers its own surface.
  std::vector<std::uint64_t> light_versions;
  std::uint64_t transforms_version = 0;
  // CausticMapEngine::casters() for (transforms_version, glass method):
  // worked out again only when either changes (O(objects^2) box tests).
  std::vector<bool> cmap_casters;
  std::optional<std::pair<std::uint64_t, GlassMethod>> cmap_casters_of;
  const std::vector<bool>& caustic_map_casters(GlassMethod method) {
    const std::pair<std::uint64_t, GlassMethod> key{transforms_version, method};
    if (cmap_casters_of != key) {
      cmap_casters = CausticMapEngine::casters(scene, method);
      cmap_casters_of = key;
    }
    return cmap_casters;
  }
  FrameWork work;  // what the last update() remade and reused
  // The blocks as last uploaded (uploaded only when they change).
  std::vector<LightBlock> uploaded;
  std::vector<bool> uploaded_valid;
  // The last update()'s wavelengths, for the refracted views through
  // dispersive water and glass (draw_water, draw_glass's nearby view).
  ViewSpectrum view_spectrum;

  void draw_object(std::uint32_t i) const { meshes[scene.objects[i].mesh_index].draw(); }
  glm::mat4 model_of(std::uint32_t i) const { return glm::make_mat4(scene.objects[i].transform.data()); }
  float scene_radius() const { return 0.5f * glm::length(hi - lo) + 1e-3f; }
  glm::vec3 scene_center() const { return 0.5f * (lo + hi); }

  // World bounds from each mesh's box at its object's transform.
  void compute_bounds() {
    bool first = true;
    object_min_y.assign(scene.objects.size(), 0.0f);
    object_boxes.assign(scene.objects.size(), {glm::vec3(1e30f), glm::vec3(-1e30f)});
    for (std::size_t oi = 0; oi < scene.objects.size(); ++oi) {
      const Object& o = scene.objects[oi];
      const MeshInfo& mi = scene.meshes[o.mesh_index];
      const glm::mat4 model = glm::make_mat4(o.transform.data());
      float min_y = 1e30f;
      for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? mi.bounds_max[0] : mi.bounds_min[0], (c & 2) ? mi.bounds_max[1] : mi.bounds_min[1],
                               (c & 4) ? mi.bounds_max[2] : mi.bounds_min[2]);
        const glm::vec3 w = glm::vec3(model * glm::vec4(corner, 1.0f));
        lo = first ? w : glm::min(lo, w);
        hi = first ? w : glm::max(hi, w);
        min_y = std::min(min_y, w.y);
        object_boxes[oi] = {glm::min(object_boxes[oi][0], w), glm::max(object_boxes[oi][1], w)};
        first = false;
      }
      object_min_y[oi] = min_y;
    }
  }

  bool light_above_water(const Light& l) const {
    return scene.water && (l.type == LightType::kDirectional || l.position[1] > scene.water->level);
  }

  // The light's part of the block (the same for every receiver).
  void fill_light(LightBlock& b, std::uint32_t li, const CausticsOptions& co) const {
    const ShadowOptions& so = co.shadows;
    const Light& light = scene.lights[li];
    const bool dir = light.type == LightType::kDirectional;
    const ShadowMaps::Maps m = shadows->maps(li);
    b.mode.y = dir ? 1 : 2;
    b.mode.w = glass ? 1 : 0;
    b.light_direction = glm::vec4(glm::normalize(to_glm(light.direction)), m.vsm ? 1.0f : 0.0f);
    b.light_position = vec4_of(light.position, m.vsm ? so.vsm_bleeding : 0.0f);
    b.light_color = vec4_of(light.color, dir ? light.irradiance : light.intensity);
    const auto cone = spot_terms(light);
    b.spot = glm::vec4(cone[0], cone[1], cone[2], 0.0f);
    b.world_to_shadow = m.world_to_shadow;
    b.water = glm::vec4(-1e30f, 1.0f, m.far, m.texel);
    b.absorption = glm::vec4(0.0f);
    b.refracted = glm::vec4(0.0f);
    if (scene.water) {
      b.water.x = scene.water->level;
      b.water.y = water_index(*scene.water, co);  // n_d, or n at a monochromatic image's wavelength
      b.absorption = vec4_of(scene.water->absorption, 0.0f);
      b.refracted = glm::vec4(glm::refract(glm::vec3(b.light_direction), glm::vec3(0, 1, 0), 1.0f / b.water.y), 0.0f);
    }
  }

  // Per (object, light): caustics casting, flat-water transmission, or
  // direct light (the include's light modes), and light through glass.
  void fill_receiver(ReceiverLighting& r, std::uint32_t oi, std::uint32_t li, const CausticsOptions& co) const {
    const ShadowMaps::Maps m = shadows->maps(li);
    r.block = LightBlock{};
    fill_light(r.block, li, co);
    r.shadow_2d = m.opaque_2d;
    r.shadow_cube = m.opaque_cube;
    r.glass_shadow_2d = m.glass_2d;
    r.glass_shadow_cube = m.glass_cube;
    r.shadow_vsm = m.opaque_vsm;
    r.glass_shadow_vsm = m.glass_vsm;
    r.caustics = r.position = r.caustics_color = dummy_2d.get();
    r.glass_illumination = dummy_array.get();
    r.glass_target = dummy_2d.get();
    r.world_to_caustics = r.world_to_glass = r.world_to_caustic_map = glm::mat4(1.0f);
    r.caustic_map = dummy_2d.get();
    LightBlock& b = r.block;
    std::optional<CausticsEngine::Binding> cb;
    if (caustics && co.method != CausticsMethod::kNone) cb = caustics->binding(oi, li);
    if (cb) {
      const BoundingFrame& f = cb->map->frame;
      const float n = static_cast<float>(cb->map->map_size);
      b.mode.x = static_cast<int>(LightMode::kCaustics);
      b.frame_origin = vec4_of(f.origin, cb->self_tolerance);
      b.frame_u = vec4_of(f.u, 0.5f * std::hypot(2.0f * f.half[0] / n, 2.0f * f.half[2] / n));
      b.frame_v = vec4_of(f.v, cb->color ? 1.0f : 0.0f);
      b.frame_w = vec4_of(f.w, 0.0f);
      b.frame_half = vec4_of(f.half, 0.0f);
      r.caustics = cb->caustics;
      if (cb->color) r.caustics_color = cb->color;
      r.position = cb->position_map;
      r.world_to_caustics = frame_matrix(f);
      return;
    }
    const Light& light = scene.lights[li];
    const bool under = scene.water && object_min_y[oi] < scene.water->level && light_above_water(light);
    b.mode.x = static_cast<int>(under ? LightMode::kFlatWater : LightMode::kDirect);
    std::optional<CausticMapEngine::Binding> cm;
    // Not on a mirror itself: it is no receiver of the map (it lies in
    // front of the receivers the map's alpha records).
    if (caustic_maps && !under && co.method != CausticsMethod::kNone && !is_mirror(scene.objects[oi].role)) cm = caustic_maps->binding(li);
    if (cm) {
      const BoundingFrame& f = cm->frame;
      b.cmap_origin = vec4_of(f.origin, 1.0f);
      b.cmap_u = vec4_of(f.u, cm->texel_diagonal);
      b.cmap_v = vec4_of(f.v, cm->tolerance);
      b.cmap_w = vec4_of(f.w, cm->main_share);
      b.cmap_half = vec4_of(f.half, 0.0f);
      r.caustic_map = cm->map;
      r.world_to_caustic_map = frame_matrix(f);
      for (int c = 0; c < 4; ++c) r.world_to_caustic_map[c][1] *= cm->main_share;  // t over the main map's rows
    }
    std::optional<GlassEngine::Binding> g;
    if (glass && !under && co.method != CausticsMethod::kNone && co.glass_method == GlassMethod::kTable) g = glass->binding(oi, li);
    if (!g) return;
    const BoundingFrame& f = g->frame;
    b.mode.z = 1;
    b.glass_origin = vec4_of(f.origin, g->tolerance);
    b.glass_u = vec4_of(f.u, static_cast<float>(g->plane_v.size()));
    b.glass_v = vec4_of(f.v, g->focus[0]);
    b.glass_w = vec4_of(f.w, g->focus[1]);
    b.glass_half = vec4_of(f.half, g->focus[2]);
    for (std::size_t k = 0; k < g->plane_v.size() && k < 16; ++k) b.glass_plane_v[k / 4][static_cast<int>(k % 4)] = g->plane_v[k];
    r.glass_illumination = g->illumination;
    r.glass_target = g->target;
    r.world_to_glass = frame_matrix(f);
  }

  std::size_t slot(std::uint32_t oi, std::uint32_t li) const { return std::size_t{oi} * scene.lights.size() + li; }

  void upload_light(std::uint32_t li, const CausticsOptions& co) {
    for (std::uint32_t oi = 0; oi < scene.objects.size(); ++oi) {
      const std::size_t k = slot(oi, li);
      ReceiverLighting& r = lighting[k];
      fill_receiver(r, oi, li, co);
      if (uploaded_valid[k] && std::memcmp(&uploaded[k], &r.block, sizeof(LightBlock)) == 0) continue;
      glNamedBufferSubData(blocks.get(), static_cast<GLintptr>(r.offset), sizeof(LightBlock), &r.block);
      uploaded[k] = r.block;
      uploaded_valid[k] = true;
      ++work.blocks_uploaded;
    }
  }

  GpuMemory memory() const {
    GpuMemory m;
    for (const auto& e : effects) e->memory(m);  // shadow maps, level maps, glass, caustic maps, media
    for (const GpuMesh& mesh : meshes) m.meshes += mesh.gpu_bytes();
    m.meshes += textures.gpu_bytes;
    if (water) m.water = water->gpu_bytes();
    if (glass) m.views += glass->view_bytes();
    if (water_view) m.views += water_view->gpu_bytes();  // refraction, reflection, glow targets
    m.views += scene_reader.gpu_bytes();  // copies of the caller's scene, where a view-side draw needs them
    m.other = std::uint64_t{stride} * lighting.size() + 16 + 16;  // light blocks, the 1x1 stand-ins
    m.receiver_table = table.gpu_bytes();
    return m;
  }

  // What the effects borrow from the engine while they update.
  struct Services final : EngineServices {
    Impl& s;
    explicit Services(Impl& impl) : s(impl) {}
    const std::vector<std::vector<std::array<double, 3>>>& world_vertices() const override { return s.world_vertices; }
    const std::vector<std::array<glm::vec3, 2>>& object_boxes() const override { return s.object_boxes; }
    glm::vec3 scene_center() const override { return s.scene_center(); }
    float scene_radius() const override { return s.scene_radius(); }
    const WaterSurface* water() const override { return s.water ? &*s.water : nullptr; }
    const std::vector<bool>& caustic_map_casters(const CausticsOptions& o) override { return s.caustic_map_casters(o.glass_method); }
    void bind_light(std::uint32_t li, const CausticsOptions& co, const gl::Program* p) override {
      const ReceiverLighting& light_slot = s.lighting[s.slot(0, li)];
      ReceiverLighting now = light_slot;
      s.fill_receiver(now, 0, li, co);
      s.bind_slot(now);
      if (!p) return;
      const LightBlock& b = light_slot.block;
      p->set("u_light_type", b.mode.y);
      p->set("u_light_direction", glm::vec3(b.light_direction));
      p->set("u_light_position", glm::vec3(b.light_position));
      p->set("u_light_power", b.light_color.w);
      p->set("u_spot", glm::vec3(b.spot));
    }
    GpuMemory memory() const override { return s.memory(); }
    std::function<std::vector<ExitRay>()> glass_exit_rays(std::uint32_t li) const override {
      if (!s.glass) return {};
      return [&impl = s, li]() { return impl.glass->exit_sample(impl.scene, li); };
    }
  };

  void bind_slot(const ReceiverLighting& r) const {
    // The multi-bind call binds the indexed point alone: glBindBufferRange
    // would also set the generic GL_UNIFORM_BUFFER binding, which the
    // application may be using.
    const GLuint buffer = blocks.get();
    const auto offset = static_cast<GLintptr>(r.offset);
    const auto size = static_cast<GLsizeiptr>(sizeof(LightBlock));
    glBindBuffersRange(GL_UNIFORM_BUFFER, bindings.block, 1, &buffer, &offset, &size);
    glBindTextureUnit(bindings.shadow_2d, r.shadow_2d);
    glBindTextureUnit(bindings.shadow_cube, r.shadow_cube);
    glBindTextureUnit(bindings.caustics, r.caustics);
    glBindTextureUnit(bindings.position, r.position);
    glBindTextureUnit(bindings.glass_illumination, r.glass_illumination);
    glBindTextureUnit(bindings.glass_target, r.glass_target);
    glBindTextureUnit(bindings.glass_shadow_2d, r.glass_shadow_2d);
    glBindTextureUnit(bindings.glass_shadow_cube, r.glass_shadow_cube);
    glBindTextureUnit(bindings.caustic_map, r.caustic_map);
    glBindTextureUnit(bindings.shadow_vsm, r.shadow_vsm);
    glBindTextureUnit(bindings.glass_shadow_vsm, r.glass_shadow_vsm);
    glBindTextureUnit(bindings.caustics_color, r.caustics_color);
  }

  std::string lighting_prefix() const {
    const Bindings& b = bindings;
    std::string s;
    auto def = [&](const char* name, unsigned v) { s += std::string("#define ") + name + " " + std::to_string(v) + "\n"; };
    def("CAUSTIX_BINDING_BLOCK", b.block);
    def("CAUSTIX_BINDING_TABLE", b.table);
    def("CAUSTIX_UNIT_SHADOW_2D", b.shadow_2d);
    def("CAUSTIX_UNIT_SHADOW_CUBE", b.shadow_cube);
    def("CAUSTIX_UNIT_CAUSTICS", b.caustics);
    def("CAUSTIX_UNIT_POSITION", b.position);
    def("CAUSTIX_UNIT_GLASS_ILLUMINATION", b.glass_illumination);
    def("CAUSTIX_UNIT_GLASS_TARGET", b.glass_target);
    def("CAUSTIX_UNIT_GLASS_SHADOW_2D", b.glass_shadow_2d);
    def("CAUSTIX_UNIT_GLASS_SHADOW_CUBE", b.glass_shadow_cube);
    def("CAUSTIX_UNIT_CAUSTIC_MAP", b.caustic_map);
    def("CAUSTIX_UNIT_SHADOW_VSM", b.shadow_vsm);
    def("CAUSTIX_UNIT_GLASS_SHADOW_VSM", b.glass_shadow_vsm);
    def("CAUSTIX_UNIT_CAUSTICS_COLOR", b.caustics_color);
    return s + shaders::k_caustix_glsl;
  }

  gl::StateGuard guard() const { return gl::StateGuard(units); }

  // GL call counts (GlCalls): the frame in progress, and what set_*
  // calls issue before the next update() opens a frame.
  mutable gl::CallTally frame_calls, pending_calls;
  // GPU time per pass (gl/pass_timer.h).
  mutable gl::PassTimer timer;
  // An engine call's scope: its GL calls counted into the frame, its
  // passes timed by the engine's timer.
  struct FrameScope {
    gl::Counting counting;
    gl::Timing timing;
  };
  FrameScope count_frame() const { return FrameScope{gl::Counting(frame_calls), gl::Timing(timer)}; }
  gl::Counting count_pending() const { return gl::Counting(pending_calls); }
  void begin_frame_calls() {
    frame_calls = pending_calls;
    pending_calls = {};
  }

  // The light entering the water (ambient sky plus every directional light
  // through flat water), the water's colour and attenuation.
  WaterMedium medium(const glm::vec3& eye, const WaterLook& look) const {
    WaterMedium m;
    if (!scene.water) return m;
    glm::vec3 light_in_water = look.ambient * look.sky;
    for (const Light& l : scene.lights) {
      if (l.type != LightType::kDirectional) continue;
      const glm::vec3 d = glm::normalize(to_glm(l.direction));
      if (d.y < 0.0f) {
        const double t = fresnel_transmittance(-d.y, 1.0 / scene.water->ior);
        light_in_water += to_glm(l.color) * (l.irradiance * -d.y * static_cast<float>(t));
      }
    }
    m.color = look.water_color * light_in_water;
    m.k = look.attenuation ? *look.attenuation : to_glm(scene.water->absorption);
    m.camera_under = eye.y < scene.water->level;
    return m;
  }
};

Engine::Engine() : impl_(std::make_unique<Impl>()) {}
Engine::~Engine() = default;

Result<std::unique_ptr<Engine>> Engine::create(const RuntimeScene& scene, const Bindings& bindings) {
  const unsigned units[12] = {bindings.shadow_2d,       bindings.shadow_cube,       bindings.caustics,
                              bindings.position,        bindings.glass_illumination, bindings.glass_target,
                              bindings.glass_shadow_2d, bindings.glass_shadow_cube,  bindings.caustic_map,
                              bindings.shadow_vsm,      bindings.glass_shadow_vsm,   bindings.caustics_color};
  GLint max_units = 0, max_ubo = 0, max_ssbo = 0;
  glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &max_units);
  glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &max_ubo);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &max_ssbo);
  if (max_units == 0) return make_error(ErrorCode::kGraphics, "no current OpenGL context (the engine needs the application's 4.5 core context)");
  for (int i = 0; i < 12; ++i) {
    if (units[i] >= static_cast<unsigned>(max_units)) {
      return usage("Bindings: texture unit " + std::to_string(units[i]) + " is beyond this context's " + std::to_string(max_units));
    }
    for (int j = 0; j < i; ++j) {
      if (units[i] == units[j]) return usage("Bindings: texture unit " + std::to_string(units[i]) + " is given twice");
    }
  }
  if (bindings.block >= static_cast<unsigned>(max_ubo)) return usage("Bindings: uniform-buffer binding " + std::to_string(bindings.block) + " is beyond this context's " + std::to_string(max_ubo));
  if (bindings.table >= static_cast<unsigned>(max_ssbo)) return usage("Bindings: shader-storage binding " + std::to_string(bindings.table) + " is beyond this context's " + std::to_string(max_ssbo));

  std::unique_ptr<Engine> e(new Engine());
  Impl& s = *e->impl_;
  s.scene = scene.desc;
  s.bindings = bindings;
  for (GLuint u = 0; u < 8; ++u) s.units.push_back(u);  // the passes' own units
  for (unsigned u : units) {
    if (u >= 8) s.units.push_back(u);
  }
  const gl::StateGuard guard = s.guard();

  for (const TriangleMesh& m : scene.meshes) s.meshes.push_back(upload_mesh(m));
  s.textures = upload_surface_textures(s.scene);
  for (TextureImage& im : s.scene.images) {  // on the GPU now
    std::vector<std::uint8_t>().swap(im.rgb);
    std::vector<std::uint8_t>().swap(im.alpha);
  }
  s.cpu_meshes = scene.meshes;
  for (const Object& o : s.scene.objects) s.world_vertices.push_back(world_points(o.transform, scene.meshes[o.mesh_index].positions));
  s.compute_bounds();

  Impl* impl = &s;
  auto shadows = ShadowMaps::create(s.scene, [impl](std::uint32_t i) { impl->draw_object(i); });
  if (!shadows) return shadows.error();
  s.shadows.emplace(std::move(*shadows));
  s.dummy_array = gl::make_texture(GL_TEXTURE_2D_ARRAY);
  glTextureStorage3D(s.dummy_array.get(), 1, GL_RGBA32F, 1, 1, 1);
  glClearTexImage(s.dummy_array.get(), 0, GL_RGBA, GL_FLOAT, nullptr);
  s.dummy_2d = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(s.dummy_2d.get(), 1, GL_RGBA32F, 1, 1);
  glClearTexImage(s.dummy_2d.get(), 0, GL_RGBA, GL_FLOAT, nullptr);

  bool has_glass = false;
  for (const Object& o : s.scene.objects) has_glass = has_glass || transmits(o.role);
  if (has_glass) {
    auto engine = GlassEngine::create(s.scene, scene.transport_tables, scene.spectral_tables, s.meshes, scene.meshes,
                                      [impl](std::uint32_t i) { impl->draw_object(i); },
                                      kGlslVersion + s.lighting_prefix());
    if (!engine) return engine.error();
    s.glass = std::move(*engine);
  }
  {
    auto volume = VolumeEngine::create(s.scene, scene.index_grids, s.lo.y, kGlslVersion + s.lighting_prefix());
    if (!volume) return volume.error();
    s.volume = std::move(*volume);
  }
  if (s.scene.water) {
    auto water = WaterSurface::create(*s.scene.water);
    if (!water) return water.error();
    s.water.emplace(std::move(*water));
    auto view = WaterView::create();
    if (!view) return view.error();
    s.water_view.emplace(std::move(*view));
    if (!scene.level_maps.empty()) {
      s.level_maps = scene.level_maps;
      auto engine = CausticsEngine::create(
          s.level_maps, *s.water, [impl](std::uint32_t i) { impl->draw_object(i); },
          [impl](std::uint32_t i) { return impl->model_of(i); });
      if (!engine) return engine.error();
      s.caustics = std::move(*engine);
    }
  }

  // The light-side effects, in the order update() runs them per light: the
  // shadow maps first (the others read them), the water's caustics, the
  // glass's (whose rays read the light's block), the caustic maps (made on
  // the first frame that needs them), and last the media, whose photons
  // start from what the others made.
  s.effects.push_back(std::make_unique<ShadowEffect>(*s.shadows));
  if (s.caustics) s.effects.push_back(std::make_unique<CausticsEffect>(*s.caustics));
  if (s.glass) s.effects.push_back(std::make_unique<GlassEffect>(*s.glass));
  s.effects.push_back(std::make_unique<CausticMapEffect>(s.caustic_maps, s.scene, [impl](std::uint32_t i) { impl->draw_object(i); }));
  if (s.volume) s.effects.push_back(std::make_unique<VolumeEffect>(*s.volume));

  // The blocks, one per (object, light), each at a multiple of the
  // context's uniform-buffer offset alignment.
  GLint align = 256;
  glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &align);
  const auto a = static_cast<std::size_t>(std::max(align, 1));
  s.stride = (sizeof(LightBlock) + a - 1) / a * a;
  s.lighting.resize(s.scene.objects.size() * s.scene.lights.size());
  s.uploaded.resize(s.lighting.size());
  s.uploaded_valid.assign(s.lighting.size(), false);
  s.light_versions.assign(s.scene.lights.size(), 0);
  for (std::size_t i = 0; i < s.lighting.size(); ++i) s.lighting[i].offset = i * s.stride;
  if (!s.lighting.empty()) {
    s.blocks = gl::make_buffer();
    glNamedBufferStorage(s.blocks.get(), static_cast<GLsizeiptr>(s.lighting.size() * s.stride), nullptr, GL_DYNAMIC_STORAGE_BIT);
    for (ReceiverLighting& r : s.lighting) r.buffer = s.blocks.get();
  }
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("engine set-up"));
  return e;
}

const SceneDesc& Engine::scene() const { return impl_->scene; }
const Bindings& Engine::bindings() const { return impl_->bindings; }
CausticsOptions Engine::default_options() const { return default_caustics_options(impl_->scene); }
WaterLook Engine::default_water_look() const { return runtime::default_water_look(impl_->scene); }
glm::vec3 Engine::bounds_min() const { return impl_->lo; }
glm::vec3 Engine::bounds_max() const { return impl_->hi; }

Status Engine::set_light(std::uint32_t index, const Light& light) {
  Impl& s = *impl_;
  if (index >= s.scene.lights.size() || light.type != s.scene.lights[index].type) {
    return usage("set_light: no light " + std::to_string(index) + " of that type");
  }
  SceneDesc probe;
  probe.lights = {light};
  normalize_scene(probe);
  s.scene.lights[index] = probe.lights[0];
  ++s.light_versions[index];
  if (s.caustics) s.caustics->rederive(index, std::nullopt);  // at its next update (no GL here)
  return Status::success();
}

Status Engine::set_object_transform(std::uint32_t index, const Mat4f& t) {
  Impl& s = *impl_;
  if (index >= s.scene.objects.size()) return usage("set_object_transform: no object " + std::to_string(index));
  SceneDesc probe = s.scene;
  probe.objects[index].transform = t;
  // The engine's images keep their sizes, not their texels (they live on
  // the GPU), which the rules would refuse; the transform is not theirs.
  probe.images.clear();
  if (auto issue = validate_scene(probe, false)) return usage("set_object_transform: " + issue->pointer + ": " + issue->message);
  s.scene.objects[index].transform = t;
  s.world_vertices[index] = world_points(t, s.cpu_meshes[s.scene.objects[index].mesh_index].positions);
  s.compute_bounds();
  ++s.transforms_version;
  if (s.caustics) s.caustics->rederive(std::nullopt, index);  // at the next update (no GL here)
  return Status::success();
}

void Engine::set_wave_scale(float scale) {
  if (impl_->water) impl_->water->set_amplitude_scale(scale);
}

std::optional<WaterGrid> Engine::water_grid() const {
  const SceneDesc& sc = impl_->scene;
  if (!sc.water) return std::nullopt;
  const Water& w = *sc.water;
  return WaterGrid{w.cells[0] + 1, w.cells[1] + 1, w.extent[0], w.extent[1], w.extent[2], w.extent[3], w.level};
}

Status Engine::set_water_heights(std::span<const float> heights) {
  Impl& s = *impl_;
  const auto grid = water_grid();
  if (!grid) return usage("set_water_heights: the scene has no water");
  const std::size_t n = std::size_t{grid->columns} * grid->rows;
  if (heights.size() != n) {
    return usage("set_water_heights: " + std::to_string(heights.size()) + " heights for a grid of " + std::to_string(grid->columns) +
                 " x " + std::to_string(grid->rows) + " vertices");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(heights[i])) {
      return usage("set_water_heights: height " + std::to_string(i) + " (column " + std::to_string(i % grid->columns) + ", row " +
                   std::to_string(i / grid->columns) + ") is not finite");
    }
  }
  const gl::Counting counting = s.count_pending();
  const gl::StateGuard guard = s.guard();
  s.water->set_heights(heights.data());
  return gl::check_gl("water heights");
}

Status Engine::set_water_heights_buffer(unsigned buffer, std::size_t offset) {
  Impl& s = *impl_;
  const auto grid = water_grid();
  if (!grid) return usage("set_water_heights_buffer: the scene has no water");
  if (buffer == 0 || !glIsBuffer(buffer)) return usage("set_water_heights_buffer: " + std::to_string(buffer) + " is not a GL buffer");
  GLint64 size = 0;
  glGetNamedBufferParameteri64v(buffer, GL_BUFFER_SIZE, &size);
  const std::size_t need = std::size_t{4} * grid->columns * grid->rows;
  if (offset % 4 != 0 || size < 0 || offset > static_cast<std::size_t>(size) || static_cast<std::size_t>(size) - offset < need) {
    return usage("set_water_heights_buffer: buffer " + std::to_string(buffer) + " holds " + std::to_string(size) + " bytes; " +
                 std::to_string(need) + " from offset " + std::to_string(offset) + " (a multiple of 4) are needed");
  }
  const gl::Counting counting = s.count_pending();
  const gl::StateGuard guard = s.guard();
  s.water->copy_heights_from_buffer(buffer, static_cast<GLintptr>(offset));
  return gl::check_gl("water heights from a buffer");
}

Status Engine::set_water_heights_texture(unsigned texture) {
  Impl& s = *impl_;
  const auto grid = water_grid();
  if (!grid) return usage("set_water_heights_texture: the scene has no water");
  if (texture == 0 || !glIsTexture(texture)) return usage("set_water_heights_texture: " + std::to_string(texture) + " is not a GL texture");
  GLint target = 0, w = 0, h = 0, format = 0;
  glGetTextureParameteriv(texture, GL_TEXTURE_TARGET, &target);
  if (target != GL_TEXTURE_2D) return usage("set_water_heights_texture: texture " + std::to_string(texture) + " is not a 2D texture");
  glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_WIDTH, &w);
  glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_HEIGHT, &h);
  glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
  if (format != GL_R32F || w != static_cast<GLint>(grid->columns) || h != static_cast<GLint>(grid->rows)) {
    return usage("set_water_heights_texture: texture " + std::to_string(texture) + " must be GL_R32F, " + std::to_string(grid->columns) +
                 " x " + std::to_string(grid->rows) + " (it is " + std::to_string(w) + " x " + std::to_string(h) + ")");
  }
  const gl::Counting counting = s.count_pending();
  const gl::StateGuard guard = s.guard();
  s.water->copy_heights_from_texture(texture);
  return gl::check_gl("water heights from a texture");
}

void Engine::use_scene_waves() {
  if (impl_->water) impl_->water->use_waves();
}

Status Engine::update(const FrameUpdate& f) {
  Impl& s = *impl_;
  if (!std::isfinite(f.time)) return usage("update: time is not finite");
  if (f.light_side_interval < 1 || f.light_side_interval > 64) {
    return usage("update: light_side_interval must be 1..64, got " + std::to_string(f.light_side_interval));
  }
  if (f.out_of_view_interval < 1 || f.out_of_view_interval > 64) {
    return usage("update: out_of_view_interval must be 1..64, got " + std::to_string(f.out_of_view_interval));
  }
  if (f.camera) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) {
        if (!std::isfinite((*f.camera)[c][r])) return usage("update: camera has a value that is not finite");
      }
    }
  }
  // The options are checked where they change: once, by the effects
  // that read them, not every frame.
  const bool new_options = s.options != f.caustics;
  if (new_options) {
    Impl::Services checking(s);
    CAUSTIX_RETURN_IF_ERROR(check_wavelengths(s.scene, f.caustics));
    for (const auto& e : s.effects) CAUSTIX_RETURN_IF_ERROR(e->check(f.caustics, checking));
    s.options = f.caustics;
  }
  s.begin_frame_calls();
  const auto scope = s.count_frame();
  const gl::StateGuard guard = s.guard();
  const CausticsOptions& co = f.caustics;
  ++s.frame;
  s.timer.begin_frame(s.frame);
  s.work = FrameWork{};
  if (s.water) s.work.water = s.water->update(f.time);
  s.volume_options = co.volume;
  Impl::Services services(s);
  // Objects whose world box lies wholly outside one of the camera's clip
  // planes are out of view.
  s.out_of_view.clear();
  if (f.camera) {
    s.out_of_view.assign(s.scene.objects.size(), false);
    for (std::size_t oi = 0; oi < s.object_boxes.size(); ++oi) {
      const auto& b = s.object_boxes[oi];
      std::array<int, 6> outside{};
      for (int c = 0; c < 8; ++c) {
        const glm::vec4 p = *f.camera * glm::vec4((c & 1) ? b[1].x : b[0].x, (c & 2) ? b[1].y : b[0].y, (c & 4) ? b[1].z : b[0].z, 1.0f);
        for (int k = 0; k < 3; ++k) {
          outside[static_cast<std::size_t>(2 * k)] += p[k] < -p.w ? 1 : 0;
          outside[static_cast<std::size_t>(2 * k + 1)] += p[k] > p.w ? 1 : 0;
        }
      }
      s.out_of_view[oi] = std::any_of(outside.begin(), outside.end(), [](int n) { return n == 8; });
    }
  }
  for (const auto& e : s.effects) {
    CAUSTIX_RETURN_IF_ERROR(e->begin_frame(FrameStart{s.scene, s.frame, co, services, &s.out_of_view, f.out_of_view_interval}));
  }
  FrameWork& work = s.work;
  for (std::uint32_t li = 0; li < s.scene.lights.size(); ++li) {
    // Lights take turns when the light side runs every Nth frame.
    const bool due = f.light_side_interval <= 1 || (s.frame + li) % f.light_side_interval == 0;
    const LightUpdate u{s.scene, li, co, SceneVersions{s.light_versions[li], s.transforms_version, s.water ? s.water->version() : 0},
                        due, services, work};
    // The light's blocks are uploaded before an effect that reads them,
    // with what the effects before it made, and after the last that
    // writes them.
    bool block_stale = true;
    for (const auto& e : s.effects) {
      if (!e->active(co)) continue;
      if (e->reads_light_block() && block_stale) {
        s.upload_light(li, co);
        block_stale = false;
      }
      CAUSTIX_RETURN_IF_ERROR(e->update_light(u));
      block_stale = block_stale || e->writes_light_block();
    }
    if (block_stale) s.upload_light(li, co);
  }
  for (const auto& e : s.effects) e->end_frame(s.frame);
  s.view_spectrum = ViewSpectrum{traced_wavelengths(s.scene, co), co.wavelength_nm.has_value()};
  s.updated = true;
  if (s.table.built()) CAUSTIX_RETURN_IF_ERROR(s.refresh_table(new_options));
  return gl::check_gl("engine update");
}

Result<ReceiverLighting> Engine::lighting(std::uint32_t object, std::uint32_t light) const {
  const Impl& s = *impl_;
  if (object >= s.scene.objects.size()) return usage("lighting: no object " + std::to_string(object));
  if (light >= s.scene.lights.size()) return usage("lighting: no light " + std::to_string(light));
  if (transmits(s.scene.objects[object].role)) {
    return usage("lighting: object " + std::to_string(object) + " ('" + s.scene.objects[object].name + "') is transparent, not a receiver");
  }
  if (!s.updated) return usage("lighting: update() has not run yet");
  return s.lighting[s.slot(object, light)];
}

Status Engine::bind(std::uint32_t object, std::uint32_t light) const {
  auto r = lighting(object, light);
  if (!r) return r.error();
  const auto scope = impl_->count_frame();
  impl_->bind_slot(*r);
  return Status::success();
}

Status Engine::bind_all() {
  Impl& s = *impl_;
  if (!s.updated) return usage("bind_all: update() has not run yet");
  const auto scope = s.count_frame();
  if (!s.table.built()) {
    const gl::StateGuard guard = s.guard();
    CAUSTIX_RETURN_IF_ERROR(s.refresh_table(true));
  }
  s.table.bind(s.bindings);
  return Status::success();
}

std::string Engine::glsl_include() const { return impl_->lighting_prefix(); }

WaterMedium Engine::water_medium(const View& view, const WaterLook& look) const { return impl_->medium(view.eye(), look); }

Status Engine::draw_water(const View& view, const WaterLook& look, const std::function<void(const WaterPass&)>& draw_scene,
                          unsigned scene_depth) {
  Impl& s = *impl_;
  if (!s.water) return usage("draw_water: the scene has no water");
  gl::SceneTexture depth;
  if (scene_depth != 0) {
    CAUSTIX_ASSIGN_OR_RETURN(depth, gl::describe_scene_texture("draw_water", scene_depth, gl::SceneTextureKind::kDepth, "scene depth"));
  }
  if (look.steps < 1 || look.steps > 64 || look.max_steps < 1 || look.max_steps > 64 || look.texture_size < 0 ||
      look.texture_size > 8192 || !(look.fov_ext >= 1.0f && look.fov_ext <= 4.0f) ||
      (look.max_texture_size != 0 && (look.max_texture_size < 16 || look.max_texture_size > 8192))) {
    return usage("draw_water: water look: steps and max_steps must be 1..64, texture size 0 (auto) or 1..8192, its limit 0 or "
                 "16..8192, FOV_ext 1..4");
  }
  if (!(view.aspect > 0.0f) || !(view.near_plane > 0.0f) || !(view.far_plane > view.near_plane) || !(view.fov_y_deg > 0.0f && view.fov_y_deg < 180.0f)) {
    return usage("draw_water: the view needs aspect > 0, 0 < near < far and a field of view in (0, 180) degrees");
  }
  const auto scope = s.count_frame();
  const gl::StateGuard guard = s.guard();
  GLint target_fbo = 0;
  int viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target_fbo);
  glGetIntegerv(GL_VIEWPORT, viewport);
  if (depth) {
    const int w = depth.width, h = depth.height;
    if (w < viewport[0] + viewport[2] || h < viewport[1] + viewport[3]) {
      return usage("draw_water: scene depth is " + std::to_string(w) + "x" + std::to_string(h) +
                   ", smaller than the viewport's far corner " + std::to_string(viewport[0] + viewport[2]) + "x" +
                   std::to_string(viewport[1] + viewport[3]));
    }
  }

  WaterView::Frame f;
  f.target_fbo = static_cast<GLuint>(target_fbo);
  std::copy(viewport, viewport + 4, f.viewport);
  f.main.view = view.view;
  f.main.proj = view.projection();
  f.main.eye = view.eye();
  f.fov_y_deg = view.fov_y_deg;
  f.aspect = view.aspect;
  f.near_plane = view.near_plane;
  f.far_plane = view.far_plane;
  f.water = &*s.scene.water;
  f.medium = s.medium(f.main.eye, look);
  f.waves = view_samples(s.view_spectrum, s.scene.water->ior, s.scene.water->dispersion);
  // The sun (first directional light): highlight and glow.
  for (const Light& l : s.scene.lights) {
    if (l.type != LightType::kDirectional) continue;
    f.sun_direction = glm::normalize(to_glm(l.direction));
    f.sun_color = to_glm(l.color) * l.irradiance;
    break;
  }
  CAUSTIX_RETURN_IF_ERROR(s.water_view->draw(f, look, draw_scene, guard, s.scene_reader, depth, [&]() { s.water->draw(); }));
  return gl::check_gl("water surface");
}

Status Engine::draw_glass(const View& view, unsigned scene_color, unsigned scene_depth, const glm::vec3& sky,
                          const GlassViewOptions& options) {
  Impl& s = *impl_;
  for (const auto& [name, value] : {std::pair{"glass view iterations", options.iterations},
                                    std::pair{"glass view exit_iterations", options.exit_iterations}}) {
    if (value < 1 || value > 64) return usage(std::string("draw_glass: ") + name + " must be 1..64, got " + std::to_string(value));
  }
  if (!s.glass) return Status::success();
  if (options.environment != 0) {
    GLint target = 0;
    if (glIsTexture(options.environment)) glGetTextureParameteriv(options.environment, GL_TEXTURE_TARGET, &target);
    if (target != GL_TEXTURE_CUBE_MAP) {
      return usage("draw_glass: environment " + std::to_string(options.environment) + " is not a cube-map texture");
    }
  }
  gl::SceneTexture color, depth;
  CAUSTIX_ASSIGN_OR_RETURN(color, gl::describe_scene_texture("draw_glass", scene_color, gl::SceneTextureKind::kColor, "scene colour"));
  CAUSTIX_ASSIGN_OR_RETURN(depth, gl::describe_scene_texture("draw_glass", scene_depth, gl::SceneTextureKind::kDepth, "scene depth"));
  if (color.width != depth.width || color.height != depth.height) return usage("draw_glass: scene colour and depth differ in size");
  const auto scope = s.count_frame();
  const gl::StateGuard guard = s.guard();
  CAUSTIX_RETURN_IF_ERROR(s.glass->draw_glass(s.scene, view.projection() * view.view, view.eye(), sky, color, depth, s.scene_reader,
                                              2.0f * s.scene_radius(), options, s.view_spectrum, s.object_boxes));
  return gl::check_gl("glass surface");
}

bool Engine::has_media() const { return impl_->volume != nullptr; }

Status Engine::draw_media(const glm::mat4& view_proj, unsigned scene_color, unsigned scene_depth, float scale) {
  Impl& s = *impl_;
  if (!s.volume) return Status::success();
  if (!s.updated) return usage("draw_media: update() has not run yet");
  gl::SceneTexture color, depth;
  if (scene_color != 0) {
    CAUSTIX_ASSIGN_OR_RETURN(color, gl::describe_scene_texture("draw_media", scene_color, gl::SceneTextureKind::kColor, "scene colour"));
  }
  CAUSTIX_ASSIGN_OR_RETURN(depth, gl::describe_scene_texture("draw_media", scene_depth, gl::SceneTextureKind::kDepth, "scene depth"));
  if (color && (color.width != depth.width || color.height != depth.height)) {
    return usage("draw_media: scene colour and depth differ in size");
  }
  if (!std::isfinite(scale) || scale < 0.0f) return usage("draw_media: scale must be finite and >= 0");
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(view_proj[c][r])) return usage("draw_media: the view-projection matrix is not finite");
    }
  }
  if (std::fabs(glm::determinant(view_proj)) < 1e-30f) return usage("draw_media: the view-projection matrix is singular");
  const auto scope = s.count_frame();
  const gl::StateGuard guard = s.guard();
  CAUSTIX_RETURN_IF_ERROR(s.volume->draw(s.scene, view_proj, color, depth, s.scene_reader, scale, s.volume_options));
  return gl::check_gl("media");
}

VolumeStats Engine::volume_stats(bool wait) {
  Impl& s = *impl_;
  if (!s.volume) return VolumeStats{};
  const auto scope = s.count_frame();
  const gl::StateGuard guard = s.guard();
  return s.volume->stats(wait);
}

std::optional<AlbedoMap> Engine::albedo_map(std::uint32_t index) const {
  const Impl& s = *impl_;
  if (index >= s.scene.objects.size() || s.textures.albedo[index] == 0) return std::nullopt;
  const AlbedoTexture& t = *s.scene.objects[index].material.albedo_texture;
  return AlbedoMap{s.textures.albedo[index], t.projection, t.transform};
}

std::optional<SurfaceMapBindings> Engine::surface_maps(std::uint32_t index) const {
  const Impl& s = *impl_;
  if (index >= s.scene.objects.size() || !s.scene.objects[index].material.maps) return std::nullopt;
  const SurfaceMaps& m = *s.scene.objects[index].material.maps;
  SurfaceMapBindings b;
  const std::array<std::pair<const std::optional<MapTexture>*, SurfaceMapBindings::Map*>, 4> slots{
      {{&m.metallic_roughness, &b.metallic_roughness}, {&m.normal, &b.normal}, {&m.occlusion, &b.occlusion}, {&m.emissive, &b.emissive}}};
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const auto& [map, out] = slots[k];
    if (*map && s.textures.maps[index][k] != 0) *out = {s.textures.maps[index][k], (*map)->projection, (*map)->transform};
  }
  b.normal_scale = m.normal_scale;
  b.occlusion_strength = m.occlusion_strength;
  b.alpha_mode = m.alpha_mode;
  b.alpha = m.alpha;
  b.alpha_cutoff = m.alpha_cutoff;
  return b;
}

Status Engine::draw_object(std::uint32_t index) const {
  const Impl& s = *impl_;
  if (index >= s.scene.objects.size()) return usage("draw_object: no object " + std::to_string(index));
  const auto scope = s.count_frame();
  GLint vao = 0;
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao);
  s.draw_object(index);
  glBindVertexArray(static_cast<GLuint>(vao));
  return Status::success();
}

CausticsStats Engine::stats(bool wait) {
  Impl& s = *impl_;
  const auto scope = s.count_frame();
  CausticsStats st = s.caustics ? s.caustics->stats(wait) : CausticsStats{};
  st.frame = s.frame;
  st.work = s.work;
  st.memory = s.memory();
  if (s.glass) st.glass_wavelengths = s.glass->wavelengths();
  st.gpu_bytes = st.memory.total();
  const gl::CallTally& c = s.frame_calls;
  st.gl = GlCalls{gl::kCountingBuilt, c.calls, c.draws, c.dispatches, c.syncs, c.upload_bytes};
  return st;
}

void Engine::set_gpu_timing(bool enabled, bool statistics) { impl_->timer.set_enabled(enabled, statistics); }

GpuTimes Engine::gpu_times() {
  const auto scope = impl_->count_frame();
  return impl_->timer.latest();
}

CausticMapStats Engine::caustic_map_stats(bool wait) {
  Impl& s = *impl_;
  if (!s.caustic_maps) return {};
  const auto scope = s.count_frame();
  const gl::StateGuard guard = s.guard();
  return s.caustic_maps->stats(wait);
}

}  // namespace caustix::runtime
