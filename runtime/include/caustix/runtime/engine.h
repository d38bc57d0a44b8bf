#pragma once
// caustix::runtime::Engine: caustics inside an application's own renderer.
// docs/embedding.md is the guide; this header is the contract.
//
// The context. Every call needs the application's OpenGL 4.5 core context
// current on the calling thread (the one the engine was created in). The
// engine never creates a context, never draws into the default framebuffer
// unless the caller has it bound, and never assumes a viewport, program,
// VAO or any other state: each call saves the state it touches and restores
// it before returning (tests/engine_test.cpp compares the GL state it knows
// before and after every call). The exceptions are named where they apply:
// bind() and bind_all() exist to change bindings, and the callback of
// draw_water() runs with the caller's state but for what WaterPass lists.
//
// The light side (no camera): update() animates the water (or takes the
// application's heights), renders every light's shadow maps, its caustics
// maps (Tipprasert 2006: level map, uniform, volumetric, splatting) and the glass
// illumination textures (Iwasaki et al.). Afterwards, for every (receiver, light)
// pair, lighting() gives the GL textures, the world -> map matrices and the
// scalars as a plain struct, and bind() binds them where the GLSL include
// (glsl_include(), installed as caustix/runtime/caustix.glsl) expects
// them; the application's fragment shader then calls
//     vec3 caustix_irradiance(vec3 world_position, vec3 world_normal)
// once per light and adds the results (Tipprasert 2006 eq. 4-20). A deferred or
// clustered-forward pass, which cannot bind per pair, calls bind_all()
// instead and, in a shader compiled with CAUSTIX_ALL_RECEIVERS,
// caustix_irradiance_all(world_position, world_normal, object): every
// light at any receiver.
//
// The view side, into the caller's framebuffer with the caller's camera:
// draw_water() (Mihalik 2008), draw_glass() (Iwasaki et al. §3) and draw_media()
// (Pfeuti), each optional.
//
// Mirrors and caustic maps (timofy 2009; docs/caustic-maps.md): light off
// mirror objects, and through glass when FrameUpdate::caustics.glass_method
// is kCausticMap, reaches the receivers through each light's image-space
// caustic map, which update() renders; the include adds it.
//
// Media (Pfeuti; docs/volume.md): in a scene where something scatters (a
// medium box, water or glass with "scattering"), update() also marches
// photons through the media, bent by the transparent objects' baked index
// grids, into a radiance grid per light; draw_media() adds the single
// scattering seen along the camera's rays. Scenes without media pay
// nothing.
//
// Errors: every fallible call returns Status/Result; bad input (an index out
// of range, a non-finite height, a non-rigid transform, a texture of the
// wrong size) is an Error with code kUsage naming the argument, and leaves
// the engine as it was. A GL failure is kGraphics. Nothing throws.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/bindings.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/scene_loader.h"
#include "caustix/runtime/stats.h"
#include "caustix/runtime/view.h"
#include "caustix/runtime/water_look.h"

namespace caustix::runtime {

// The water grid an application's heights must cover: columns x rows
// vertices, vertex (i, j) at x = x0 + i (x1 - x0)/(columns - 1),
// z = z0 + j (z1 - z0)/(rows - 1), stored at index j * columns + i.
struct WaterGrid {
  std::uint32_t columns = 0, rows = 0;
  float x0 = 0, z0 = 0, x1 = 0, z1 = 0;
  float level = 0;  // rest level; heights are displacements above it
};

// Per-frame input of the light side.
struct FrameUpdate {
  float time = 0.0f;         // seconds: drives the scene's waves (not the application's heights)
  CausticsOptions caustics;  // method and its knobs; Engine::default_options() is the scene's preset
  // The light side at a lower rate than the frame (docs/runtime-speed.md,
  // "Updating the light side less often"): 1 remakes whatever changed every
  // update(); N > 1 remakes each light's out-of-date products only every
  // Nth update() (light i on the updates k with (k + i) mod N = 0, so that
  // lights take turns), keeping them meanwhile: the caustics then lag
  // behind moving water, lights and objects by up to N - 1 frames. A
  // product that does not exist yet is always made. 1..64.
  std::uint32_t light_side_interval = 1;
  // What the application's camera sees (its view-projection matrix), for
  // a light side that spends its work where it is seen
  // (docs/runtime-speed.md, "Receivers out of view"): a receiver whose
  // world box lies outside this frustum keeps its caustics maps while the
  // water or the light moves, each remade on one update() in
  // out_of_view_interval (the maps taking turns, so that the cost does not
  // pulse) and as soon as it comes into view. Absent: every receiver is in
  // view. A map that does not exist yet is always made.
  std::optional<glm::mat4> camera = std::nullopt;
  std::uint32_t out_of_view_interval = 8;  // 1..64; 1: out of view costs the same
};

class Engine {
 public:
  // Uploads the scene and builds what it needs (model only what the scene
  // requires: no water passes without water, no glass passes without
  // transparent objects). `scene` need not outlive the engine.
  static Result<std::unique_ptr<Engine>> create(const RuntimeScene& scene, const Bindings& bindings = {});
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // The scene as the engine holds it (lights and transforms as last set).
  // Its images keep their sizes but not their texels, which live on the
  // GPU (albedo_map()).
  const SceneDesc& scene() const;
  const Bindings& bindings() const;
  // The options the scene's bake preset chose (RNDR chunk), else the defaults.
  CausticsOptions default_options() const;
  // The water's look with the preset's texture limit (WaterLook::max_texture_size).
  WaterLook default_water_look() const;
  // World bounds of all objects at their current transforms.
  glm::vec3 bounds_min() const;
  glm::vec3 bounds_max() const;

