// caustix.glsl: caustic irradiance for an application's fragment shaders.
// Shipped with caustix (installed as include/caustix/runtime/caustix.glsl;
// Engine::glsl_include() returns it with the engine's bindings). Put it after
// the shader's #version line (450 core or later). docs/embedding.md.
//
// Call, per light, after Engine::bind(receiver, light):
//   vec3 caustix_irradiance(vec3 world_position, vec3 world_normal)
//   vec3 caustix_light_travel(vec3 world_position)  (the light's direction there, for specular)
// or, with CAUSTIX_ALL_RECEIVERS defined before the include and after
// Engine::bind_all() (deferred and clustered-forward passes):
//   vec3 caustix_irradiance_at(vec3 world_position, vec3 world_normal, int receiver, int light)
//   vec3 caustix_irradiance_all(vec3 world_position, vec3 world_normal, int receiver)
//   int caustix_light_count()
// the irradiance (W/m^2 times the light's linear colour) that light delivers
// at the point: through flat water (Fresnel, refraction), as caustics from
// the water (Tipprasert 2006 §4.6, eq. 4-19), through glass (Iwasaki et al. §4.3), with
// shadows and the water's absorption. A diffuse surface's outgoing radiance
// is albedo / pi times it (caustix's own renderer omits the 1/pi, as the
// thesis's I_c I_d does). Sum over lights (eq. 4-20).
//
// Names this file declares: the struct CaustixLightData, the uniform block
// CAUSTIX_BLOCK_NAME (its member caustix_light) or, with
// CAUSTIX_ALL_RECEIVERS, the storage block CAUSTIX_TABLE_NAME at
// CAUSTIX_BINDING_TABLE (a shader-storage binding) and the struct
// CaustixTableEntry; samplers caustix_*, functions caustix_*. One shader
// uses one of the two modes. Define any of the
// macros below before including it to move a binding (and create the Engine
// with the same caustix::runtime::Bindings); CAUSTIX_OPTICS_ONLY keeps only
// the Fresnel functions. Include guards (CAUSTIX_GLSL_OPTICS,
// CAUSTIX_GLSL_LIGHTING) make a second inclusion into one shader a no-op.

