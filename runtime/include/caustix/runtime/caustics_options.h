#pragma once
// The knobs of the light side, switchable at run time (what an application
// passes in; what a frame did and cost is stats.h). Every water method
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
  kLevelMap,    // level map with smart-sliced planes (Tipprasert 2006 ch. 4, §4.7.2)
  kUniform,     // level map with the uniform planes (eq. 4-6..4-9)
  kVolumetric,  // the volumetric baseline: one slice image per plane (§5.2.1)
  kSplat,       // photon splatting (Mihalik 2008 ch. 8, GPU variant): photon texture -> points, additive
  kNone,        // no caustics: refraction and Fresnel through flat water only; glass casts a plain shadow
};

const char* to_string(CausticsMethod m);

// How the level maps of a light are drawn (CausticsOptions::map_batching;
// docs/caustics.md, "batches"). The maps of one light and one size always
// share a texture array, a map to a layer (each map's texture is a view of
// its layer). In a batch, one cull, one geometry pass and one draw serve
// them all, choosing each map's layer in the vertex shader
// (GL_ARB_shader_viewport_layer_array); without it, with a water that
// disperses, and for the volumetric and splatting methods, maps are drawn
// one by one. The maps agree to the rounding of the order beams are added
// in.
enum class MapBatching {
  // Batches of at least 8 maps drawn in an update, on a GPU; a software
  // rasteriser (llvmpipe) renders a layered target several times slower
  // per fragment and draws them one by one (docs/runtime-speed.md, "A
  // fixed number of calls").
  kAuto,
  kAlways,  // every batch, whatever its size and the renderer
  kNever,   // one set of calls per map
};
std::optional<CausticsMethod> parse_method(const std::string& name);

// Volume caustics and single scattering in media (Pfeuti; docs/volume.md).
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
  // How a ray crosses an object's surface in its index grid: false follows
  // the seed's curved path through the blurred index (x += (ds / n) v,
  // v += ds grad n), true goes straight on either side and refracts by
  // Snell's law, with Fresnel, where the coverage crosses 1/2
  // (docs/volume.md, "Photon marching").
  bool surface_refraction = true;
  // Viewing pass: steps along the camera's rays, in radiance-grid voxels
  // (focus-grid voxels inside the focus grid).
  float view_step = 0.5f;
  // The focus grid: voxels along each side of a second grid
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
  // light-transport tables (Iwasaki et al. §4): baked per object. A glass whose
  // world bounding box holds a receiver's (an insect in amber) is lit by
  // caustic maps instead: the tables' rays start where light leaves the
  // glass and never reach inside (docs/glass.md).
  kTable,
  kCausticMap,  // image-space caustic maps (timofy 2009; Shah et al. 2007): nothing baked, any rigid object
};
const char* to_string(GlassMethod m);
std::optional<GlassMethod> parse_glass_method(const std::string& name);

// How Engine::draw_glass() finds what the camera sees through the glass
// (docs/glass.md, "The view through the glass").
enum class GlassView {
  // Iwasaki et al. §3: per vertex, the light-transport table gives where and in
  // which direction the view ray leaves the object; the exit ray is marched
  // through the scene's depth buffer.
  kTable,
  // Nearby-geometry refraction (timofy 2009; Shah, Konttinen & Pattanaik 2007,
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
  // What the view through glass, and its reflection, see where their rays
  // leave the scene: the name of the application's GL_TEXTURE_CUBE_MAP (its
  // sky or environment, linear colour, sampled with the texture's own
  // filtering; Engine::draw_glass binds it at texture unit 4 and puts the
  // unit back), so that the glass shows the sky the application draws
  // behind it. 0: draw_glass's flat `sky` colour (seen by reflection,
  // brighter upward).
  unsigned environment = 0;
  bool operator==(const GlassViewOptions&) const = default;
};

// Image-space caustic maps (timofy 2009, Shah, Konttinen & Pattanaik 2007;
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
  // A focus window: where the landed photons concentrate, the
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
  kVsm,  // variance shadow maps (Donnelly & Lauritzen 2006; timofy 2009): soft, filtered moments, Chebyshev's bound
};
const char* to_string(ShadowFilter f);
std::optional<ShadowFilter> parse_shadow_filter(const std::string& name);
struct ShadowOptions {
  ShadowFilter filter = ShadowFilter::kPcf;
  std::uint32_t vsm_filter = 5;  // VSM: box filter width over the moments, texels (odd, 1..63; the blog: 5)
  float vsm_bleeding = 0.2f;     // VSM light-bleeding reduction: bounds below this read as shadow, the rest rescaled ([0, 0.95])
  bool operator==(const ShadowOptions&) const = default;
};

// The smallest map the budget coarsens a receiver's to (a map_size below
// it is kept as asked).
inline constexpr std::uint32_t kMinCausticsMapSize = 16;

