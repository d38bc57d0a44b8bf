#pragma once
// What a frame did and cost, as Engine::stats(), gpu_times(),
// caustic_map_stats() and volume_stats() report it: GL calls and
// synchronisations, products remade and kept, GPU time per pass, GPU
// memory per effect, and each method's own counts. Options are
// caustics_options.h.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace caustix::runtime {

// The OpenGL calls the engine made in one frame: those of the
// set_* calls before an update(), of update() itself and of every call
// after it (bind, draw_*, stats, ...) up to the next update(). Counted by
// the runtime's own layer around its GL calls (docs/runtime-speed.md),
// which a build has only with the CMake option CAUSTIX_COUNT_GL_CALLS;
// the application's own calls are not in them.
struct GlCalls {
  bool counted = false;          // false: built without the counter, every count 0
  std::uint64_t calls = 0;       // every GL call
  std::uint64_t draws = 0;       // glDraw* / glMultiDraw* (clears are not draws)
  std::uint64_t dispatches = 0;  // glDispatchCompute*
  // GPU -> CPU synchronisations: read-backs of buffers, textures or query
  // results into client memory, glFinish, fence waits. Each waits for the
  // GPU to catch up with the CPU; a warmed-up frame has none.
  std::uint64_t syncs = 0;
  std::uint64_t upload_bytes = 0;  // CPU -> GPU buffer uploads (glBufferSubData)
};

// How many of one light-side product a frame remade and how many it kept.
struct EffectWork {
  std::uint32_t updated = 0;   // remade this frame
  std::uint32_t reused = 0;    // still valid: nothing it depends on changed
  std::uint32_t deferred = 0;  // out of date but kept (FrameUpdate::light_side_interval)
};
struct FrameWork {
  bool water = false;          // the water's surface moved (waves in time, new heights)
  EffectWork shadow_maps;      // per light
  EffectWork level_maps;       // per light: its caustics maps (level map, uniform, volumetric, splat)
  EffectWork glass;            // per light: the glass illumination textures of every receiver
  EffectWork caustic_maps;     // per light
  EffectWork media;            // per light: the radiance grid
  std::uint32_t blocks_uploaded = 0;  // (receiver, light) uniform blocks re-uploaded (changed)
  // The all-receivers table (Engine::bind_all(); 0 until its first call):
  // textures copied into its arrays, and their bytes.
  std::uint32_t table_copies = 0;
  std::uint64_t table_copied_bytes = 0;
};

// GPU time of the engine's passes in one frame (timer queries read without
// waiting: a frame or more old), each named ("level maps: cull", "glass:
// illumination", "water: surface"...) and labelled compute or raster;
// passes of one name (per light, per map) are summed. docs/runtime-speed.md
// lists them. With statistics (Engine::set_gpu_timing) each pass also has
// the pipeline's counts (ARB_pipeline_statistics_query): the work itself,
// the same on llvmpipe as on a GPU.
struct GpuPassTime {
  std::string name;
  bool compute = false;    // a compute pass (else rasterisation)
  double ms = 0;
  std::uint32_t count = 0;  // how many passes of this name the frame ran
  std::uint64_t vertex_invocations = 0;    // vertex-shader invocations
  std::uint64_t primitives = 0;            // primitives submitted (points, lines, triangles)
  std::uint64_t fragment_invocations = 0;  // fragment-shader invocations
  std::uint64_t compute_invocations = 0;   // compute-shader invocations
};
struct GpuTimes {
  std::uint64_t frame = 0;  // the update() count of the frame measured; 0: none yet
  std::vector<GpuPassTime> passes;
  double compute_ms = 0, raster_ms = 0;
  bool statistics = false;  // the passes' pipeline counts were measured
};