#ifndef CAUSTIX_GLSL_OPTICS
#define CAUSTIX_GLSL_OPTICS
// ---- optics ----
// Exact unpolarised Fresnel reflectance at an interface, eta = n1/n2 (n1 on
// the incident side); 1 beyond the critical angle (total internal reflection).
float caustix_fresnel_reflectance(float cos_i, float eta) {
  float sin2_t = eta * eta * (1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) return 1.0;
  float cos_t = sqrt(1.0 - sin2_t);
  float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// Exact Fresnel transmittance, unpolarised, from air (n = 1) into n2.
float caustix_fresnel_transmittance(float cos_i, float n2) { return 1.0 - caustix_fresnel_reflectance(cos_i, 1.0 / n2); }

// A point light's intensity towards unit direction `travel` (away from the
// light) relative to its own: 1 without a cone; for a spot light
// (KHR_lights_punctual), t^2 with t = clamp((travel . axis - cos outer) /
// (cos inner - cos outer), 0, 1). `spot` is (cos outer, 1 / (cos inner -
// cos outer), 1 for a spot or 0); formats' spot_factor() is its twin.
float caustix_spot_factor(vec3 travel, vec3 axis, vec3 spot) {
  if (spot.z == 0.0) return 1.0;
  float t = clamp((dot(travel, axis) - spot.x) * spot.y, 0.0, 1.0);
  return t * t;
}

// Where a receiver's albedo texture is looked up (Engine::albedo_map;
// formats/scene.h AlbedoTexture): projection 1 takes the mesh's texture
// coordinates `uv` (attribute 2), projection 2 world metres on the axis
// plane the world normal `n` faces most (x: (z, y), y: (x, z), z: (x, y));
// then (s, t) = (dot(row0, (u, v, 1)), dot(row1, (u, v, 1))).
vec2 caustix_texture_coords(int projection, vec3 row0, vec3 row1, vec2 uv, vec3 world, vec3 n) {
  vec2 c = uv;
  if (projection == 2) {
    vec3 a = abs(n);
    c = a.x >= a.y && a.x >= a.z ? world.zy : (a.y >= a.z ? world.xz : world.xy);
  }
  return vec2(dot(row0, vec3(c, 1.0)), dot(row1, vec3(c, 1.0)));
}
#endif  // CAUSTIX_GLSL_OPTICS

#if !defined(CAUSTIX_OPTICS_ONLY) && !defined(CAUSTIX_GLSL_LIGHTING)
#define CAUSTIX_GLSL_LIGHTING

#ifndef CAUSTIX_BLOCK_NAME
#define CAUSTIX_BLOCK_NAME CaustixLight
#endif
#ifndef CAUSTIX_BINDING_BLOCK
#define CAUSTIX_BINDING_BLOCK 7
#endif
#ifndef CAUSTIX_BINDING_TABLE
#define CAUSTIX_BINDING_TABLE 7
#endif
#ifndef CAUSTIX_UNIT_SHADOW_2D
#define CAUSTIX_UNIT_SHADOW_2D 4
#endif
#ifndef CAUSTIX_UNIT_SHADOW_CUBE
#define CAUSTIX_UNIT_SHADOW_CUBE 5
#endif
#ifndef CAUSTIX_UNIT_CAUSTICS
#define CAUSTIX_UNIT_CAUSTICS 6
#endif
#ifndef CAUSTIX_UNIT_POSITION
#define CAUSTIX_UNIT_POSITION 7
#endif
#ifndef CAUSTIX_UNIT_GLASS_ILLUMINATION
#define CAUSTIX_UNIT_GLASS_ILLUMINATION 8
#endif
#ifndef CAUSTIX_UNIT_GLASS_TARGET
#define CAUSTIX_UNIT_GLASS_TARGET 9
#endif
#ifndef CAUSTIX_UNIT_GLASS_SHADOW_2D
#define CAUSTIX_UNIT_GLASS_SHADOW_2D 10
#endif
#ifndef CAUSTIX_UNIT_GLASS_SHADOW_CUBE
#define CAUSTIX_UNIT_GLASS_SHADOW_CUBE 11
#endif
#ifndef CAUSTIX_UNIT_CAUSTIC_MAP
#define CAUSTIX_UNIT_CAUSTIC_MAP 12
#endif
#ifndef CAUSTIX_UNIT_SHADOW_VSM
#define CAUSTIX_UNIT_SHADOW_VSM 13
#endif
#ifndef CAUSTIX_UNIT_GLASS_SHADOW_VSM
#define CAUSTIX_UNIT_GLASS_SHADOW_VSM 14
#endif
#ifndef CAUSTIX_UNIT_CAUSTICS_COLOR
#define CAUSTIX_UNIT_CAUSTICS_COLOR 15
#endif

// A stage without implicit derivatives (compute, vertex, geometry) must
// `#define CAUSTIX_NO_DERIVATIVES` before including this file: the glass
// focus windows query their mip level (textureQueryLod), which only a
// fragment shader has.
//
// The glass focus windows' texels per side, as a fraction of their
// illumination texture's (LightBlock::glass_half.w says where a window
// lies): a window's layers hold it in their lower corner. The engine's
// kFocusTexels.
const float CAUSTIX_GLASS_FOCUS_TEXELS = 0.65;

// One (receiver, light): caustix::runtime::LightBlock field for field (the
// per-receiver block, and each entry of the all-receivers table).
// Light modes (mode.x), chosen per (object, light) by the engine:
//  0 direct: no water between light and point (no water, object above it,
//    or light and object both under it): E_in cos(theta) * visibility, plus
//    light through glass.
//  1 flat water (method "none"): refraction and Fresnel through the flat
//    surface, no caustics: E_in T(theta_i) cos(theta_i)/cos(theta_t) * n.(-T)
//    * e^(-K d) * visibility.
//  2 caustics casting (Tipprasert 2006 §4.6): the caustics map holds irradiance on
//    planes perpendicular to V (eq. 4-18, R) and the light's mean direction
//    of travel d there (G, B: R times d.U / d.V and d.W / d.V); a point gets
//    R n.d / V.d (the cos theta_t of eq. 4-18 for this surface and the light
//    that actually arrives, where the thesis takes n.V), e^(-K d) (eq.
//    4-17), and its visibility: not behind its own first surface (position
//    map) and not in another object's shadow. When the water disperses
//    (frame_v.w 1) the map's R is the mean over the traced
//    wavelengths and caustix_caustics_color holds the irradiance per RGB
//    channel (the spectral integral): each channel is scaled by its ratio
//    to R, the direction taken as the wavelengths' mean.
struct CaustixLightData {
  ivec4 mode;            // x light mode, y light type (1 directional, 2 point), z glass textures bound, w scene has glass
  vec4 light_direction;  // xyz unit direction of travel (directional), w 1: variance shadow maps
  vec4 light_position;   // xyz (point), w VSM light-bleeding reduction
  vec4 light_color;      // rgb linear colour, w E0 (W/m^2) or I (W/sr)
  vec4 water;            // x rest level, y IOR, z point shadow far, w shadow texel (m)
  vec4 absorption;       // xyz K per metre
  vec4 refracted;        // xyz directional travel below flat water
  mat4 world_to_shadow;
  vec4 frame_origin;     // w self-shadow tolerance
  vec4 frame_u;          // w half a position-map texel's diagonal
  vec4 frame_v;          // w 1: the caustics colour texture is bound
  vec4 frame_w;
  vec4 frame_half;
  vec4 glass_origin;     // w tolerance
  vec4 glass_u;          // w plane count
  vec4 glass_v;
  vec4 glass_w;
  vec4 glass_half;
  vec4 glass_plane_v[4]; // 16 plane coordinates along V, decreasing: plane 0 nearest the light
  vec4 cmap_origin;      // w 1: a caustic map is bound
  vec4 cmap_u;           // w half a texel's diagonal
  vec4 cmap_v;           // w visibility tolerance along V
  vec4 cmap_w;
  vec4 cmap_half;
  vec4 spot;             // xyz a spot light's cone (caustix_spot_factor; axis light_direction.xyz), z 0 without one
};

#ifndef CAUSTIX_ALL_RECEIVERS
// ---- one (receiver, light) at a time: Engine::bind(receiver, light) ----
// The block has no instance name: its one member, caustix_light, is global.
layout(std140, binding = CAUSTIX_BINDING_BLOCK) uniform CAUSTIX_BLOCK_NAME { CaustixLightData caustix_light; };

layout(binding = CAUSTIX_UNIT_SHADOW_2D) uniform sampler2DShadow caustix_shadow_2d;
layout(binding = CAUSTIX_UNIT_SHADOW_CUBE) uniform samplerCubeShadow caustix_shadow_cube;
layout(binding = CAUSTIX_UNIT_CAUSTICS) uniform sampler2D caustix_caustics_map;  // irradiance on planes perpendicular to V, and its direction
layout(binding = CAUSTIX_UNIT_POSITION) uniform sampler2D caustix_position_map;  // the first surface's frame V, coded (caustix_irradiance_from_light)
layout(binding = CAUSTIX_UNIT_CAUSTICS_COLOR) uniform sampler2D caustix_caustics_color;  // irradiance per RGB channel (dispersion)
// Glass (Iwasaki et al. §4.3): the receiver's illumination textures for this
// light, on planes perpendicular to glass_v: the mean transmitted direction
// reversed, or a flat receiver's normal on its lit side (one plane, the
// receiver's own), and the glass's own shadow maps, which
// take the direct light away where glass stands in its path.
layout(binding = CAUSTIX_UNIT_GLASS_ILLUMINATION) uniform sampler2DArray caustix_glass_illumination;
layout(binding = CAUSTIX_UNIT_GLASS_TARGET) uniform sampler2D caustix_glass_target;
layout(binding = CAUSTIX_UNIT_GLASS_SHADOW_2D) uniform sampler2DShadow caustix_glass_shadow_2d;
layout(binding = CAUSTIX_UNIT_GLASS_SHADOW_CUBE) uniform samplerCubeShadow caustix_glass_shadow_cube;
// Image-space caustic map (timofy 2009; docs/caustic-maps.md): light off
// mirrors, and through glass drawn by caustic maps, as irradiance on the
// receivers' first surface seen from the light (rgb) and that surface's
// coordinate along cmap_v (alpha).
layout(binding = CAUSTIX_UNIT_CAUSTIC_MAP) uniform sampler2D caustix_caustic_map;
// Variance shadow maps: the filtered depth moments of the light's shadow
// map and of the glass's.
layout(binding = CAUSTIX_UNIT_SHADOW_VSM) uniform sampler2D caustix_shadow_vsm;
layout(binding = CAUSTIX_UNIT_GLASS_SHADOW_VSM) uniform sampler2D caustix_glass_shadow_vsm;

// What the lighting below reads, one function per texture.
vec4 caustix_fetch_caustics(vec2 uv) { return texture(caustix_caustics_map, uv); }
vec3 caustix_fetch_caustics_color(vec2 uv) { return texture(caustix_caustics_color, uv).rgb; }
float caustix_fetch_position(vec2 uv) { return texture(caustix_position_map, uv).r; }
float caustix_fetch_glass_front(vec2 uv) { return texture(caustix_glass_target, uv).w; }
vec3 caustix_fetch_glass_illumination(vec2 uv, int plane) { return texture(caustix_glass_illumination, vec3(uv, float(plane))).rgb; }
#ifndef CAUSTIX_NO_DERIVATIVES
float caustix_glass_lod(vec2 uv) { return textureQueryLod(caustix_glass_illumination, uv).x; }  // the level read
#else
float caustix_glass_lod(vec2 uv) { return 0.0; }  // a stage without derivatives samples level 0
#endif
vec4 caustix_fetch_caustic_map(vec2 uv) { return textureLod(caustix_caustic_map, uv, 0.0); }  // the main map: level 0
vec3 caustix_fetch_caustic_map_lod(vec2 uv, float lod) { return textureLod(caustix_caustic_map, uv, lod).rgb; }
vec4 caustix_caustic_map_texel(ivec2 t) { return texelFetch(caustix_caustic_map, t, 0); }
vec2 caustix_caustic_map_size() { return vec2(textureSize(caustix_caustic_map, 0)); }
#ifndef CAUSTIX_NO_DERIVATIVES
float caustix_caustic_map_lod(vec2 uv) { return textureQueryLod(caustix_caustic_map, uv).x; }
#else
float caustix_caustic_map_lod(vec2 uv) { return 0.0; }
#endif
float caustix_shadow_tap(bool glass, vec2 uv, float ref) {
  return glass ? texture(caustix_glass_shadow_2d, vec3(uv, ref)) : texture(caustix_shadow_2d, vec3(uv, ref));
}
vec2 caustix_shadow_texel(bool glass) {
  return 1.0 / vec2(glass ? textureSize(caustix_glass_shadow_2d, 0) : textureSize(caustix_shadow_2d, 0));
}
float caustix_shadow_cube_tap(bool glass, vec3 d, float ref) {
  return glass ? texture(caustix_glass_shadow_cube, vec4(d, ref)) : texture(caustix_shadow_cube, vec4(d, ref));
}
vec2 caustix_fetch_moments(bool glass, vec2 uv) {
  return glass ? texture(caustix_glass_shadow_vsm, uv).xy : texture(caustix_shadow_vsm, uv).xy;
}

#else
// ---- every (receiver, light) at once: Engine::bind_all() ----
// For deferred and clustered-forward passes, which know a point's receiver
// (a G-buffer's object id) but bind nothing per receiver. The table holds
// every pair's block, in the order receiver * lights + light, with where
// its textures lie in the texture arrays bound at the same units as the
// per-pair samplers: each pair's or light's texture is a layer (its texels
// in the layer's corner, `size` of them). Textures are read at level 0
// (a deferred pass has no derivatives of a receiver's map coordinates).
struct CaustixTableEntry {
  CaustixLightData light;
  ivec4 layer[3];  // per texture, in caustix::runtime::Bindings order: its layer (cube maps: cube index)
  ivec4 size[6];   // per texture, the same order: its width, height in texels (two per ivec4)
};
#ifndef CAUSTIX_TABLE_NAME
#define CAUSTIX_TABLE_NAME CaustixTable
#endif
layout(std430, binding = CAUSTIX_BINDING_TABLE) readonly buffer CAUSTIX_TABLE_NAME {
  ivec4 caustix_table_shape;  // x objects (receivers and not), y lights
  CaustixTableEntry caustix_table[];
};
int caustix_entry = 0;  // the pair being lit
#define caustix_light (caustix_table[caustix_entry].light)

layout(binding = CAUSTIX_UNIT_SHADOW_2D) uniform sampler2DArrayShadow caustix_shadow_2d;
layout(binding = CAUSTIX_UNIT_SHADOW_CUBE) uniform samplerCubeArrayShadow caustix_shadow_cube;
layout(binding = CAUSTIX_UNIT_CAUSTICS) uniform sampler2DArray caustix_caustics_map;
layout(binding = CAUSTIX_UNIT_POSITION) uniform sampler2DArray caustix_position_map;
layout(binding = CAUSTIX_UNIT_CAUSTICS_COLOR) uniform sampler2DArray caustix_caustics_color;
layout(binding = CAUSTIX_UNIT_GLASS_ILLUMINATION) uniform sampler2DArray caustix_glass_illumination;
layout(binding = CAUSTIX_UNIT_GLASS_TARGET) uniform sampler2DArray caustix_glass_target;
layout(binding = CAUSTIX_UNIT_GLASS_SHADOW_2D) uniform sampler2DArrayShadow caustix_glass_shadow_2d;
layout(binding = CAUSTIX_UNIT_GLASS_SHADOW_CUBE) uniform samplerCubeArrayShadow caustix_glass_shadow_cube;
layout(binding = CAUSTIX_UNIT_CAUSTIC_MAP) uniform sampler2DArray caustix_caustic_map;
layout(binding = CAUSTIX_UNIT_SHADOW_VSM) uniform sampler2DArray caustix_shadow_vsm;
layout(binding = CAUSTIX_UNIT_GLASS_SHADOW_VSM) uniform sampler2DArray caustix_glass_shadow_vsm;

// Texture k of the pair (k in Bindings order: 0 shadow_2d, 1 shadow_cube,
// 2 caustics, 3 position, 4 glass_illumination, 5 glass_target,
// 6 glass_shadow_2d, 7 glass_shadow_cube, 8 caustic_map, 9 shadow_vsm,
// 10 glass_shadow_vsm, 11 caustics_color).
int caustix_table_layer(int k) { return caustix_table[caustix_entry].layer[k >> 2][k & 3]; }
vec2 caustix_table_size(int k) {
  ivec4 s = caustix_table[caustix_entry].size[k >> 1];
  return vec2((k & 1) == 0 ? s.xy : s.zw);
}
// A coordinate over texture k -> over its corner of the array's layer,
// clamped to its edge texels' centres (what clamp-to-edge does for it).
vec3 caustix_table_uv(int k, vec2 uv, ivec3 array_size, int plane) {
  vec2 size = caustix_table_size(k);
  return vec3(clamp(uv * size, vec2(0.5), size - 0.5) / vec2(array_size.xy), float(caustix_table_layer(k) + plane));
}
vec4 caustix_fetch_caustics(vec2 uv) { return textureLod(caustix_caustics_map, caustix_table_uv(2, uv, textureSize(caustix_caustics_map, 0), 0), 0.0); }
vec3 caustix_fetch_caustics_color(vec2 uv) { return textureLod(caustix_caustics_color, caustix_table_uv(11, uv, textureSize(caustix_caustics_color, 0), 0), 0.0).rgb; }
float caustix_fetch_position(vec2 uv) { return textureLod(caustix_position_map, caustix_table_uv(3, uv, textureSize(caustix_position_map, 0), 0), 0.0).r; }
float caustix_fetch_glass_front(vec2 uv) { return textureLod(caustix_glass_target, caustix_table_uv(5, uv, textureSize(caustix_glass_target, 0), 0), 0.0).w; }
vec3 caustix_fetch_glass_illumination(vec2 uv, int plane) {
  return textureLod(caustix_glass_illumination, caustix_table_uv(4, uv, textureSize(caustix_glass_illumination, 0), plane), 0.0).rgb;
}
float caustix_glass_lod(vec2 uv) { return 0.0; }  // level 0, as every fetch here
vec4 caustix_fetch_caustic_map(vec2 uv) { return textureLod(caustix_caustic_map, caustix_table_uv(8, uv, textureSize(caustix_caustic_map, 0), 0), 0.0); }
vec3 caustix_fetch_caustic_map_lod(vec2 uv, float lod) { return caustix_fetch_caustic_map(uv).rgb; }
vec2 caustix_caustic_map_size() { return caustix_table_size(8); }
vec4 caustix_caustic_map_texel(ivec2 t) { return caustix_fetch_caustic_map((vec2(t) + 0.5) / caustix_caustic_map_size()); }
float caustix_caustic_map_lod(vec2 uv) { return 0.0; }  // level 0, as every fetch here
float caustix_shadow_tap(bool glass, vec2 uv, float ref) {
  vec3 c = glass ? caustix_table_uv(6, uv, textureSize(caustix_glass_shadow_2d, 0), 0) : caustix_table_uv(0, uv, textureSize(caustix_shadow_2d, 0), 0);
  return glass ? texture(caustix_glass_shadow_2d, vec4(c, ref)) : texture(caustix_shadow_2d, vec4(c, ref));
}
vec2 caustix_shadow_texel(bool glass) { return 1.0 / caustix_table_size(glass ? 6 : 0); }
float caustix_shadow_cube_tap(bool glass, vec3 d, float ref) {
  return glass ? texture(caustix_glass_shadow_cube, vec4(d, float(caustix_table_layer(7))), ref)
               : texture(caustix_shadow_cube, vec4(d, float(caustix_table_layer(1))), ref);
}
vec2 caustix_fetch_moments(bool glass, vec2 uv) {
  return glass ? textureLod(caustix_glass_shadow_vsm, caustix_table_uv(10, uv, textureSize(caustix_glass_shadow_vsm, 0), 0), 0.0).xy
               : textureLod(caustix_shadow_vsm, caustix_table_uv(9, uv, textureSize(caustix_shadow_vsm, 0), 0), 0.0).xy;
}
#endif  // CAUSTIX_ALL_RECEIVERS

// ---- the lighting, one (receiver, light): the same code for both ----
float caustix_plane_v(int i) { return caustix_light.glass_plane_v[i >> 2][i & 3]; }

// Variance shadow maps (Donnelly & Lauritzen 2006): the filtered moments
// (m1, m2) of the light's depth around p's texel bound the fraction of it
// at or beyond depth z by Chebyshev's one-tailed inequality (their eq. 5),
// p_max = var / (var + (z - m1)^2), exact for one planar occluder over a
// planar receiver; the bound's tail below `bleeding` is cut (light-bleeding
// reduction, GPU Gems 3 ch. 8) and the rest rescaled to [0, 1].
float caustix_vsm_visibility(vec2 m, float z) {
  if (z <= m.x) return 1.0;
  float variance = max(m.y - m.x * m.x, 2e-6);  // float cancellation in m2 - m1^2
  float d = z - m.x;
  float p_max = variance / (variance + d * d);
  float bleeding = caustix_light.light_position.w;
  return clamp((p_max - bleeding) / (1.0 - bleeding), 0.0, 1.0);
}

// The opaque objects' shadow maps, or (glass) the glass's own.
float caustix_shadow_visibility_in(bool glass, vec3 p, vec3 n, vec3 to_light) {
  if (caustix_light.mode.y == 2) {
    vec3 q = p + n * (0.01 * length(p - caustix_light.light_position.xyz));
    vec3 d = q - caustix_light.light_position.xyz;
    return caustix_shadow_cube_tap(glass, d, length(d) / caustix_light.water.z - 0.002);
  }
  // Normal offset against acne; 3x3 PCF against aliasing, or the moments.
  vec4 s = caustix_light.world_to_shadow * vec4(p + n * (1.5 * caustix_light.water.w), 1.0);
  s.xyz /= s.w;
  if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0)))) return 1.0;
  float bias = 0.002 * (1.0 - max(dot(n, to_light), 0.0)) + 0.0005;
  if (caustix_light.light_direction.w != 0.0) return caustix_vsm_visibility(caustix_fetch_moments(glass, s.xy), s.z - bias);
  vec2 texel = caustix_shadow_texel(glass);
  float sum = 0.0;
  for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x)
      sum += caustix_shadow_tap(glass, s.xy + vec2(x, y) * texel, s.z - bias);
  return sum / 9.0;
}

