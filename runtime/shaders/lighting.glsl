// Shared by receiver.frag and irradiance.frag (prefixed with #version and
// optics.glsl by the renderer): the irradiance one light delivers to a receiver point.
//
// Modes, chosen per (object, light) by the renderer:
//  0 direct: no water between light and point (no water, object above it,
//    or light and object both under it): E_in cos(theta) * visibility.
//  1 flat water (method "none"): refraction and Fresnel through the flat
//    surface, no caustics: E_in T(theta_i) cos(theta_i)/cos(theta_t) * n.(-T)
//    * e^(-K d) * visibility.
//  2 caustics casting (seed 000 §4.6): the caustics map holds irradiance on
//    planes perpendicular to V (eq. 4-18); a point gets it times n.V (the
//    cos theta_t of eq. 4-18 for this surface), e^(-K d) (eq. 4-17), and its
//    visibility: not behind its own first surface (position map) and not in
//    another object's shadow.

uniform int u_light_mode;
uniform int u_light_type;        // 1 directional, 2 point
uniform vec3 u_light_direction;  // directional: unit direction of travel
uniform vec3 u_light_position;   // point
uniform vec3 u_light_color;
uniform float u_light_power;     // E0 (W/m^2) or I (W/sr)
uniform float u_water_level;
uniform float u_water_ior;
uniform vec3 u_absorption;       // K per metre
uniform vec3 u_refracted;        // directional: travel direction below flat water

uniform mat4 u_shadow_matrix;
uniform float u_shadow_far;
uniform float u_shadow_texel;
layout(binding = 0) uniform sampler2DShadow u_shadow_2d;
layout(binding = 1) uniform samplerCubeShadow u_shadow_cube;

layout(binding = 2) uniform sampler2D u_caustics_map;  // irradiance on planes perpendicular to V
layout(binding = 3) uniform sampler2D u_position_map;  // frame V of the first surface
uniform vec3 u_frame_origin;
uniform vec3 u_frame_U;
uniform vec3 u_frame_V;
uniform vec3 u_frame_W;
uniform vec3 u_frame_half;
uniform float u_self_tolerance;
uniform float u_position_half_diagonal;  // half a position-map texel's diagonal (metres)

// Glass (seed 002 §4.3): the receiver's illumination textures for this
// light, on planes perpendicular to the mean transmitted direction
// (u_glass_V points back along it), and the glass's own shadow maps, which
// take the direct light away where glass stands in its path.
uniform int u_glass_on;        // 1: illumination textures bound for this receiver
uniform int u_glass_shadows;   // 1: the scene has glass (its shadow maps are valid)
uniform vec3 u_glass_origin;
uniform vec3 u_glass_U;
uniform vec3 u_glass_V;
uniform vec3 u_glass_W;
uniform vec3 u_glass_half;
uniform int u_glass_planes;
uniform float u_glass_plane_v[16];  // decreasing: plane 0 nearest the light
uniform float u_glass_tolerance;
layout(binding = 4) uniform sampler2DArray u_glass_illumination;
layout(binding = 5) uniform sampler2D u_glass_target;
layout(binding = 6) uniform sampler2DShadow u_glass_shadow_2d;
layout(binding = 7) uniform samplerCubeShadow u_glass_shadow_cube;

float shadow_visibility_in(sampler2DShadow map_2d, samplerCubeShadow map_cube, vec3 p, vec3 n, vec3 to_light) {
  if (u_light_type == 2) {
    vec3 q = p + n * (0.01 * length(p - u_light_position));
    vec3 d = q - u_light_position;
    return texture(map_cube, vec4(d, length(d) / u_shadow_far - 0.002));
  }
  // Normal offset against acne, 3x3 PCF against aliasing.
  vec4 s = u_shadow_matrix * vec4(p + n * (1.5 * u_shadow_texel), 1.0);
  s.xyz /= s.w;
  if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0)))) return 1.0;
  float bias = 0.002 * (1.0 - max(dot(n, to_light), 0.0)) + 0.0005;
  vec2 texel = 1.0 / vec2(textureSize(map_2d, 0));
  float sum = 0.0;
  for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x)
      sum += texture(map_2d, vec3(s.xy + vec2(x, y) * texel, s.z - bias));
  return sum / 9.0;
}

// Opaque objects' shadow.
float shadow_visibility(vec3 p, vec3 n, vec3 to_light) { return shadow_visibility_in(u_shadow_2d, u_shadow_cube, p, n, to_light); }