  // ---- light side ----
  // Moves light `index` (directional: direction of travel; point: its
  // position; the type cannot change). No GL call: the next update()
  // re-derives its level maps on the GPU (frame, position map, depth
  // profile and planes: Tipprasert 2006 §4.2, §4.7.2) and remakes its other
  // light-side products.
  Status set_light(std::uint32_t index, const Light& light);
  // Moves object `index` (rigid or similarity: its object -> world matrix,
  // column-major). No GL call: the next update() re-derives its level
  // maps and remakes what the object's place changes (every light's
  // shadow maps, glass and caustic maps, media).
  Status set_object_transform(std::uint32_t index, const Mat4f& transform);
  // Scales every wave's amplitude of the scene's wave list (1 = as baked).
  void set_wave_scale(float scale);

  // The application's water. Without water in the scene these fail
  // (kUsage). Heights are displacements above the rest level, metres, one
  // per grid vertex (water_grid()); normals follow from them by central
  // differences. Once set, update() uses them instead of the wave list
  // until use_scene_waves(); they stay as set until set again.
  std::optional<WaterGrid> water_grid() const;
  // A CPU array of columns * rows finite floats (copied).
  Status set_water_heights(std::span<const float> heights);
  // A GL buffer the application filled: columns * rows floats from byte
  // `offset` (a multiple of 4), copied on the GPU at this call (no read-back).
  Status set_water_heights_buffer(unsigned buffer, std::size_t offset = 0);
  // A GL_R32F 2D texture of columns x rows texels (texel (i, j) = vertex
  // (i, j)), copied on the GPU at this call. Non-finite values read as 0.
  Status set_water_heights_texture(unsigned texture);
  void use_scene_waves();

  // Animates the water and renders every light's shadow maps, caustics
  // maps and glass illumination textures for the current lights,
  // transforms and water. Afterwards lighting()/bind() of every pair are
  // valid until the next update(). A product is remade only when what it
  // depends on changed (its light, the transforms, the water's surface,
  // the options) or FrameUpdate::light_side_interval says it is due; a
  // still scene costs no GPU work here (stats().work). Once warmed up it
  // never waits for the GPU (stats().gl.syncs; docs/embedding.md).
  // frame.caustics is checked when it differs from the last options
  // accepted (kUsage naming the field, the engine left as it was); the
  // same options again are not checked again.
  Status update(const FrameUpdate& frame);

  // The resources of (receiver object, light) from the last update(). An
  // object that is transparent, or an index out of range, is kUsage.
  Result<ReceiverLighting> lighting(std::uint32_t object, std::uint32_t light) const;
  // Binds lighting(object, light): the block at bindings().block and the
  // twelve textures at their units. Leaves exactly these thirteen bindings
  // changed (and nothing else): the point of the call.
  Status bind(std::uint32_t object, std::uint32_t light) const;