// Opaque objects' shadow.
float caustix_shadow_visibility(vec3 p, vec3 n, vec3 to_light) {
  return caustix_shadow_visibility_in(false, p, n, to_light);
}

// Iwasaki et al. §4.3: the incident intensity at p from the illumination textures:
// zero where p lies behind the target's first surface as the virtual camera
// sees it (shadow), else interpolated between the two planes around p
// (d_i <= z_p < d_(i+1)), clamped at the outermost planes.
vec3 caustix_glass_irradiance(vec3 p) {
  vec3 rel = p - caustix_light.glass_origin.xyz;
  vec3 c = vec3(dot(rel, caustix_light.glass_u.xyz), dot(rel, caustix_light.glass_v.xyz), dot(rel, caustix_light.glass_w.xyz));
  vec2 uv = 0.5 * (c.xz / caustix_light.glass_half.xyz.xz + 1.0);
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return vec3(0.0);
  float front = caustix_fetch_glass_front(uv);
  if (c.y < front - caustix_light.glass_origin.w) return vec3(0.0);
  int n = int(caustix_light.glass_u.w);
  float layer = 0.0;
  if (n > 1 && c.y < caustix_plane_v(0)) {
    layer = float(n - 1);
    for (int i = 0; i + 1 < n; ++i) {
      if (c.y >= caustix_plane_v(i + 1)) {
        layer = float(i) + (caustix_plane_v(i) - c.y) / max(caustix_plane_v(i) - caustix_plane_v(i + 1), 1e-12);
        break;
      }
    }
  }
  int i0 = int(floor(layer));
  int i1 = min(i0 + 1, n - 1);
  float f = layer - float(i0);
  vec3 e = mix(caustix_fetch_glass_illumination(uv, i0), caustix_fetch_glass_illumination(uv, i1), f);
  // The focus window: where the light through the glass
  // concentrates, layers n..2n-1 hold the same planes over a square of
  // half-size glass_half.w around (glass_v.w, glass_w.w), in uv units, in
  // their lower corner (CAUSTIX_GLASS_FOCUS_TEXELS of the side; the
  // texture has mips, so that a focus finer than the pixel is averaged,
  // not aliased). Read there, blended into the main layers over the
  // window's outer tenth and where its mip level is no finer than the main
  // layers' texels. Fetched wherever a window exists (a uniform
  // condition), so that the level's derivatives are taken alike across the
  // pixels around the window's edge.
  float h = caustix_light.glass_half.w;
  if (h > 0.0) {
    vec2 d = (uv - vec2(caustix_light.glass_v.w, caustix_light.glass_w.w)) / h;
    vec2 fuv = 0.5 * CAUSTIX_GLASS_FOCUS_TEXELS * (d + 1.0);
    vec3 fine = mix(caustix_fetch_glass_illumination(fuv, n + i0), caustix_fetch_glass_illumination(fuv, n + i1), f);
    float finer = log2(CAUSTIX_GLASS_FOCUS_TEXELS / (2.0 * h)) - caustix_glass_lod(fuv);  // levels finer than the main texels
    e = mix(e, fine, clamp((1.0 - max(abs(d.x), abs(d.y))) * 10.0, 0.0, 1.0) * clamp(finer, 0.0, 1.0));
  }
  return e;
}

