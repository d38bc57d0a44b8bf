#pragma once
// The knobs of the water-caustics pass, switchable at run time. Every method
// produces the same thing, a caustics map per (receiver, light), so their
// images can be compared pixel for pixel.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/formats/spectrum.h"
#include "caustix/runtime/water_look.h"

namespace caustix::runtime {

enum class CausticsMethod {
  kLevelMap,    // level map with smart-sliced planes (seed 000 ch. 4, §4.7.2)
  kUniform,     // level map with the uniform planes (eq. 4-6..4-9)
  kVolumetric,  // the volumetric baseline: one slice image per plane (§5.2.1)
  kSplat,       // photon splatting (seed 001 ch. 8, GPU variant): photon texture -> points, additive
  kNone,        // no caustics: refraction and Fresnel through flat water only; glass casts a plain shadow
};

const char* to_string(CausticsMethod m);
std::optional<CausticsMethod> parse_method(const std::string& name);

// Volume caustics and single scattering in media (seed 004; docs/volume.md).
// Used only by scenes where something scatters (a medium box, water or glass
// with "scattering"); elsewhere they cost nothing.
struct VolumeOptions {
  bool enabled = true;
  // Photon marching: photons x photons per light, over the window of the
  // light that covers the media (or over the water surface for water).
  std::uint32_t photons = 256;
  // The radiance grid: voxels along the longest side of the box around
  // the media (the others in proportion); at most kMaxRadianceVoxels.
  std::uint32_t grid = 64;
  // Steps inside an object's index grid where the index varies (octree
  // level 0), in index-grid voxels; with `octree`, a photon crosses a
  // wider uniform node in one step ("Photon Marching"), else it takes this
  // step everywhere inside the grid (the uniform baseline).
  float step = 0.5f;
  bool octree = true;
  // Viewing pass: steps along the camera's rays, in radiance-grid voxels
  // (focus-grid voxels inside the focus grid).
  float view_step = 0.5f;
  // The focus grid (issue 47): voxels along each side of a second grid
  // over the box where the light through transparent objects concentrates
  // (a ball's focal line), placed per light from the glass's sampled exit
  // rays; 0 turns it off, else 2..128. Only scenes with glass in a medium
  // have one.
  std::uint32_t focus_grid = 64;
  bool operator==(const VolumeOptions&) const = default;
};
inline constexpr std::uint64_t kMaxRadianceVoxels = std::uint64_t{1} << 24;

// How light through transparent objects reaches the receivers.
enum class GlassMethod {
  // light-transport tables (seed 002 §4): baked per object. A glass whose
  // world bounding box holds a receiver's (an insect in amber) is lit by
  // caustic maps instead: the tables' rays start where light leaves the
  // glass and never reach inside (docs/glass.md).
  kTable,
  kCausticMap,  // image-space caustic maps (seed 003; Shah et al. 2007): nothing baked, any rigid object
};
const char* to_string(GlassMethod m);
std::optional<GlassMethod> parse_glass_method(const std::string& name);

// How Engine::draw_glass() finds what the camera sees through the glass
// (docs/glass.md, "The view through the glass").
enum class GlassView {
  // Seed 002 §3: per vertex, the light-transport table gives where and in
  // which direction the view ray leaves the object; the exit ray is marched
  // through the scene's depth buffer.
  kTable,
  // Nearby-geometry refraction (seed 003; Shah, Konttinen & Pattanaik 2007,
  // with Wyman 2005's back faces): per pixel, exact refraction into the
  // glass, the exit point by iterating against the glass's back faces seen
  // from the camera, exact refraction out, and the landing point by Shah's
  // iteration against the scene's depth. Nothing baked; exact on planes.
  kNearby,
};
const char* to_string(GlassView v);
std::optional<GlassView> parse_glass_view(const std::string& name);
struct GlassViewOptions {
  GlassView method = GlassView::kTable;
  std::uint32_t iterations = 10;      // nearby: landing iterations against the scene's depth (1..64)
  std::uint32_t exit_iterations = 4;  // nearby: exit-point iterations against the back faces (1..64)
  bool operator==(const GlassViewOptions&) const = default;
};

// Image-space caustic maps (seed 003, Shah, Konttinen & Pattanaik 2007;
// docs/caustic-maps.md): per light, the casters (mirrors always, glass with
// GlassMethod::kCausticMap) seen from the light give photons * photons
// photons, refracted or reflected in a compute shader, landed on the
// receivers seen from the light and splatted into a map_size^2 caustic map.
struct CausticMapOptions {
  std::uint32_t photons = 512;     // photon grid side over the casters' footprint (1..4096)
  std::uint32_t map_size = 512;    // caustic map side (16..4096)
  float splat_sigma = 1.0f;        // Gaussian splat's standard deviation, caustic-map texels (0: one texel, no filter; <= 8)
  bool two_pass = false;           // splat into one texel, then a separable Gaussian blur (Wyman's baseline) instead of one-pass splats
  std::uint32_t iterations = 10;   // landing iterations against the receivers seen from the light (the blog: ten; 1..64)
  std::uint32_t exit_iterations = 4;  // exit-point iterations against the casters' back faces (1..64)
  std::uint32_t bounces = 2;       // mirror reflections followed per photon (1..8)
  bool tir_one_sided = true;       // TIR at the exit: leave unrefracted (the blog's one-sided refraction); false drops the photon
  float edge_cos = 0.0f;           // edge testing: drop photons entering where |n . l| < edge_cos (0: off)
  float max_deviation_deg = 180.0f;  // bounded refraction deviation: drop photons turned more than this from the light (180: off)
  float max_travel = 0.0f;         // catacaustics: drop photons that travel farther than this after a mirror, metres (0: the scene's diagonal)
  // Adaptive caustic maps (Wyman & Nichols 2009): 0 traces the uniform
  // grid; n (1..8) starts from cells of 2^n x 2^n grid texels (the grid's
  // side rounded up to a multiple of 2^n) and refines only the cells that
  // cover a caster, level by level, the outline and where the casters'
  // normal turns first, until photon_budget photons.
  std::uint32_t adaptive_levels = 0;
  std::uint32_t photon_budget = 1u << 16;  // adaptive: most photons traced (>= the coarsest level's cells; <= 2^24)
  // A focus window (issue 47): where the landed photons concentrate, the
  // same photons splatted a second time into a square of half the map's
  // texels a side, placed on the GPU from this update's photons; the
  // texture then holds it above the main map (map_size x (map_size +
  // map_size / 2), with mips; docs/caustic-maps.md). false: the map alone.
  bool focus = true;
  bool operator==(const CausticMapOptions&) const = default;
};

// Shadows of the direct light (caustix.glsl's caustix_shadow_visibility)
// for the opaque objects and the glass. Point lights keep 3x3 PCF on their
// cube maps whichever filter is chosen.
enum class ShadowFilter {
  kPcf,  // 3x3 percentage-closer filtering of the depth map
  kVsm,  // variance shadow maps (Donnelly & Lauritzen 2006; seed 003): soft, filtered moments, Chebyshev's bound
};
const char* to_string(ShadowFilter f);
std::optional<ShadowFilter> parse_shadow_filter(const std::string& name);
struct ShadowOptions {
  ShadowFilter filter = ShadowFilter::kPcf;
  std::uint32_t vsm_filter = 5;  // VSM: box filter width over the moments, texels (odd, 1..63; the blog: 5)
  float vsm_bleeding = 0.2f;     // VSM light-bleeding reduction: bounds below this read as shadow, the rest rescaled ([0, 0.95])
  bool operator==(const ShadowOptions&) const = default;
};

struct CausticsOptions {
  CausticsMethod method = CausticsMethod::kLevelMap;
  std::optional<std::uint32_t> planes;  // re-slice with n pieces (uniform) / eps = h/(2n) (smart)
  std::optional<float> epsilon;         // re-slice smart planes with this eps (metres)
  std::uint32_t map_size = 512;         // caustics map S x S
  // Largest magnification of a beam's cross-section (A_w cos / A_d in
  // eq. 4-18): keeps folds where refracted rays cross finite.
  float max_magnification = 1.0e4f;
  // Beyond the thesis (§6.1): drop illumination volumes that miss the
  // frame, and draw each volume only through the planes the surface under
  // it needs. Off: every volume through every plane, as the thesis did.
  bool cull = true;
  // Photon splatting: the water is rasterised into a photons x photons
  // texture over the frame's window (plus a margin), one photon a texel.
  std::uint32_t photons = 1024;
  // Glass (seed 002 §4.2): virtual planes per target (the paper: 4; at most
  // 16) and the illumination-texture size (the paper: 512).
  std::uint32_t glass_planes = 4;
  std::uint32_t glass_map_size = 512;
  // Smooth glass caustics (issue 21; docs/glass.md): each whole
  // intersection triangle's intensity interpolated from its corners'
  // neighbourhoods (triangles within 10x of its own), scaled to keep the
  // triangle's flux, instead of eq. 3's one constant per triangle: no
  // spokes or steps from a faceted mesh (the glass ball's shadow ring:
  // ring spread 0.089 -> 0.023). false: eq. 3 as the paper has it.
  bool glass_smooth = true;
  // Focus windows (issue 47; docs/glass.md): where the light through the
  // glass lands concentrated (at least kFocusConcentration times the
  // incident irradiance, judged from the CPU sample of the tables), each
  // plane gets a second illumination texture of glass_map_size texels over
  // a square fitted to that region, and the shading reads it there. Off:
  // one texture per plane over the whole target, as the paper.
  bool glass_focus = true;
  // In a focus window, the triangles at least this many of its texels high
  // across their longest edge are drawn by a second program that covers
  // the texels along one edge in closed form instead of clipping them
  // (docs/glass.md, "The window's wide primitives"): the same light (0.05 %
  // of glass_ball's focus image) for less of the window's cost with the
  // light moving (glass_teapot +50 % -> +24 % on llvmpipe). 0 (or not
  // finite): every triangle clipped.
  float glass_focus_wide = 4.0f;
  // Where glass disperses, a focus window is drawn once per traced
  // wavelength; true: at half its texels a side, into a square beside it,
  // and interpolated into its own (docs/glass.md, "A window per
  // wavelength"). On the dispersive ball (llvmpipe, the light turning) the
  // frame costs +22.6 % of the frame without a window instead of +26.2 %;
  // its F, d, C lines within 1 cm read -1.4, -4.7, -3.5 % of optics
  // instead of -0.8, -3.1, -2.1 %, its d line's brightest 2 mm -45 %
  // instead of -25 %. A monochromatic image (wavelength_nm) is drawn alike,
  // so that it is what the RGB image sums; one wavelength (the d line
  // alone) is the glass without dispersion, at the window's own texels.
  // The bake preset's (RenderDefaults::glass_spectral_coarse; accurate:
  // false).
  bool glass_focus_spectral_coarse = true;
  // Water caustics: each intersection triangle's irradiance interpolated
  // from its corners' (estimated from the water grid around each vertex by
  // central differences) and scaled to keep eq. 4-18's flux, instead of one
  // constant per water triangle: no mosaic of the water grid beating
  // against the pixels (moire in caustic lines; issue 21). Triangles at
  // folds (corners beyond 10x the triangle's) keep the constant. false:
  // seed 000's eq. 4-18 as written.
  bool water_smooth = true;
  VolumeOptions volume;
  GlassMethod glass_method = GlassMethod::kTable;
  CausticMapOptions caustic_map;
  ShadowOptions shadows;
  // Dispersion (issue 22; docs/dispersion.md). In a scene with dispersion
  // the image-space caustic maps trace this many wavelengths (1..32), each
  // at the centre of an equal bin of 380-780 nm and added into RGB with the
  // bin's CIE-to-linear-sRGB weights; 1 traces the d line only (every index
  // n_d: no fringes, the cost of a scene without dispersion). A scene
  // without dispersion traces one whatever this says. The level-map water
  // family (level map, uniform, volumetric, splat) traces as many when the
  // water disperses, into the caustics map and an RGB colour texture
  // (Bindings::caustics_color); the media's photon march traces as many in
  // any scene with dispersion; glass light-transport tables as many when
  // dispersive glass was baked with tables at other wavelengths
  // (caustix-bake --ltt-wavelengths), each wavelength between the two
  // tables that bracket its index. Flat water traces the d line (n_d)
  // unless wavelength_nm is set. The views refract as many: the water
  // surface (Engine::draw_water) and glass through the nearby view
  // (draw_glass, GlassView::kNearby).
  std::uint32_t wavelengths = 8;
  // A monochromatic image: every index at this wavelength (nm, 380..780)
  // and the light's own colour (caustix-render --wavelength): the caustic
  // maps, the water's passes and the glass tables refract at
  // n(wavelength_nm). Engine::update refuses it for a dispersive glass
  // object lit by its light-transport table when the file has its table at
  // n_d only (baked with --ltt-wavelengths 0): use GlassMethod::kCausticMap.
  std::optional<float> wavelength_nm;
  bool operator==(const CausticsOptions&) const = default;
};

// The wavelengths the caustic maps trace for `scene` under `options`
// (above): one with weight (1, 1, 1) at wavelength_nm when set, one at the
// d line in a scene without dispersion, else options.wavelengths bins.
std::vector<WavelengthSample> traced_wavelengths(const SceneDesc& scene, const CausticsOptions& options);
// The wavelengths the water-caustics passes trace: as traced_wavelengths,
// but several only when the water itself disperses.
std::vector<WavelengthSample> water_wavelengths(const Water& water, const CausticsOptions& options);
// The water's index for the passes that trace one wavelength: at
// options.wavelength_nm when set, else its `ior` (n_d).
float water_index(const Water& water, const CausticsOptions& options);
// Checks the two fields above; a usage error names the field.
Status check_wavelengths(const SceneDesc& scene, const CausticsOptions& options);

// Sets the fields a bake preset records (RNDR chunk): map sizes, glass planes.
void apply_render_defaults(CausticsOptions& options, const RenderDefaults& render);
// The options a renderer starts from for this scene: the built-in defaults
// above, or the runtime defaults a bake preset recorded.
CausticsOptions default_caustics_options(const SceneDesc& scene);
// The water's look a renderer starts from: WaterLook's defaults with the
// preset's texture limit (RenderDefaults::water_texture).
WaterLook default_water_look(const SceneDesc& scene);

// The OpenGL calls the engine made in one frame (issue 44): those of the
// set_* calls before an update(), of update() itself and of every call
// after it (bind, draw_*, stats, ...) up to the next update(). Counted by
// the runtime's own layer around its GL calls (docs/runtime-speed.md);
// the application's own calls are not in them.
struct GlCalls {
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
// lists them.
struct GpuPassTime {
  std::string name;
  bool compute = false;    // a compute pass (else rasterisation)
  double ms = 0;
  std::uint32_t count = 0;  // how many passes of this name the frame ran
};
struct GpuTimes {
  std::uint64_t frame = 0;  // the update() count of the frame measured; 0: none yet
  std::vector<GpuPassTime> passes;
  double compute_ms = 0, raster_ms = 0;
};

// Bytes the engine holds on the GPU, by effect (textures at their mip
// chains, buffers at their allocated size).
struct GpuMemory {
  std::uint64_t meshes = 0;        // the scene's vertex and index buffers and albedo textures
  std::uint64_t shadow_maps = 0;   // depth maps, their moments (VSM)
  std::uint64_t water = 0;         // the surface's buffers
  std::uint64_t level_maps = 0;    // position and caustics maps, lists, slices (seed 000, 001 ch. 8)
  std::uint64_t glass = 0;         // transport tables, rays, targets, illumination textures (seed 002)
  std::uint64_t caustic_maps = 0;  // caster and caustic maps, photons (seed 003)
  std::uint64_t media = 0;         // radiance and index grids (seed 004)
  std::uint64_t views = 0;         // the view side: water textures and glow, copies of the caller's scene
  std::uint64_t other = 0;         // light blocks, read-back rings
  std::uint64_t receiver_table = 0;  // Engine::bind_all()'s table and texture arrays (0 until its first call)
  std::uint64_t total() const {
    return meshes + shadow_maps + water + level_maps + glass + caustic_maps + media + views + other + receiver_table;
  }
};

// What the last frame's caustics pass did, per level map (for benchmarks).
struct CausticsStats {
  std::uint64_t frame = 0;            // update() calls so far
  std::uint64_t water_triangles = 0;  // per light
  // Counted on the GPU and read back without stalling (issue 44): these
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
  // The GL calls of the current frame so far (see GlCalls).
  GlCalls gl;
  // What the current frame's update() recomputed and what it reused
  // (issue 44): each light-side product is remade only when what it was
  // made from changed (its light, the objects' transforms, the water's
  // surface, the options), or kept by FrameUpdate::light_side_interval.
  FrameWork work;
  // GPU memory by effect; gpu_bytes is their sum.
  GpuMemory memory;
};

// What the last update()'s caustic maps did (issue 20), summed over lights.
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

// What the photon marching did (seed 004), summed over lights. Energies
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
  std::uint64_t glass_photons = 0;     // of which over the glass's own window (focus grids, issue 47)
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
  // The focus grids (issue 47), per light: the world box (x0, y0, z0, x1,
  // y1, z1) each light's concentrated light got, empty where it has none.
  std::vector<std::array<float, 6>> focus_boxes;
  std::uint64_t grid_bytes = 0;        // radiance grids (accumulator and textures) and index grids on the GPU
  double march_ms = 0, resolve_ms = 0; // GPU time of the last update's photon pass and grid resolve (timer queries)
};

}  // namespace caustix::runtime