// Bytes the engine holds on the GPU, by effect (textures at their mip
// chains, buffers at their allocated size).
struct GpuMemory {
  std::uint64_t meshes = 0;        // the scene's vertex and index buffers and albedo textures
  std::uint64_t shadow_maps = 0;   // depth maps, their moments (VSM)
  std::uint64_t water = 0;         // the surface's buffers
  std::uint64_t level_maps = 0;    // position and caustics maps, lists, slices (Tipprasert 2006, 001 ch. 8)
  std::uint64_t glass = 0;         // transport tables, rays, targets, illumination textures (Iwasaki et al.)
  std::uint64_t caustic_maps = 0;  // caster and caustic maps, photons (timofy 2009)
  std::uint64_t media = 0;         // radiance and index grids (Pfeuti)
  std::uint64_t views = 0;         // the view side: water textures and glow, copies of the caller's scene
  std::uint64_t other = 0;         // light blocks, read-back rings
  std::uint64_t receiver_table = 0;  // Engine::bind_all()'s table and texture arrays (0 until its first call)
  // What CausticsOptions::memory_budget holds: all but the meshes, the
  // view side and the table.
  std::uint64_t light_side() const { return shadow_maps + water + level_maps + glass + caustic_maps + media + other; }
  std::uint64_t total() const {
    return meshes + shadow_maps + water + level_maps + glass + caustic_maps + media + views + other + receiver_table;
  }
};

// The caustics maps' texels by need and the memory budget
// (CausticsOptions::texel_size, memory_budget; docs/caustics.md).
struct CausticsTexels {
  float texel = 0.0f;              // metres: the finest texel a light's maps use now (0: no maps)
  float coarsened = 1.0f;          // the budget's factor on every light's texel (1: none)
  // The least side a map keeps (map_size with the texel from map_size),
  // as the budget lowered it towards the receivers' own need (0: no
  // longer a floor).
  std::uint32_t least_side = 0;
  std::uint32_t maps = 0;          // caustics maps held
  std::uint32_t unreachable = 0;   // (receiver, light) maps the water's light cannot reach now: no texels
  std::uint64_t map_bytes = 0;     // the caustics maps' textures (and their mips, colour, slices)
  std::uint64_t budget = 0;        // memory_budget (0: none)
  std::uint64_t light_side = 0;    // the light side's memory as planned, with room for the pair lists to grow
  bool over_budget = false;        // the light side is over the budget without its caustics maps: they stay at their need
};

// What the last frame's caustics pass did, per level map (for benchmarks).
struct CausticsStats {
  std::uint64_t frame = 0;            // update() calls so far
  std::uint64_t water_triangles = 0;  // per light
  // Counted on the GPU and read back without stalling: these
  // three are of frame `counters_frame` (the update() count; 0 before any
  // has arrived), a few frames before the current one, or of the current
  // one when Engine::stats() is asked to wait.
  std::uint64_t counters_frame = 0;
  std::uint64_t volumes_drawn = 0;    // primitives drawn: (volume, plane) pairs, or volumes when not culling
  bool overflowed = false;            // a map's pair list was full: it drew the pieces that fitted (the list grows)
  std::uint64_t planes_drawn = 0;     // summed over maps
  std::uint64_t volumes_total = 0;    // before culling, summed over maps
  std::uint64_t gpu_bytes = 0;        // everything the engine holds on the GPU (memory below, by effect)
  // Wavelengths the water passes traced (several only when the water
  // disperses). The counters above are one wavelength's pass: the passes
  // ran this many times over the same volumes and planes.
  std::uint32_t wavelengths = 1;
  // Wavelengths the glass light-transport tables traced (several only for
  // dispersive glass baked with tables at other wavelengths).
  std::uint32_t glass_wavelengths = 1;
  // Caustics maps the last update() kept, not remade, because their
  // receiver was out of the camera's view (FrameUpdate::camera), summed
  // over lights.
  std::uint32_t maps_out_of_view = 0;
  // The GL calls of the current frame so far (see GlCalls).
  GlCalls gl;
  // What the current frame's update() recomputed and what it reused:
  // each light-side product is remade only when what it was
  // made from changed (its light, the objects' transforms, the water's
  // surface, the options), or kept by FrameUpdate::light_side_interval.
  FrameWork work;
  // GPU memory by effect; gpu_bytes is their sum.
  GpuMemory memory;
  CausticsTexels texels;
  // What the engine warns of, each once, since the previous stats() call
  // (a budget that coarsens the texels, with the figures).
  std::vector<std::string> warnings;
};