// The caustic map's irradiance at p: zero where p lies behind the first
// receiver surface the light sees there (the photons land on that one; a
// slope-scaled tolerance as for the caustics map). Not multiplied by the
// shadow maps: the photons found their own way (a mirror lights the floor
// its own wall shades from the sun).
//
// With a focus window (engine.h's LightBlock says where it lies)
// the main map fills the texture's lowest rows (t scaled by cmap_w.w), and
// inside the window's square the light of the photons that landed densely
// there is in the window's finer texels instead: the two add up. The
// window has mips, so that a focus finer than the pixel is averaged, not
// aliased; its level is taken before any pixel returns, so that the
// derivatives are alike across the pixels around the window's edge.
vec3 caustix_caustic_map_irradiance(vec3 p, vec3 n) {
  vec3 rel = p - caustix_light.cmap_origin.xyz;
  vec3 c = vec3(dot(rel, caustix_light.cmap_u.xyz), dot(rel, caustix_light.cmap_v.xyz), dot(rel, caustix_light.cmap_w.xyz));
  vec2 uv = 0.5 * (c.xz / caustix_light.cmap_half.xyz.xz + 1.0);
  float share = caustix_light.cmap_w.w;
  vec2 size = caustix_caustic_map_size();
  vec4 window = vec4(0.0);
  vec2 fuv = vec2(0.0), d = vec2(2.0);
  float lod = 0.0;
  if (share < 1.0) {
    window = caustix_caustic_map_texel(ivec2(size) - 1);  // (centre s, t, half-size, 1)
    float side = size.y - size.x;  // the window's texels a side
    d = (uv - window.xy) / max(window.z, 1e-30);
    fuv = (0.5 * (d + 1.0) * side + vec2(0.0, size.x)) / size;
    lod = caustix_caustic_map_lod(fuv);
  }
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return vec3(0.0);
  vec4 m = caustix_fetch_caustic_map(vec2(uv.x, min(uv.y * share, share - 0.5 / size.y)));
  float cos_t = abs(dot(n, caustix_light.cmap_v.xyz));
  float slope = sqrt(max(1.0 - cos_t * cos_t, 0.0)) / max(cos_t, 0.05);
  if (c.y < m.a - caustix_light.cmap_v.w - caustix_light.cmap_u.w * slope) return vec3(0.0);
  if (window.z <= 0.0 || max(abs(d.x), abs(d.y)) >= 1.0) return m.rgb;
  return m.rgb + caustix_fetch_caustic_map_lod(fuv, lod);
}