// Seed 002 §4.3: the incident intensity at p from the illumination textures:
// zero where p lies behind the target's first surface as the virtual camera
// sees it (shadow), else interpolated between the two planes around p
// (d_i <= z_p < d_(i+1)), clamped at the outermost planes.
vec3 glass_irradiance(vec3 p) {
  vec3 rel = p - u_glass_origin;
  vec3 c = vec3(dot(rel, u_glass_U), dot(rel, u_glass_V), dot(rel, u_glass_W));
  vec2 uv = 0.5 * (c.xz / u_glass_half.xz + 1.0);
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return vec3(0.0);
  float front = texture(u_glass_target, uv).w;
  if (c.y < front - u_glass_tolerance) return vec3(0.0);
  int n = u_glass_planes;
  float layer = 0.0;
  if (n > 1 && c.y < u_glass_plane_v[0]) {
    layer = float(n - 1);
    for (int i = 0; i + 1 < n; ++i) {
      if (c.y >= u_glass_plane_v[i + 1]) {
        layer = float(i) + (u_glass_plane_v[i] - c.y) / max(u_glass_plane_v[i] - u_glass_plane_v[i + 1], 1e-12);
        break;
      }
    }
  }
  int i0 = int(floor(layer));
  int i1 = min(i0 + 1, n - 1);
  float f = layer - float(i0);
  return mix(texture(u_glass_illumination, vec3(uv, float(i0))).rgb, texture(u_glass_illumination, vec3(uv, float(i1))).rgb, f);
}

// Path length in water along the refracted light (eq. 4-17's d).
float water_path(vec3 p, vec3 travel) {
  return p.y < u_water_level ? (u_water_level - p.y) / max(-travel.y, 1e-4) : 0.0;
}

vec3 irradiance_from_light(vec3 p, vec3 n) {
  if (u_light_mode == 2) {
    vec3 rel = p - u_frame_origin;
    vec3 c = vec3(dot(rel, u_frame_U), dot(rel, u_frame_V), dot(rel, u_frame_W));
    vec2 uv = 0.5 * (c.xz / u_frame_half.xz + 1.0);
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return vec3(0.0);
    float front = texture(u_position_map, uv).r;
    float cos_t = max(dot(n, u_frame_V), 0.0);
    // Behind its own first surface? The map holds the depth at its texel's
    // centre; within the texel a surface tilted against V departs from it by
    // up to half the texel's diagonal times tan(theta_t): a slope-scaled
    // tolerance on top of the windows' (coarse maps on slanted floors went
    // dark, docs/robustness.md).
    float slope = sqrt(max(1.0 - cos_t * cos_t, 0.0)) / max(cos_t, 0.05);
    if (c.y < front - u_self_tolerance - u_position_half_diagonal * slope) return vec3(0.0);
    float e = texture(u_caustics_map, uv).r;
    vec3 travel = -u_frame_V;
    return u_light_color * e * cos_t * exp(-u_absorption * water_path(p, travel)) * shadow_visibility(p, n, u_frame_V);
  }
  vec3 l = u_light_type == 1 ? u_light_direction : normalize(p - u_light_position);
  float e_in = u_light_type == 1 ? u_light_power : u_light_power / max(dot(p - u_light_position, p - u_light_position), 1e-12);
  if (u_light_mode == 1) {
    float cos_i = max(-l.y, 0.0);
    vec3 travel = u_light_type == 1 ? u_refracted : refract(l, vec3(0.0, 1.0, 0.0), 1.0 / u_water_ior);
    float cos_t = max(-travel.y, 1e-4);
    float beam = e_in * fresnel_transmittance(cos_i, u_water_ior) * cos_i / cos_t;
    return u_light_color * beam * max(dot(n, -travel), 0.0) * exp(-u_absorption * water_path(p, travel)) *
           shadow_visibility(p, n, -travel);
  }
  float vis = shadow_visibility(p, n, -l);
  float glass_vis = u_glass_shadows != 0 ? shadow_visibility_in(u_glass_shadow_2d, u_glass_shadow_cube, p, n, -l) : 1.0;
  vec3 e = vec3(e_in * max(dot(n, -l), 0.0) * vis * glass_vis);
  // Eq. 2: light through glass, I_Q; other objects' shadows along the
  // unrefracted light direction (an approximation, docs/glass.md).
  if (u_glass_on != 0) e += glass_irradiance(p) * vis;
  return u_light_color * e;
}