// What the last update()'s caustic maps did, summed over lights.
struct CausticMapStats {
  bool active = false;                // some light had casters
  // The counters below are of frame `counters_frame` (update() calls),
  // read back without stalling a few frames late, or of the last frame
  // when Engine::caustic_map_stats() waits.
  std::uint64_t counters_frame = 0;
  std::uint64_t photons = 0;          // emitted (grid texels covered by a caster)
  std::uint64_t landed = 0;           // splatted onto a receiver
  std::uint64_t reflections = 0;      // mirror reflections
  std::uint64_t tir = 0;              // total internal reflections left unrefracted (one-sided refraction)
  std::uint64_t tir_dropped = 0;      // ... or dropped (tir_one_sided false)
  std::uint64_t edge_dropped = 0;     // edge testing
  std::uint64_t deviation_dropped = 0;  // bounded refraction deviation
  std::uint64_t too_far = 0;          // travelled farther than max_travel after a mirror
  std::uint64_t lost = 0;             // no receiver seen from the light where they land
  std::uint64_t out_of_bounces = 0;   // met a mirror after the last reflection allowed (ended there)
  double landed_power = 0;            // sum of the landed photons' luminance flux, W (only when waiting)
  // Adaptive: photons traced per traversal level (0: one grid texel; level
  // k: a cell of 4^k texels), only when waiting.
  std::array<std::uint64_t, 9> photons_per_level{};
  // GPU time of the last light's passes (timer queries: the latest ready,
  // or the last frame's when waiting); photons and splats summed over the
  // traced wavelengths.
  double capture_ms = 0, photon_ms = 0, splat_ms = 0;
  std::uint64_t gpu_bytes = 0;
  // Wavelengths traced (dispersion). The counters above sum over them;
  // landed_power is the last wavelength's (its photons carry its bin's
  // weights), so it is the whole landed power only when this is 1.
  std::uint32_t wavelengths = 1;
  // The focus window of the last light with a caustic map (CausticMapOptions::focus):
  // centre s, t and half-size in the main map's texture coordinates (0: none).
  // Only when waiting (it is placed on the GPU).
  std::array<float, 3> focus{0, 0, 0};
};

// What the photon marching did (Pfeuti), summed over lights. Energies
// are luminance-weighted photon power divided by E0 (the first directional
// light's irradiance, else 1), m^2. in = scattered + absorbed + leaving +
// reflected + truncated up to the fixed-point rounding of the GPU's
// integer atomics.
struct VolumeStats {
  bool active = false;                 // the scene has media and the effect ran
  // The tallies below are of frame `tallies_frame` (update() calls), read
  // back without stalling a few frames late, or of the last frame when
  // Engine::volume_stats() waits.
  std::uint64_t tallies_frame = 0;
  std::uint64_t photons = 0;           // emitted
  std::uint64_t glass_photons = 0;     // of which over the glass's own square across the light (focus grids)
  std::uint64_t steps = 0;             // marching steps (curved steps in index grids + straight runs)
  std::uint64_t grid_steps = 0;        // of which inside index grids
  double power_in = 0;                 // entered a medium
  double scattered = 0;                // lost to scattering: the single-scattering source
  double absorbed = 0;
  double leaving = 0;                  // left the media (out of the box, into clear glass or air, onto a surface)
  double reflected = 0;                // Fresnel reflection at glass boundaries (not followed)
  double truncated = 0;                // still carried when the step limit ended the march
  double deposited = 0;                // the radiance grid's sum of scattered power (read back), = scattered
  std::array<std::uint32_t, 3> grid_size{0, 0, 0};
  // The focus grids, per light: the world box (x0, y0, z0, x1,
  // y1, z1) each light's concentrated light got, empty where it has none.
  std::vector<std::array<float, 6>> focus_boxes;
  std::uint64_t grid_bytes = 0;        // radiance grids (accumulator and textures) and index grids on the GPU
  double march_ms = 0, resolve_ms = 0; // GPU time of the last update's photon pass and grid resolve (timer queries)
};

}  // namespace caustix::runtime