// Path length in water along the refracted light (eq. 4-17's d).
float caustix_water_path(vec3 p, vec3 travel) {
  return p.y < caustix_light.water.x ? (caustix_light.water.x - p.y) / max(-travel.y, 1e-4) : 0.0;
}

vec3 caustix_irradiance_from_light(vec3 p, vec3 n) {
  if (caustix_light.mode.x == 2) {
    vec3 rel = p - caustix_light.frame_origin.xyz;
    vec3 c = vec3(dot(rel, caustix_light.frame_u.xyz), dot(rel, caustix_light.frame_v.xyz), dot(rel, caustix_light.frame_w.xyz));
    vec2 uv = 0.5 * (c.xz / caustix_light.frame_half.xyz.xz + 1.0);
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return vec3(0.0);
    // The position map holds the baker's 16-bit code of the first
    // surface's V (R16: code / 65535; 1 where there is none, which decodes
    // below every point of the frame).
    float front = caustix_light.frame_half.y - caustix_fetch_position(uv) * (2.0 * caustix_light.frame_half.y * (65535.0 / 65534.0));
    float cos_t = max(dot(n, caustix_light.frame_v.xyz), 0.0);
    // Behind its own first surface? The map holds the depth at its texel's
    // centre; within the texel a surface tilted against V departs from it by
    // up to half the texel's diagonal times tan(theta_t): a slope-scaled
    // tolerance on top of the windows' (coarse maps on slanted floors went
    // dark, docs/robustness.md).
    float slope = sqrt(max(1.0 - cos_t * cos_t, 0.0)) / max(cos_t, 0.05);
    if (c.y < front - caustix_light.frame_origin.w - caustix_light.frame_u.w * slope) return vec3(0.0);
    // Sum over the beams in the texel of I_c,i n.d_i / V.d_i, from the
    // map's (sum I_c,i, sum I_c,i d_i.U / d_i.V, sum I_c,i d_i.W / d_i.V).
    // Alpha is the receiver's presence (its filtered coverage where the map
    // is filtered): dividing by it keeps the empty texels beyond the
    // receiver's outline seen from the light from darkening its edge.
    vec4 m4 = caustix_fetch_caustics(uv);
    vec3 m = m4.a > 1e-3 ? m4.rgb / m4.a : m4.rgb;
    float e = max(m.r * dot(n, caustix_light.frame_v.xyz) + m.g * dot(n, caustix_light.frame_u.xyz) + m.b * dot(n, caustix_light.frame_w.xyz), 0.0);
    vec3 travel = -caustix_light.frame_v.xyz;
    vec3 tint = vec3(1.0);
    if (caustix_light.frame_v.w != 0.0) {
      vec3 c = caustix_fetch_caustics_color(uv);
      // Kept signed: a saturated spectral colour lies outside linear sRGB
      // (red is negative around 500 nm), as in the caustic maps; display
      // clamps. R > 0 wherever light arrives: every bin's mean weight is.
      tint = m4.r > 0.0 ? c / m4.r : vec3(0.0);
    }
    return caustix_light.light_color.rgb * tint * e * exp(-caustix_light.absorption.xyz * caustix_water_path(p, travel)) * caustix_shadow_visibility(p, n, caustix_light.frame_v.xyz);
  }
  vec3 l = caustix_light.mode.y == 1 ? caustix_light.light_direction.xyz : normalize(p - caustix_light.light_position.xyz);
  float e_in = caustix_light.mode.y == 1 ? caustix_light.light_color.w : caustix_light.light_color.w / max(dot(p - caustix_light.light_position.xyz, p - caustix_light.light_position.xyz), 1e-12);
  if (caustix_light.mode.y == 2) e_in *= caustix_spot_factor(l, caustix_light.light_direction.xyz, caustix_light.spot.xyz);
  if (caustix_light.mode.x == 1) {
    float cos_i = max(-l.y, 0.0);
    vec3 travel = caustix_light.mode.y == 1 ? caustix_light.refracted.xyz : refract(l, vec3(0.0, 1.0, 0.0), 1.0 / caustix_light.water.y);
    float cos_t = max(-travel.y, 1e-4);
    float beam = e_in * caustix_fresnel_transmittance(cos_i, caustix_light.water.y) * cos_i / cos_t;
    return caustix_light.light_color.rgb * beam * max(dot(n, -travel), 0.0) * exp(-caustix_light.absorption.xyz * caustix_water_path(p, travel)) *
           caustix_shadow_visibility(p, n, -travel);
  }
  float vis = caustix_shadow_visibility(p, n, -l);
  float glass_vis = caustix_light.mode.w != 0 ? caustix_shadow_visibility_in(true, p, n, -l) : 1.0;
  vec3 e = vec3(e_in * max(dot(n, -l), 0.0) * vis * glass_vis);
  // Eq. 2: light through glass, I_Q; other objects' shadows along the
  // unrefracted light direction (an approximation, docs/glass.md).
  if (caustix_light.mode.z != 0) e += caustix_glass_irradiance(p) * vis;
  if (caustix_light.cmap_origin.w != 0.0) e += caustix_caustic_map_irradiance(p, n);
  return caustix_light.light_color.rgb * e;
}

