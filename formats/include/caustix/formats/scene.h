#pragma once
// The scene description as it travels from scene.json through the .cxb to
// the runtime: objects (with material, role, transform and mesh metadata),
// lights, water and the default camera. Units are metres, world space is
// right-handed with +y up, colours are linear RGB (docs/architecture.md).
//
// encode_scene() turns a SceneDesc plus one Draco stream per mesh into a
// .cxb; decode_scene() is its inverse over a validated Container and is as
// safe on hostile bytes as read_container(): every count, index, enum and
// float is checked, and an error names the chunk, the byte offset in its
// payload and the field.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/container.h"
#include "caustix/formats/index_grid.h"
#include "caustix/formats/level_map.h"
#include "caustix/formats/light_transport.h"
#include "caustix/formats/types.h"

namespace caustix {

// On-disk enums: never renumber.
// kMirror: a two-sided specular reflector (any mesh, open ones
// too); it casts shadows, reflects material.reflectance of the light that
// reaches it and is lit by the image-space caustic maps (timofy 2009), not a
// receiver of caustics itself.
// kThin: a thin-walled transparent surface (glTF's
// KHR_materials_transmission without KHR_materials_volume: a window pane, a
// lamp shade, a bulb), open or closed. Light crosses each sheet where it
// meets it, without bending: Fresnel in and out at the same point, the
// light bouncing between its faces summed, so a sheet transmits
// tint (1 - r) / (1 + r) and reflects 2 r / (1 + r) for a face's Fresnel
// reflectance r (docs/glass.md). It has no light-transport table or index
// grid; the caustic maps carry its light whatever the glass method.
enum class Role : std::uint8_t { kReceiver = 1, kTransparent = 2, kBoth = 3, kMirror = 4, kThin = 5 };
enum class LightType : std::uint8_t { kDirectional = 1, kPoint = 2 };
enum class Phase : std::uint8_t { kIsotropic = 1, kSchlick = 2 };

inline bool is_receiver(Role r) { return r == Role::kReceiver || r == Role::kBoth; }
inline bool is_transparent(Role r) { return r == Role::kTransparent || r == Role::kBoth; }
inline bool is_mirror(Role r) { return r == Role::kMirror; }
inline bool is_thin(Role r) { return r == Role::kThin; }
// Light passes through it: solid or thin-walled glass.
inline bool transmits(Role r) { return is_transparent(r) || is_thin(r); }
// Objects whose light the image-space caustic maps carry (timofy 2009).
inline bool is_caster(Role r) { return transmits(r) || is_mirror(r); }


// Single scattering in a participating medium (Pfeuti, "Viewing Pass"):
// scattering coefficient sigma_s and the phase function, isotropic 1/(4 pi)
// or Schlick's (1/(4 pi)) (1 - k^2) / (1 - k cos a)^2 with a the angle
// between the light's direction of travel and the scattered direction
// (k > 0 scatters forward). The extinction is sigma_t = sigma_s + sigma_a,
// sigma_a being the absorption of whatever holds the scattering.
struct Scattering {
  Vec3f coefficient{0, 0, 0};      // sigma_s, 1/m per RGB channel, >= 0
  Phase phase = Phase::kIsotropic;
  float anisotropy = 0.0f;         // Schlick's k, in (-1, 1); 0 for isotropic
  bool scatters() const { return coefficient[0] > 0 || coefficient[1] > 0 || coefficient[2] > 0; }
};

// A base-colour texture on a receiver (the TEXR chunk): the
// diffuse reflectance is albedo times the texture's linear colour. Where
// the texture is looked up:
//  kUv   the mesh's texture coordinates (glTF TEXCOORD_0; (0, 0) is the
//        image's top-left texel);
//  kBox  world-space metres on the axis plane the surface faces most (box or
//        triplanar projection: a face whose normal is mostly x takes (z, y),
//        mostly y (x, z), mostly z (x, y)) -- tiles of a given size in metres
//        across every wall, for meshes without texture coordinates.
// The coordinates then go through `transform`, row-major 2 x 3:
// (s, t) = (m0 u + m1 v + m2, m3 u + m4 v + m5) (KHR_texture_transform's
// offset, rotation and scale; for kBox, repeats per metre).
enum class TextureProjection : std::uint8_t { kUv = 1, kBox = 2 };
enum class TextureWrap : std::uint8_t { kRepeat = 1, kClamp = 2, kMirror = 3 };  // glTF sampler wrapS / wrapT
struct AlbedoTexture {
  std::uint32_t image = 0;  // index into SceneDesc::images
  TextureProjection projection = TextureProjection::kUv;
  TextureWrap wrap_s = TextureWrap::kRepeat;
  TextureWrap wrap_t = TextureWrap::kRepeat;
  std::array<float, 6> transform{1, 0, 0, 0, 1, 0};
};

// KHR_texture_transform's T * R * S (offset, rotation in radians, scale) as
// AlbedoTexture::transform; the rotation turns UVs counter-clockwise, as
// the Khronos sample viewer applies it (rows (c, s) and (-s, c)).
inline std::array<float, 6> texture_transform(const std::array<float, 2>& offset, float rotation, const std::array<float, 2>& scale) {
  const float c = std::cos(rotation), s = std::sin(rotation);
  return {c * scale[0], s * scale[1], offset[0], -s * scale[0], c * scale[1], offset[1]};
}

// An image as the .cxb stores it: 8-bit sRGB-encoded RGB, top row first
// (the baker reads files through OpenImageIO and drops alpha).
inline constexpr std::uint32_t kMaxTextureSize = 8192;
struct TextureImage {
  std::string source;  // the file or glTF image it came from, for messages
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3
  // Empty: opaque. Else width * height bytes, the image's alpha (linear,
  // top row first), kept where a material masks or blends with its base
  // colour's alpha (SurfaceMaps::alpha_mode; the TEXM chunk).
  std::vector<std::uint8_t> alpha;
};

// A receiver's surface beyond Lambert's, as glTF's metallic-roughness
// model has it (the SURF chunk). It changes only how a renderer shades the
// receiver (the sample renderer: docs/display.md, "Surfaces"); the light
// the engine computes for it is the same.
struct Surface {
  float metallic = 0.0f;   // [0, 1]: 1 a metal, whose albedo is its specular colour
  float roughness = 1.0f;  // [0, 1]: GGX's alpha is roughness^2
  // Emitted light, linear RGB, each in [0, 1e6], relative to the scene's
  // light: a surface emitting (1, 1, 1) is drawn as bright as a white
  // diffuse surface under the scene's reference irradiance (its first
  // sun's E0; docs/display.md), as glTF viewers draw emissiveFactor 1.
  Vec3f emissive{0, 0, 0};
  bool operator==(const Surface&) const = default;
};

// glTF 2.0 §3.9.4's alpha modes: kMask draws the surface where its alpha
// reaches the cut-off and nothing elsewhere; kBlend composites it over
// what is behind by its alpha.
enum class AlphaMode : std::uint8_t { kOpaque = 0, kMask = 1, kBlend = 2 };

// A receiver's textures beyond its base colour, and its alpha, as glTF's
// metallic-roughness material has them (glTF 2.0 §3.9; the TEXM chunk).
// Shading only, like Surface: the light the engine computes is the same
// (an alpha-masked leaf still casts its whole shadow). Each map is looked
// up as an albedo texture is, through its own projection, wrap and
// transform (glTF's are kUv: the mesh carries one coordinate set, the base
// colour's, or the maps' where the base colour has no texture).
using MapTexture = AlbedoTexture;
struct SurfaceMaps {
  std::optional<MapTexture> metallic_roughness;  // linear; G multiplies Surface::roughness, B Surface::metallic
  // Linear; the tangent-space normal 2 rgb - 1 (x along increasing u, y
  // along the normal crossed with it, z the surface normal), its x and y
  // times normal_scale.
  std::optional<MapTexture> normal;
  // Linear; R is the fraction of the ambient (sky) light a point receives,
  // applied as 1 + occlusion_strength (R - 1).
  std::optional<MapTexture> occlusion;
  std::optional<MapTexture> emissive;  // sRGB; multiplies Surface::emissive
  float normal_scale = 1.0f;        // finite, |.| <= 1000
  float occlusion_strength = 1.0f;  // [0, 1]
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha = 1.0f;         // [0, 1], glTF's base colour factor's alpha; times the albedo texture's (TextureImage::alpha)
  float alpha_cutoff = 0.5f;  // [0, 1]; kMask draws where alpha >= alpha_cutoff
  bool any_map() const { return metallic_roughness || normal || occlusion || emissive; }
};

struct Material {
  Vec3f albedo{0.8f, 0.8f, 0.8f};  // diffuse reflectance, each in [0, 1]
  bool transparent = false;
  float ior = 1.5f;                // used when transparent; >= 1
  Vec3f absorption{0, 0, 0};       // transparent: 1/m per RGB channel, >= 0 (stored in the LTTB chunk)
  Scattering scattering;           // transparent: milky or dusty glass (stored in the MDIA chunk)
  Vec3f reflectance{0.9f, 0.9f, 0.9f};  // mirror: specular reflectance per RGB channel, in [0, 1] (the MIRR chunk)
  // transparent: 20 / Abbe number, in [0, kMaxDispersion] (spectrum.h; the
  // DISP chunk). 0: the same index at every wavelength.
  float dispersion = 0.0f;
  // transparent with dispersion: how many light-transport tables at other
  // wavelengths than n_d the file holds (its LTTS chunks; set by the baker
  // and by decode_scene, not stored in OBJS). 0: the caustics from its
  // tables refract at n_d only.
  std::uint32_t spectral_tables = 0;
  std::optional<AlbedoTexture> albedo_texture;  // receivers only: multiplies albedo (the TEXR chunk)
  // transparent: the fraction of each RGB channel light keeps each time it
  // is transmitted through the surface, in [0, 1] (glTF's base colour on a
  // transmissive material, KHR_materials_transmission; the TINT chunk).
  // Light through a solid crosses its surface twice: tint^2. Reflections
  // are not tinted.
  Vec3f tint{1, 1, 1};
  // Receivers only: absent, a Lambertian surface of `albedo` (scene.json
  // without "metallic", "roughness" or "emissive"); glTF materials always
  // have one.
  std::optional<Surface> surface;
  // Receivers only: absent, no maps and opaque.
  std::optional<SurfaceMaps> maps;
};

// Calls f(std::optional<MapTexture>&) for each texture slot of material
// `m` (its albedo texture, then its maps' if it has maps), and f(MapTexture&)
// for every texture it reads: for code that renumbers, gathers or drops
// images.
template <class M, class F>
void for_each_texture_slot(M& m, F f) {
  f(m.albedo_texture);
  if (m.maps) {
    for (auto* t : {&m.maps->metallic_roughness, &m.maps->normal, &m.maps->occlusion, &m.maps->emissive}) f(*t);
  }
}
template <class M, class F>
void for_each_texture(M& m, F f) {
  for_each_texture_slot(m, [&](auto& slot) {
    if (slot) f(*slot);
  });
}

inline bool is_tinted(const Material& m) { return m.tint[0] != 1 || m.tint[1] != 1 || m.tint[2] != 1; }

// What the baker recorded about an encoded mesh; the runtime checks the
// decoded mesh against it.
struct MeshInfo {
  std::string source;              // file name as given in scene.json
  std::uint32_t vertex_count = 0;  // of the source; Draco may split non-manifold vertices
  std::uint32_t triangle_count = 0;
  std::uint8_t position_bits = 0;  // Draco quantisation of positions
  std::uint8_t normal_bits = 0;    // Draco quantisation of normals
  Vec3f bounds_min{};              // object space, before quantisation
  Vec3f bounds_max{};
};

struct Object {
  std::string name;
  std::uint32_t mesh_index = 0;
  Role role = Role::kReceiver;
  Material material;
  Mat4f transform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  // Solid transparent objects: the earlier object whose
  // light-transport tables (LTTB, LTTS) this one uses instead of its own
  // (the LTTR chunk). Allowed when both are solid glass on the same mesh
  // with the same IOR, dispersion and absorption, whatever their
  // transforms: the tables are in object space, and the runtime applies
  // each object's rotation, translation and uniform scale.
  std::optional<std::uint32_t> tables_from;
};

// Whether the upper 3x3 has orthogonal columns of equal length (relative
// 1e-4): a rotation (or mirroring), translation and uniform scale.
bool is_similarity(const Mat4f& m);

// Whether `b` may use `a`'s light-transport tables (Object::tables_from).
inline bool can_share_tables(const Object& a, const Object& b) {
  return is_transparent(a.role) && is_transparent(b.role) && !a.tables_from && a.mesh_index == b.mesh_index &&
         a.material.ior == b.material.ior && a.material.dispersion == b.material.dispersion &&
         a.material.absorption == b.material.absorption;
}

struct Light {
  LightType type = LightType::kDirectional;
  std::string name;
  Vec3f color{1, 1, 1};            // linear RGB tint, each >= 0
  Vec3f direction{0, -1, 0};       // directional: unit direction of travel; spot: unit axis (where it points)
  float irradiance = 1.0f;         // directional: E0 in W/m^2, >= 0
  Vec3f position{0, 5, 0};         // point
  float intensity = 1.0f;          // point: W/sr, >= 0 (a spot's, along its axis)
  // A spot light is a point light whose intensity falls off outside a cone
  // about `direction` (KHR_lights_punctual's spot: half-angles in radians,
  // 0 <= inner < outer <= pi/2; spot_factor()).
  bool spot = false;
  float inner_cone = 0.0f;
  float outer_cone = 0.78539816f;  // pi/4, glTF's default
};

// The cone's terms as the shaders take them: x cos(outer), y 1 / (cos(inner)
// - cos(outer)), z 1 for a spot (0: no cone).
inline std::array<float, 3> spot_terms(const Light& l) {
  if (!l.spot) return {-1.0f, 1.0f, 0.0f};
  const float co = std::cos(l.outer_cone), ci = std::cos(l.inner_cone);
  return {co, 1.0f / std::max(ci - co, 1e-4f), 1.0f};
}

// A point light's intensity towards unit direction `travel` (away from the
// light) relative to its `intensity`: 1 without a cone; for a spot, the
// falloff of the KHR_lights_punctual specification's reference
// implementation, t^2 with t = clamp((cos a - cos outer) / (cos inner -
// cos outer), 0, 1) and a the angle from the axis -- 1 inside the inner
// cone, 0 outside the outer one, smooth between. The GLSL twin is
// caustix_spot_factor() in caustix.glsl.
inline float spot_factor(const Light& l, const Vec3f& travel) {
  if (!l.spot) return 1.0f;
  const auto t = spot_terms(l);
  const float c = travel[0] * l.direction[0] + travel[1] * l.direction[1] + travel[2] * l.direction[2];
  const float x = std::clamp((c - t[0]) * t[1], 0.0f, 1.0f);
  return x * x;
}

// Water height y(x, z, t) = level + sum_i A_i sin(k_i (d_i . (x, z) - c_i t) + phi_i),
// k_i = 2 pi / wavelength_i, d_i a unit 2-D direction.
struct Wave {
  float amplitude = 0.0f;          // metres, >= 0
  float wavelength = 1.0f;         // metres, > 0
  Vec2f direction{1, 0};           // unit (x, z)
  float speed = 0.0f;              // metres per second (phase speed)
  float phase = 0.0f;              // radians
};

struct Water {
  float level = 0.0f;
  float ior = 1.33f;
  Vec3f absorption{0, 0, 0};       // K per metre, per RGB channel, >= 0
  std::array<std::uint32_t, 2> cells{128, 128};  // grid quads along x and z
  std::array<float, 4> extent{-2, -2, 2, 2};     // x0, z0, x1, z1
  std::vector<Wave> waves;
  Scattering scattering;           // water that scatters shows light shafts (stored in the MDIA chunk)
  float dispersion = 0.0f;         // 20 / Abbe number, [0, kMaxDispersion] (spectrum.h; the DISP chunk); pure water: 0.36
};

// A homogeneous participating medium filling an axis-aligned box (fog, dust).
struct Medium {
  std::array<float, 6> extent{-1, -1, -1, 1, 1, 1};  // x0, y0, z0, x1, y1, z1
  Vec3f absorption{0, 0, 0};       // sigma_a, 1/m per RGB channel, >= 0
  Scattering scattering;
};

struct Camera {
  Vec3f position{0, 4, 6};
  Vec3f target{0, 0, 0};
  Vec3f up{0, 1, 0};
  float fov_y_deg = 45.0f;
  float near_plane = 0.05f;
  float far_plane = 100.0f;
};

// The runtime settings a bake preset chose (caustix-bake --preset,
// docs/tradeoff.md): renderers start from these instead of their built-in
// defaults; options given explicitly still win. Not from scene.json.
inline constexpr std::uint32_t kMaxRuntimeMapSize = 8192;
inline constexpr std::uint32_t kMaxGlassPlanes = 16;
struct RenderDefaults {
  std::string preset;                   // the preset's name, for messages
  std::uint32_t caustics_map_size = 512;  // water caustics map S x S, 1..kMaxRuntimeMapSize
  std::uint32_t glass_map_size = 512;     // glass illumination textures, 1..kMaxRuntimeMapSize
  std::uint32_t glass_planes = 4;         // virtual planes per glass target, 1..kMaxGlassPlanes
  // Media (Pfeuti; docs/volume.md): photons per axis per light (1..8192)
  // and radiance-grid voxels along the media's longest side (2..1024).
  std::uint32_t volume_photons = 256;
  std::uint32_t volume_grid = 64;
  // Image-space caustic maps (docs/caustic-maps.md): photon grid
  // side (1..4096), caustic map side (16..4096), adaptive traversal levels
  // (0..8; 0: the uniform grid) and photon budget (1..2^24).
  std::uint32_t cmap_photons = 512;
  std::uint32_t cmap_map_size = 512;
  std::uint32_t cmap_adaptive_levels = 0;
  std::uint32_t cmap_photon_budget = 1u << 16;
  // The water surface's refraction and reflection textures
  // (Mihalik 2008 §5.1-5.2): the largest side the automatic size (a texel per
  // pixel) may reach, 16..8192, or 0 for no limit but the driver's.
  std::uint32_t water_texture = 512;
  // Glass focus windows where glass disperses (docs/glass-focus.md, "A
  // window per wavelength"): 1 drawn at half their texels a side and
  // interpolated (fast, balanced), 0 at their own (accurate).
  std::uint32_t glass_spectral_coarse = 1;
};

struct SceneDesc {
  std::string name;
  std::vector<MeshInfo> meshes;
  std::vector<Object> objects;
  std::vector<Light> lights;
  std::optional<Water> water;
  std::optional<Medium> medium;
  std::optional<Camera> camera;
  std::optional<RenderDefaults> render;
  std::vector<TextureImage> images;  // the receivers' textures' images (TEXR; their alpha in TEXM)
};

// Limits that keep hostile or absurd inputs bounded (also documented in
// docs/scene-format.md). Exceeding one is a validation error, not a crash.
inline constexpr std::size_t kMaxObjects = 65536;
inline constexpr std::size_t kMaxLights = 4096;
inline constexpr std::size_t kMaxWaves = 256;
inline constexpr std::size_t kMaxNameLength = 4096;
inline constexpr std::uint32_t kMaxWaterCells = 4096;  // per axis
inline constexpr std::uint32_t kMaxMeshVertices = 1u << 26;
inline constexpr float kMaxIor = 10.0f;
inline constexpr float kMaxCoefficient = 1e6f;  // scattering and absorption, 1/m

// Whether anything in the scene scatters light (a medium box, water or glass
// with a scattering coefficient): such scenes get the MDIA chunk and the
// volume effect; others pay nothing for media.
bool scene_scatters(const SceneDesc& scene);
// Whether any transparent object or the water has dispersion > 0: such
// scenes get the DISP chunk and the renderers' wavelength sampling; others
// pay nothing for it.
bool scene_disperses(const SceneDesc& scene);
// E0, what irradiance and in-scatter images are divided by
// (docs/architecture.md): the first directional light's irradiance, else 1.
float scene_e0(const SceneDesc& scene);

// A value rule broken: `pointer` is a JSON pointer into the scene
// ("/objects/2/material/ior") so the JSON front end can turn it into a line
// and column, and the .cxb decoder can name the field.
struct ValidationIssue {
  std::string pointer;
  std::string message;
};

// Checks every value rule of the scene (ranges, finiteness, indices, unique
// names). Returns the first issue found, in document order. With
// check_meshes false the mesh records and the textures' image indices (not
// yet imported) are not checked.
std::optional<ValidationIssue> validate_scene(const SceneDesc& scene, bool check_meshes = true);

// Normalises directions in place (lights, waves); call before encoding.
void normalize_scene(SceneDesc& scene);

// Serialises the scene, one Draco stream per mesh (meshes[i] <->
// scene.meshes[i]), the level maps, the object boxes and the light-transport
// tables (one per transparent object at n_d, wavelength_nm 0, as LTTB; then
// those at other wavelengths of dispersive objects, as LTTS; none for an
// object whose Object::tables_from names another's, LTTR) and, for scenes that scatter, the
// index grids (one per transparent object) into .cxb bytes. Deterministic.
std::vector<std::uint8_t> encode_scene(const SceneDesc& scene,
                                       const std::vector<std::vector<std::uint8_t>>& draco_meshes,
                                       const std::vector<LevelMap>& level_maps = {},
                                       const std::vector<ObjectBox>& boxes = {},
                                       const std::vector<LightTransportTable>& tables = {},
                                       const std::vector<IndexGrid>& index_grids = {});

struct DecodedScene {
  SceneDesc scene;
  // Draco stream per mesh, pointing into the container's buffer.
  std::vector<std::span<const std::uint8_t>> draco_meshes;
  std::vector<LevelMap> level_maps;  // in file order; at most one per (object, light)
  std::vector<ObjectBox> boxes;
  // One per solid transparent object, in object order, except those that
  // use an earlier object's (Object::tables_from).
  std::vector<LightTransportTable> transport_tables;
  // Tables at other wavelengths (LTTS): for transparent objects with
  // dispersion, by object, then by ascending wavelength.
  std::vector<LightTransportTable> spectral_tables;
  std::vector<IndexGrid> index_grids;  // scenes that scatter: one per transparent object, in object order
};

// Decodes and validates the scene chunks of a validated container.
Result<DecodedScene> decode_scene(const cxb::Container& container);

}  // namespace caustix
