#pragma once
// What the GLSL include (caustix.glsl) reads and where: the texture units
// and binding points (Bindings), the std140 block of one (receiver, light)
// pair (LightBlock), the all-receivers table's entries, and the resources
// Engine::lighting() hands out. Applications that bind caustix's resources
// themselves, or read them from another shading language, find every
// field here; engine.h is the Engine that fills them.

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace caustix::runtime {

// Where the GLSL include finds its resources: one uniform-buffer binding
// point (the block CaustixLight), twelve texture units and, for bind_all(),
// one shader-storage binding point (the table). The default units are 4..15,
// within the 16 per shader stage that GL 4.5 guarantees, leaving 0..3 to
// the application's own textures. Change them when they collide with the
// application's own; glsl_include() then carries the matching #defines
// (CAUSTIX_BINDING_BLOCK, CAUSTIX_UNIT_*).
struct Bindings {
  unsigned block = 7;
  unsigned shadow_2d = 4;           // sampler2DShadow: the light's shadow map (directional)
  unsigned shadow_cube = 5;         // samplerCubeShadow: the light's shadow map (point)
  unsigned caustics = 6;            // sampler2D RGBA32F: the caustics map (irradiance, direction; A: the receiver's presence, divided out; caustix.glsl)
  unsigned position = 7;            // sampler2D R16: the receiver's position map (its first surface's v, coded as the bake's LMAP depth; caustix.glsl decodes it)
  unsigned glass_illumination = 8;  // sampler2DArray RGBA32F: glass illumination textures
  unsigned glass_target = 9;        // sampler2D RGBA32F: the receiver seen from the glass's virtual camera
  unsigned glass_shadow_2d = 10;    // sampler2DShadow: the glass's own shadow map (directional)
  unsigned glass_shadow_cube = 11;  // samplerCubeShadow: the glass's own shadow map (point)
  // sampler2D RGBA32F: the light's image-space caustic map (mirrors; glass
  // with GlassMethod::kCausticMap).
  unsigned caustic_map = 12;
  // sampler2D RG32F: the filtered depth moments of the light's shadow map
  // and of the glass's (variance shadow maps, ShadowOptions::filter kVsm;
  // directional lights; 1x1 where unused).
  unsigned shadow_vsm = 13;
  unsigned glass_shadow_vsm = 14;
  // sampler2D RGBA32F: the caustics map's irradiance per RGB channel when
  // the water disperses (LightBlock::frame_v.w 1; 1x1 where unused).
  unsigned caustics_color = 15;
  // Shader-storage binding point of the all-receivers table (bind_all();
  // the block CaustixTable of caustix.glsl with CAUSTIX_ALL_RECEIVERS).
  // Uniform-buffer and shader-storage points are separate: 7 here does
  // not collide with `block`.
  unsigned table = 7;
};

// How a receiver is lit by one light (the block's mode.x).
enum class LightMode : int {
  kDirect = 0,     // no water between light and receiver: E cos * visibility (+ light through glass)
  kFlatWater = 1,  // method "none": refraction and Fresnel through flat water, no caustics
  kCaustics = 2,   // Tipprasert 2006 §4.6: the caustics map, eq. 4-19
};

// The std140 uniform block CaustixLight of the GLSL include, one per
// (receiver, light). Applications that bind it themselves (their own
// buffer, another shading language) find every field here. Vectors carry
// extra scalars in w where noted.
struct LightBlock {
  glm::ivec4 mode{0};           // x LightMode, y light type (1 directional, 2 point or spot), z glass textures bound, w scene has glass
  glm::vec4 light_direction{0}; // xyz: unit direction of travel (directional); w: 1 variance shadow maps, 0 PCF
  glm::vec4 light_position{0};  // xyz: position (point); w: VSM light-bleeding reduction
  glm::vec4 light_color{0};     // rgb: linear colour; w: E0 (W/m^2, directional) or I (W/sr, point)
  glm::vec4 water{0};           // x rest level (-1e30: no water), y IOR, z point shadow far plane, w shadow texel (m)
  glm::vec4 absorption{0};      // xyz: water's K per metre
  glm::vec4 refracted{0};       // xyz: directional light's travel below flat water
  glm::mat4 world_to_shadow{1}; // world -> directional shadow map texture [0,1]^3
  // Caustics map (mode kCaustics): world -> (U, V, W) frame coordinates; the
  // map's texture coordinate is (0.5 (u/half.x + 1), 0.5 (w/half.z + 1)).
  glm::vec4 frame_origin{0};    // w: self-shadow tolerance along V (m)
  glm::vec4 frame_u{0};         // w: half a position-map texel's diagonal (m)
  glm::vec4 frame_v{0};         // w: 1 where the caustics colour texture is bound (the water disperses)
  glm::vec4 frame_w{0};
  glm::vec4 frame_half{0};      // xyz: half extents along U, V, W
  // Glass illumination (mode.z = 1): the virtual camera's frame and planes.
  glm::vec4 glass_origin{0};    // w: self-shadow tolerance along V (m)
  glm::vec4 glass_u{0};         // w: number of planes n
  // The focus window (CausticsOptions::glass_focus): layers
  // n..2n-1 of the illumination texture hold the same planes over the
  // square of half-size glass_half.w (texture-coordinate units, 0: no
  // window) centred at (glass_v.w, glass_w.w), drawn into the layers'
  // lower corner (0.65 of their texels per side: caustix.glsl's
  // CAUSTIX_GLASS_FOCUS_TEXELS), with mips.
  glm::vec4 glass_v{0};         // w: the focus window's centre, u
  glm::vec4 glass_w{0};         // w: the focus window's centre, v
  glm::vec4 glass_half{0};      // w: the focus window's half-size (0: none)
  std::array<glm::vec4, 4> glass_plane_v{};  // 16 plane coordinates along V, decreasing
  // Image-space caustic map (timofy 2009): an orthographic frame
  // along the light, V towards it; texture coordinate as for the caustics
  // map. The map holds irradiance on the receivers' first surface seen
  // from the light (rgb, without the light's colour) and that surface's
  // coordinate along V (alpha).
  // With a focus window (CausticMapOptions::focus) the texture
  // holds the main map in its lowest map_size rows, so its texture
  // coordinate t is the frame's times cmap_w.w, and above them the window:
  // the texels [0, m) x [map_size, map_size + m), m = map_size / 2, over
  // the square of half-size h around (s, t) = (c_s, c_t) in the main map's
  // coordinates, where its last texel (map_size - 1, map_size + m - 1)
  // holds (c_s, c_t, h, 1) (h 0: no window this update). The window is
  // placed on the GPU, so only that texel carries it. Inside the square
  // the irradiance is the main map's plus the window's: the light of the
  // photons that landed densely there is in the window only. The texture
  // has mips for the window; the main map is read at level 0 (caustix.glsl,
  // caustix_caustic_map_irradiance, does all this).
  glm::vec4 cmap_origin{0};     // w: 1 where a caustic map is bound, else 0
  glm::vec4 cmap_u{0};          // w: half a texel's diagonal (m)
  glm::vec4 cmap_v{0};          // w: visibility tolerance along V (m)
  glm::vec4 cmap_w{0};          // w: the main map's share of the texture's height (1 without a focus window)
  glm::vec4 cmap_half{0};
  // A spot light's cone: x cos(outer), y 1 / (cos(inner) -
  // cos(outer)), z 1 for a spot, 0 for a light without a cone; the axis is
  // light_direction.xyz. caustix_spot_factor() in caustix.glsl.
  glm::vec4 spot{0};
};
static_assert(sizeof(LightBlock) == 31 * 16, "LightBlock must match the std140 block of caustix.glsl");

// One entry of the all-receivers table (Engine::bind_all(); the std430
// struct CaustixTableEntry of caustix.glsl): the pair's block, and where
// each of its twelve textures (Bindings order: shadow_2d, shadow_cube,
// caustics, position, glass_illumination, glass_target, glass_shadow_2d,
// glass_shadow_cube, caustic_map, shadow_vsm, glass_shadow_vsm,
// caustics_color) lies in the array bound at that texture's unit: texture
// k's first layer is layer[k / 4][k % 4] (cube maps: the cube's index),
// its width and height size[k / 2][2 (k % 2)] and [2 (k % 2) + 1] texels,
// in the layer's corner. The buffer holds ivec4(objects, lights, 0, 0),
// then the entries at object * lights + light; an object that is no
// receiver has a zero block.
struct ReceiverTableEntry {
  LightBlock block;
  std::array<glm::ivec4, 3> layer{};
  std::array<glm::ivec4, 6> size{};
};
static_assert(sizeof(ReceiverTableEntry) == 40 * 16, "ReceiverTableEntry must match the std430 struct of caustix.glsl");

// Everything the GLSL include reads for one (receiver, light), as plain data.
struct ReceiverLighting {
  LightBlock block;
  // GL texture names (never 0: unused ones are valid 1x1 textures).
  unsigned shadow_2d = 0, shadow_cube = 0, caustics = 0, position = 0;
  unsigned glass_illumination = 0, glass_target = 0, glass_shadow_2d = 0, glass_shadow_cube = 0;
  unsigned caustic_map = 0;
  unsigned shadow_vsm = 0, glass_shadow_vsm = 0;
  unsigned caustics_color = 0;
  // The block's frames as matrices: world (x, y, z, 1) -> (s, t, v, 1), with
  // (s, t) the texture coordinate of the caustics and position maps (of the
  // glass textures), in [0, 1] over the region they cover, and v the
  // coordinate along V in metres (what the position map codes and the
  // glass planes hold). Identity where the mode does not use them. The caustic
  // map's t covers [0, cmap_w.w): its main map, below a focus window.
  glm::mat4 world_to_caustics{1.0f};
  glm::mat4 world_to_glass{1.0f};
  glm::mat4 world_to_caustic_map{1.0f};
  // The block as the engine uploaded it: glBindBufferRange(GL_UNIFORM_BUFFER,
  // binding, buffer, offset, sizeof(LightBlock)).
  unsigned buffer = 0;
  std::size_t offset = 0;
};

// A receiver's base-colour texture (Engine::albedo_map).
struct AlbedoMap {
  // GL_TEXTURE_2D, GL_SRGB8_ALPHA8 with a full mip chain (sampling returns
  // linear colour; alpha is the image's where the material masks or blends
  // with it, else 1); wrap and trilinear filtering are set on the texture,
  // so bind it with no sampler object.
  unsigned texture = 0;
  // kUv: the mesh's texture coordinates (draw_object's attribute 2); kBox:
  // world metres on the axis plane the surface faces most (formats/scene.h).
  TextureProjection projection = TextureProjection::kUv;
  // Row-major 2 x 3: (s, t) = (m0 u + m1 v + m2, m3 u + m4 v + m5).
  std::array<float, 6> transform{1, 0, 0, 0, 1, 0};
};

// A receiver's textures beyond its base colour and its alpha (glTF's
// metallic-roughness material; formats/scene.h SurfaceMaps): for
// applications that shade it with the standard PBR model, as the sample
// renderer does (docs/display.md, "Surfaces"). Each map is looked up as an
// AlbedoMap is, through its own projection and transform
// (caustix_texture_coords()).
struct SurfaceMapBindings {
  struct Map {
    // GL_TEXTURE_2D with a full mip chain, wrap and filtering set on it (as
    // AlbedoMap's); 0 where the material has no such map.
    unsigned texture = 0;
    TextureProjection projection = TextureProjection::kUv;
    std::array<float, 6> transform{1, 0, 0, 0, 1, 0};
  };
  Map metallic_roughness;  // GL_RGBA8: G multiplies the roughness, B the metallic factor
  Map normal;              // GL_RGBA8: tangent-space normal 2 rgb - 1 (SurfaceMaps::normal)
  Map occlusion;           // GL_RGBA8: R, the ambient light kept
  Map emissive;            // GL_SRGB8_ALPHA8: multiplies Surface::emissive
  float normal_scale = 1.0f;
  float occlusion_strength = 1.0f;
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha = 1.0f;         // times the albedo texture's alpha
  float alpha_cutoff = 0.5f;  // kMask: drawn where alpha >= alpha_cutoff
};

}  // namespace caustix::runtime
