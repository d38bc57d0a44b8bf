// The glass's colour (prefixed with #version, caustix.glsl's optics and
// glass_environment.glsl): Fresnel
// reflection of the sky plus the transmitted view ray's scene colour. The
// exit ray from the table is marched through the opaque scene's depth
// buffer in screen space (the first sample behind the stored depth is the
// nearby geometry seen through the glass); rays that leave the screen or
// hit nothing see the sky.
//
// What is inside the glass (an insect in amber; u_inside where a receiver's
// box meets the glass's): the view ray refracted at the entry point is
// marched as far as the exit point lies, and the first opaque surface it
// passes behind is seen through the entry's Fresnel transmittance, the
// tint once and Beer-Lambert absorption over the distance to it,
// e^(-sigma t) (KHR_materials_volume). The straight chord stands in for
// the ray's first segment inside, which the table does not store: exact
// for a convex object.
in vec3 v_world;
in vec3 v_normal;
in vec3 v_exit;
in vec3 v_exit_dir;
in vec3 v_transmitted;

layout(binding = 0) uniform sampler2D u_scene_color;
layout(binding = 1) uniform sampler2D u_scene_depth;
uniform mat4 u_view_proj;
uniform mat4 u_inv_view_proj;
uniform vec3 u_eye;
uniform float u_ior;
uniform float u_march_length;
uniform int u_inside;                       // 1: a receiver may be inside this glass
uniform vec3 u_glass_absorption;            // sigma, 1/m per channel
uniform vec3 u_glass_transmit = vec3(1.0);  // tint^2 (two crossings)

out vec4 o_color;

vec3 scene_along(vec3 o, vec3 d) {
  const int kSteps = 48;
  // A surface nearer the camera than the exit point is not what the exit
  // ray meets (it starts behind it): an object inside the glass, or in
  // front of its far side, would otherwise be "hit" at the first sample
  // wherever it covers the exit point's pixel (an insect in
  // amber turned the whole block black). What is inside is found before
  // this, from the entry point (scene_inside).
  vec4 cs = u_view_proj * vec4(o, 1.0);
  float start = cs.w > 0.0 ? cs.z / cs.w * 0.5 + 0.5 : 0.0;
  for (int k = 1; k <= kSteps; ++k) {
    float t = u_march_length * float(k * k) / float(kSteps * kSteps);  // denser near the glass
    vec4 c = u_view_proj * vec4(o + d * t, 1.0);
    if (c.w <= 0.0) break;
    vec3 ndc = c.xyz / c.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) break;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    float depth = texture(u_scene_depth, uv).r;
    if (depth < 1.0 && depth >= start && ndc.z * 0.5 + 0.5 >= depth) return texture(u_scene_color, uv).rgb;
  }
  return glass_sky(d);
}

// Whether the point p lies behind the opaque scene by at most `thickness`
// (metres along the view ray; that surface beyond `start`, the entry
// point's depth), and where p falls on screen. The thickness keeps a ray
// that merely passes behind an object, in its shadow from the camera, from
// taking it for a hit.
bool behind_scene(vec3 p, float start, float thickness, out vec2 uv) {
  vec4 c = u_view_proj * vec4(p, 1.0);
  vec3 ndc = c.xyz / max(c.w, 1e-9);
  uv = ndc.xy * 0.5 + 0.5;
  float depth = texture(u_scene_depth, uv).r;
  if (c.w <= 0.0 || any(greaterThan(abs(ndc.xy), vec2(1.0))) || depth >= 1.0 || depth <= start || ndc.z * 0.5 + 0.5 < depth) return false;
  vec4 s = u_inv_view_proj * vec4(vec3(uv, depth) * 2.0 - 1.0, 1.0);
  return distance(p, u_eye) - distance(s.xyz / s.w, u_eye) <= thickness;
}

// The first opaque surface the ray o + d t passes behind for 0 < t <= len,
// and its t (24 steps, then 6 halvings of the step that crossed it); t < 0
// where there is none.
vec4 scene_inside(vec3 o, vec3 d, float len) {
  const int kSteps = 24;
  vec4 cs = u_view_proj * vec4(o, 1.0);
  float start = cs.z / cs.w * 0.5 + 0.5;
  float thickness = 1.5 * len / float(kSteps);
  vec2 uv;
  for (int k = 1; k <= kSteps; ++k) {
    float t = len * float(k) / float(kSteps);
    if (!behind_scene(o + d * t, start, thickness, uv)) continue;
    float lo = t - len / float(kSteps), hi = t;
    vec2 at;
    for (int i = 0; i < 6; ++i) {
      float mid = 0.5 * (lo + hi);
      if (behind_scene(o + d * mid, start, thickness, at)) {
        hi = mid;
        uv = at;
      } else {
        lo = mid;
      }
    }
    return vec4(texture(u_scene_color, uv).rgb, hi);
  }
  return vec4(0.0, 0.0, 0.0, -1.0);
}

void main() {
  vec3 n = normalize(v_normal);
  vec3 view = normalize(v_world - u_eye);
  if (dot(n, view) > 0.0) n = -n;
  float cos_i = max(dot(-view, n), 0.0);
  float r = 1.0 - caustix_fresnel_transmittance(cos_i, u_ior);
  vec3 reflected = glass_sky_reflected(reflect(view, n));
  if (u_inside != 0) {
    vec3 d = refract(view, n, 1.0 / u_ior);
    vec4 hit = scene_inside(v_world, d, distance(v_world, v_exit));
    if (hit.w >= 0.0) {
      vec3 kept = (1.0 - r) * sqrt(u_glass_transmit) * exp(-u_glass_absorption * hit.w);
      o_color = vec4(r * reflected + kept * hit.rgb, 1.0);
      return;
    }
  }
  o_color = vec4(r * reflected + v_transmitted * scene_along(v_exit, normalize(v_exit_dir)), 1.0);
}