struct CausticsOptions {
  CausticsMethod method = CausticsMethod::kLevelMap;
  std::optional<std::uint32_t> planes;  // re-slice with n pieces (uniform) / eps = h/(2n) (smart)
  std::optional<float> epsilon;         // re-slice smart planes with this eps (metres)
  // Texels by need (docs/caustics.md, "Texels by need and the memory
  // budget"): a light's caustics maps share one texel size in metres,
  // each map a square over its receiver's frame. With texel_size set
  // (> 0) every map takes the side its frame needs at it (up to
  // kMaxRuntimeMapSize). Else the texel is the light's largest lit extent
  // (the part of a receiver's frame the water's light can reach) over
  // map_size, and every map keeps map_size a side, or four times what its
  // frame needs at that texel where that is less, unless the budget below
  // needs texels: then small receivers give theirs up first, down to
  // what their frame needs. A receiver the water's light cannot reach
  // gets no map.
  std::uint32_t map_size = 512;
  float texel_size = 0.0f;              // metres; 0: from map_size as above
  // GPU memory the light side may hold (every effect's textures and
  // buffers but the scene's meshes, the view side and bind_all()'s
  // table; GpuMemory::light_side()): where the maps as above would not
  // fit, small receivers first give up the texels they hold beyond their
  // need (their frame at the texel above), then every texel coarsens by
  // steps of 2^(1/4) until they fit, each receiver keeping a map (at
  // least kMinCausticsMapSize a side). Where the rest of the light side
  // alone is over it (position maps, shadow maps), coarsening could not
  // help: the maps stay at their need and stats().texels.over_budget says
  // so. stats().texels says what was chosen; stats().warnings says it
  // once. 0: no budget. The bake preset's: 64 MiB at fast, 128 MiB at
  // balanced (and without a preset), 256 MiB at accurate.
  std::uint64_t memory_budget = std::uint64_t{128} << 20;
  // Largest magnification of a beam's cross-section (A_w cos / A_d in
  // eq. 4-18): keeps folds where refracted rays cross finite.
  float max_magnification = 1.0e4f;
  // Beyond the thesis (§6.1): drop illumination volumes that miss the
  // frame, and draw each volume only through the planes the surface under
  // it needs. Off: every volume through every plane, as the thesis did.
  bool cull = true;
  // Beyond the thesis: the level maps of a light (kLevelMap, kUniform) in
  // batches, a fixed number of calls whatever the number of receivers
  // (MapBatching).
  MapBatching map_batching = MapBatching::kAuto;
  // Photon splatting: the water is rasterised into a photons x photons
  // texture over the frame's window (plus a margin), one photon a texel.
  std::uint32_t photons = 1024;
  // Glass (Iwasaki et al. §4.2): virtual planes per target (the paper: 4; at most
  // 16) and the illumination-texture size (the paper: 512).
  std::uint32_t glass_planes = 4;
  std::uint32_t glass_map_size = 512;
  // Smooth glass caustics (docs/glass.md): each whole
  // intersection triangle's intensity interpolated from its corners'
  // neighbourhoods (triangles within 10x of its own), scaled to keep the
  // triangle's flux, instead of eq. 3's one constant per triangle: no
  // spokes or steps from a faceted mesh (the glass ball's shadow ring).
  // false: eq. 3 as the paper has it.
  bool glass_smooth = true;
  // Focus windows (docs/glass-focus.md): where the light through the
  // glass lands concentrated (at least kFocusConcentration times the
  // incident irradiance, judged from the CPU sample of the tables), each
  // plane gets a second illumination texture of glass_map_size texels over
  // a square fitted to that region, and the shading reads it there. Off:
  // one texture per plane over the whole target, as the paper.
  bool glass_focus = true;
  // In a focus window, the triangles at least this many of its texels high
  // across their longest edge are drawn by a second program that covers
  // the texels along one edge in closed form instead of clipping them
  // (docs/glass-focus.md, "The window's wide primitives"): the same light
  // for less of the window's cost with the light moving. 0 (or not
  // finite): every triangle clipped.
  float glass_focus_wide = 4.0f;
  // In a focus window, each texel takes the light of the triangles' parts
  // within one texel of its centre, weighted by the tent
  // (1 - |dx|)(1 - |dy|); false: the light inside it (the box). By the box
  // a focus narrower than a texel jumps from texel to texel as it moves;
  // by the tent it moves between them continuously (docs/temporal.md,
  // "The glass tables' tent": with the sun turning 0.05 deg a frame,
  // glass_ball's rho ratio 0.83 -> 0.60 at balanced). The tent spreads
  // the spot by a texel more, so the window has 0.65 of the texture's
  // texels a side (docs/glass-focus.md), where the box had half:
  // glass_ball's brightest 2 mm pixel against optics -17.8 % by the box
  // then, -17.4 % by the tent now. The closed-form wide triangles
  // (glass_focus_wide) and the main textures keep the box.
  bool glass_focus_tent = true;
  // Where glass disperses, a focus window is drawn once per traced
  // wavelength; true: at half its texels a side, into a square beside it,
  // and interpolated into its own (docs/glass-focus.md, "A window per
  // wavelength", which measures what it saves and what the focus loses).
  // A monochromatic image (wavelength_nm) is drawn alike,
  // so that it is what the RGB image sums; one wavelength (the d line
  // alone) is the glass without dispersion, at the window's own texels.
  // The bake preset's (RenderDefaults::glass_spectral_coarse; accurate:
  // false).
  bool glass_focus_spectral_coarse = true;
  // Water caustics: each intersection triangle's irradiance interpolated
  // from its corners' (estimated from the water grid around each vertex by
  // central differences) and scaled to keep eq. 4-18's flux, instead of one
  // constant per water triangle: no mosaic of the water grid beating
  // against the pixels (moire in caustic lines). Triangles at
  // folds (corners beyond 10x the triangle's) keep the constant. false:
  // Tipprasert 2006's eq. 4-18 as written.
  bool water_smooth = true;
  VolumeOptions volume;
  GlassMethod glass_method = GlassMethod::kTable;
  CausticMapOptions caustic_map;
  ShadowOptions shadows;
  // Dispersion (docs/dispersion.md). In a scene with dispersion
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

}  // namespace caustix::runtime
