// Nearby-geometry refraction for the view through glass (prefixed with
// #version, caustix.glsl's optics and glass_environment.glsl;
// GlassView::kNearby). timofy 2009's
// image-space method for the camera's rays (Shah, Konttinen & Pattanaik
// 2007, "Caustics mapping: an image-space technique for real-time
// caustics", §3: the refracted ray's intersection with nearby geometry is
// estimated by iterating against positions rendered from the view point),
// with the object's far side taken from its back faces seen from the
// camera (Wyman 2005, "An approximate image-space approach for interactive
// refraction"), as the caustic maps take it from the light:
//  1. the view ray refracts into the glass at this fragment (exact Snell
//     and Fresnel with the interpolated normal);
//  2. the exit point: start where the back face lies behind this pixel and
//     step against the back faces' tangent plane at the point the ray has
//     reached, u_exit_iterations times (exact on a plane);
//  3. the ray refracts out (Fresnel); under total internal reflection it
//     leaves unrefracted without the exit's Fresnel (the blog's one-sided
//     refraction, as the caustic maps do);
//  4. the landing point: Shah's iteration d <- |P(x + d t) - x|, P the
//     scene's position (from its depth) where the point x + d t projects,
//     u_iterations times from the scene point behind the exit; rays that
//     leave the screen or meet only sky see the sky.
// Absorption along the path inside, exp(-sigma_a l).
// What is inside the glass (an insect in amber): where the opaque scene
// behind the pixel lies nearer than the exit point, step 4's iteration
// runs from the entry point along the refracted ray instead, and what it
// lands on within the glass is seen through the entry alone (its Fresnel
// transmittance, the tint once, exp(-sigma_a d) over the distance d to it).
// Dispersion: steps 1-4 run once per wavelength sample at the
// glass's index there, and the pixel is the sum of each sample's colour
// times its bin's RGB weight (one sample (1, 1, 1) at n_d without).
in vec3 v_world;
in vec3 v_normal;

layout(binding = 0) uniform sampler2D u_scene_color;
layout(binding = 1) uniform sampler2D u_scene_depth;
layout(binding = 2) uniform sampler2D u_back_position;
layout(binding = 3) uniform sampler2D u_back_normal;
// The back-face textures cover the glass's rectangle of the screen: uv
// (0..1 over the frame) minus xy, divided by zw.
uniform vec4 u_back_window;
uniform mat4 u_view_proj;
uniform mat4 u_inv_view_proj;
uniform vec3 u_eye;
uniform int u_wave_count;
uniform vec4 u_waves[32];  // xyz the sample's RGB weight, w the glass's index at its wavelength
uniform vec3 u_glass_absorption;
uniform vec3 u_glass_transmit = vec3(1.0);  // the surface's tint at the two crossings (Material::tint^2)
uniform int u_iterations;
uniform int u_exit_iterations;
uniform float u_march_length;  // how far scene_along marches for a start beyond the exit

out vec4 o_color;

// Screen coordinates of a world point; false behind the eye or off screen.
bool to_screen(vec3 p, out vec2 uv) {
  vec4 c = u_view_proj * vec4(p, 1.0);
  if (c.w <= 0.0) return false;
  vec2 ndc = c.xy / c.w;
  uv = ndc * 0.5 + 0.5;
  return all(lessThanEqual(abs(ndc), vec2(1.0)));
}

// The opaque scene's world position at uv; false where it shows sky.
bool scene_position(vec2 uv, out vec3 p) {
  float depth = texture(u_scene_depth, uv).r;
  if (depth >= 1.0) return false;
  vec4 w = u_inv_view_proj * vec4(vec3(uv, depth) * 2.0 - 1.0, 1.0);
  p = w.xyz / w.w;
  return true;
}

// What the ray from x along d sees first in the opaque scene.
vec3 scene_along(vec3 x, vec3 d) {
  vec2 uv;
  vec3 p;
  if (!to_screen(x, uv) || !scene_position(uv, p)) return glass_sky(d);
  float t = length(p - x);
  if (distance(p, u_eye) < distance(x, u_eye)) {
    // The surface behind x's pixel is in front of x (something inside the
    // glass, or in front of its far side): the iteration would start on
    // it. Start instead where a march through the depth buffer first
    // passes behind a surface beyond x (the table view's march).
    vec4 cs = u_view_proj * vec4(x, 1.0);
    float start = cs.z / cs.w * 0.5 + 0.5;
    const int kSteps = 32;
    t = -1.0;
    for (int k = 1; k <= kSteps && t < 0.0; ++k) {
      float s = u_march_length * float(k * k) / float(kSteps * kSteps);
      vec4 c = u_view_proj * vec4(x + d * s, 1.0);
      if (c.w <= 0.0) break;
      vec3 ndc = c.xyz / c.w;
      if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) break;
      float depth = texture(u_scene_depth, ndc.xy * 0.5 + 0.5).r;
      if (depth < 1.0 && depth >= start && ndc.z * 0.5 + 0.5 >= depth) t = s;
    }
    if (t < 0.0) return glass_sky(d);
  }
  for (int k = 0; k < u_iterations; ++k) {
    if (!to_screen(x + t * d, uv) || !scene_position(uv, p)) return glass_sky(d);
    t = length(p - x);
  }
  return to_screen(x + t * d, uv) ? texture(u_scene_color, uv).rgb : glass_sky(d);
}