  // Every (receiver, light) at once, for passes that light many receivers
  // from many lights in one draw (deferred lighting of a G-buffer that
  // carries an object index, clustered forward): binds the
  // all-receivers table at bindings().table and, at the twelve texture
  // units, texture arrays holding every pair's and light's textures. A
  // shader compiled with `#define CAUSTIX_ALL_RECEIVERS` before the
  // include then calls caustix_irradiance_at(position, normal, object,
  // light) or caustix_irradiance_all(position, normal, object), which give
  // what caustix_irradiance() gives after bind(object, light), read at
  // the textures' level 0. The arrays are copies, made on the GPU: the
  // first bind_all() builds them (after an update()); from then on each
  // update() copies the textures of the lights whose products it remade
  // (a still scene copies nothing; stats().work.table_*, memory in
  // stats().memory.receiver_table). Leaves exactly these thirteen
  // bindings changed. kUsage before the first update().
  Status bind_all();

  // The GLSL include for this engine's bindings (its #defines, then the
  // text of caustix.glsl). Put it after the #version line of a fragment
  // shader (it declares the block, the samplers and caustix_irradiance()).
  std::string glsl_include() const;

  // ---- view side ----
  // Into the caller's framebuffer with the caller's camera, reading its
  // scene textures; view.h is their contract: the formats they accept,
  // what each draws, reads and writes.
  Status draw_water(const View& view, const WaterLook& look, const std::function<void(const WaterPass&)>& draw_scene,
                    unsigned scene_depth = 0);
  WaterMedium water_medium(const View& view, const WaterLook& look) const;
  Status draw_glass(const View& view, unsigned scene_color, unsigned scene_depth, const glm::vec3& sky,
                    const GlassViewOptions& options = {});
  Status draw_media(const glm::mat4& view_proj, unsigned scene_color, unsigned scene_depth, float scale = 1.0f);
  bool has_media() const;

  // What the photon marching did. Its tallies come back from the GPU
  // without stalling and are a few frames old (VolumeStats::tallies_frame);
  // with `wait` they are the last update()'s (a synchronisation, counted in
  // GlCalls::syncs: for tools and tests).
  VolumeStats volume_stats(bool wait = false);

  // Draws object `index`'s mesh (attribute 0: object-space position, 1:
  // normal, 2: texture coordinates where the mesh has them -- receivers
  // whose albedo texture or maps are mapped by them; 3: linear RGBA vertex
  // colours where the mesh has them -- receivers with glTF's COLOR_0, which
  // multiply the base colour; a disabled attribute reads the context's
  // current value, so set it to (1, 1, 1, 1) with glVertexAttrib4f for
  // meshes without; GL_TRIANGLES, uint32 indices)
  // with whatever program the caller has bound: for applications that
  // draw the scene's own meshes.
  Status draw_object(std::uint32_t index) const;
  // Receiver `index`'s base-colour texture (scene.json albedo_texture,
  // glTF baseColorTexture), nullopt for an untextured object. Its
  // diffuse reflectance is material.albedo times the texture's colour at
  // caustix_texture_coords() (caustix.glsl).
  std::optional<AlbedoMap> albedo_map(std::uint32_t index) const;
  // Receiver `index`'s maps and alpha (glTF's metallic-roughness, normal,
  // occlusion and emissive textures, alpha mode), nullopt for a receiver
  // without (opaque, shaded by its factors alone).
  std::optional<SurfaceMapBindings> surface_maps(std::uint32_t index) const;

  // What the current frame did and costs: the caustics passes' counts,
  // the GL calls (GlCalls: none synchronise in a steady frame), GPU memory.
  // Counts made on the GPU come back without stalling and are a few frames
  // old (CausticsStats::counters_frame); with `wait` they are the last
  // update()'s (a synchronisation, counted in GlCalls::syncs).
  CausticsStats stats(bool wait = false);
  // GPU time per pass (GpuTimes): off until enabled (then each pass costs
  // two timestamp queries); the times are of the latest frame whose
  // queries have completed, read without waiting. With `statistics`, each
  // pass is also counted by pipeline-statistics queries (vertex, fragment
  // and compute shader invocations, primitives; GpuPassTime) where the
  // driver has ARB_pipeline_statistics_query (GpuTimes::statistics);
  // GL allows one active query per target, so with statistics on the
  // application keeps none of its own active across engine calls.
  void set_gpu_timing(bool enabled, bool statistics = false);
  GpuTimes gpu_times();
  // What the image-space caustic maps did, summed over lights; counters as
  // stats(). With `wait` also the photons' landed power and adaptive levels
  // (read back: a stall).
  CausticMapStats caustic_map_stats(bool wait = false);

 private:
  Engine();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The text of caustix.glsl as installed (default bindings, no #defines).
const char* glsl_include_source();

}  // namespace caustix::runtime