#ifndef CAUSTIX_ALL_RECEIVERS
vec3 caustix_irradiance(vec3 world_position, vec3 world_normal) {
  return caustix_irradiance_from_light(world_position, normalize(world_normal));
}

// The unit direction in which the bound light's light travels as it
// arrives at the point, for a specular lobe beside caustix_irradiance():
// the caustics map's frame axis under moving water (the mean direction:
// the waves spread it), refracted at the rest level under flat water, else
// straight from the light.
vec3 caustix_light_travel(vec3 world_position) {
  if (caustix_light.mode.x == 2) return -caustix_light.frame_v.xyz;
  vec3 l = caustix_light.mode.y == 1 ? caustix_light.light_direction.xyz : normalize(world_position - caustix_light.light_position.xyz);
  if (caustix_light.mode.x == 1) {
    return caustix_light.mode.y == 1 ? caustix_light.refracted.xyz : refract(l, vec3(0.0, 1.0, 0.0), 1.0 / caustix_light.water.y);
  }
  return l;
}
#else
int caustix_light_count() { return caustix_table_shape.y; }

// Light `light` at a point of object `receiver` (its index in the scene,
// Engine::scene().objects): what caustix_irradiance() gives after
// Engine::bind(receiver, light). Zero for an index out of range and for an
// object that is no receiver (transparent).
vec3 caustix_irradiance_at(vec3 world_position, vec3 world_normal, int receiver, int light) {
  if (receiver < 0 || receiver >= caustix_table_shape.x || light < 0 || light >= caustix_table_shape.y) return vec3(0.0);
  caustix_entry = receiver * caustix_table_shape.y + light;
  if (caustix_light.mode.y == 0) return vec3(0.0);
  return caustix_irradiance_from_light(world_position, normalize(world_normal));
}

// Every light's (Tipprasert 2006 eq. 4-20: the sum).
vec3 caustix_irradiance_all(vec3 world_position, vec3 world_normal, int receiver) {
  vec3 e = vec3(0.0);
  for (int li = 0; li < caustix_table_shape.y; ++li) e += caustix_irradiance_at(world_position, world_normal, receiver, li);
  return e;
}
#endif  // CAUSTIX_ALL_RECEIVERS

#endif  // !CAUSTIX_OPTICS_ONLY && !CAUSTIX_GLSL_LIGHTING