// The back face behind frame coordinate uv (w 0: none).
vec4 back_position(vec2 uv) {
  vec2 b = (uv - u_back_window.xy) / u_back_window.zw;
  return all(greaterThanEqual(b, vec2(0.0))) && all(lessThanEqual(b, vec2(1.0))) ? texture(u_back_position, b) : vec4(0.0);
}
vec3 back_normal(vec2 uv) { return normalize(texture(u_back_normal, (uv - u_back_window.xy) / u_back_window.zw).xyz); }

// Steps 1-4 at index `ior`, with the sky seen by reflection: what the pixel
// shows at one wavelength.
vec3 shade(vec3 n, vec3 view, float ior, vec3 sky_reflected) {
  float cos_i = max(-dot(view, n), 0.0);
  float reflectance = 1.0 - caustix_fresnel_transmittance(cos_i, ior);

  // 1. Into the glass.
  vec3 t1 = refract(view, n, 1.0 / ior);
  vec3 transmitted = vec3(1.0 - reflectance);
  // 2. The exit point against the back faces.
  vec3 x = v_world;
  vec2 uv;
  float t = 0.0;
  vec3 ne = -n;
  if (to_screen(x, uv)) {
    vec4 bp = back_position(uv);
    if (bp.w > 0.5) {
      t = max(dot(bp.xyz - x, t1), 0.0);
      ne = back_normal(uv);
    }
  }
  for (int k = 0; k < u_exit_iterations; ++k) {
    if (!to_screen(x + t * t1, uv)) break;
    vec4 bp = back_position(uv);
    if (bp.w < 0.5) break;
    vec3 nb = back_normal(uv);
    float dn = dot(t1, nb);
    if (dn < 1e-3) break;  // the back face must face away from the ray
    ne = nb;
    t = max(dot(bp.xyz - x, nb) / dn, 0.0);
  }
  // Something inside, nearer than the exit.
  vec3 p_in;
  if (to_screen(x, uv) && scene_position(uv, p_in) && length(p_in - x) < t) {
    float d = length(p_in - x);
    bool lands = true;
    for (int k = 0; k < u_iterations && lands; ++k) {
      lands = to_screen(x + d * t1, uv) && scene_position(uv, p_in);
      if (lands) d = length(p_in - x);
    }
    // Landed on the ray (not on a surface only behind it on screen, the
    // floor under a ball), within the glass.
    lands = lands && length(p_in - (x + d * t1)) < 0.02 * t + 1e-4;
    if (lands && d < t && to_screen(x + d * t1, uv)) {
      return reflectance * sky_reflected + transmitted * sqrt(u_glass_transmit) * exp(-u_glass_absorption * d) * texture(u_scene_color, uv).rgb;
    }
  }
  vec3 exit_point = x + t * t1;
  transmitted *= exp(-u_glass_absorption * t) * u_glass_transmit;
  // 3. Out of the glass (ne outward; the ray leaves through it).
  vec3 nin = dot(ne, t1) > 0.0 ? -ne : ne;
  vec3 t2 = refract(t1, nin, ior);
  if (dot(t2, t2) == 0.0) {
    t2 = t1;  // total internal reflection: one-sided refraction
  } else {
    transmitted *= caustix_fresnel_transmittance(-dot(t1, nin), 1.0 / ior);
  }
  // 4. What the exit ray meets.
  return reflectance * sky_reflected + transmitted * scene_along(exit_point, normalize(t2));
}

void main() {
  vec3 n = normalize(v_normal);
  vec3 view = normalize(v_world - u_eye);
  if (dot(n, view) > 0.0) n = -n;
  vec3 sky_reflected = glass_sky_reflected(reflect(view, n));  // the same at every wavelength
  vec3 c = vec3(0.0);
  for (int k = 0; k < u_wave_count; ++k) c += u_waves[k].xyz * shade(n, view, u_waves[k].w, sky_reflected);
  o_color = vec4(c, 1.0);
}
