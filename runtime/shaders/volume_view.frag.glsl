// volume_view.frag.glsl (after the lighting prefix and volume_common.glsl):
// the viewing pass (Pfeuti, "Viewing Pass"). Each pixel's camera ray is
// marched through the radiance grid, curved inside index grids as photons
// are, adding sigma_s-weighted radiance L = sum p(cos a) S T ds with the
// medium's phase function against the photons' mean direction, and the
// transmittance T = e^(-sum sigma_t ds); it stops behind the opaque scene
// (its depth at the point's pixel). Output: L x u_scale, plus the scene's
// colour x T when composited (blending adds further lights' L).
// Beyond the paper, one march serves kViewLights lights (volume.cpp's
// CAUSTIX_VIEW_LIGHTS, as many as the texture units 0-5 hold beside the
// index grids): the path, its transmittance, the grids and the scene's
// depth are the same for every light, only each light's source (and mean
// direction) is read per step; a scene with more lights draws the pass
// again for the next ones.
layout(location = 0, index = 0) out vec4 o_color;
// Compositing by dual-source blending (u_composite 2): the transmittance.
layout(location = 0, index = 1) out vec4 o_transmittance;

const int kViewLights = CAUSTIX_VIEW_LIGHTS;
// Per light: rgb S (volume_resolve), the focus grid after the radiance
// grid's slices; and its mean direction of travel, laid out alike.
layout(binding = CAUSTIX_GRID_UNITS) uniform sampler3D u_source[kViewLights];
#if CAUSTIX_DIRECTIONS
layout(binding = CAUSTIX_GRID_UNITS + CAUSTIX_VIEW_LIGHTS) uniform sampler3D u_direction[kViewLights];
#endif
// Per light: its focus grid's box (volume_common's u_focus_* for the
// photons of one light), and the view step inside it (metres).
uniform int u_light_focus_on[kViewLights];
uniform vec3 u_light_focus_lo[kViewLights], u_light_focus_hi[kViewLights];
uniform float u_light_step_focus[kViewLights];
layout(binding = 6) uniform sampler2D u_scene_depth;
layout(binding = 7) uniform sampler2D u_scene_color;
uniform mat4 u_view_proj, u_inv_view_proj;
uniform vec2 u_viewport_origin, u_viewport_size;
uniform int u_composite;        // 1: colour x T + L; 2: L, and T for blending over the colour; 0: L only
uniform int u_water_excluded;   // composite: the water's own attenuation is the water surface's
uniform float u_scale;
uniform float u_view_step;      // metres
uniform vec3 u_atlas;           // u_source's size in texels
uniform float u_step;           // voxels, in index grids
uniform int u_octree;
uniform int u_max_steps;

float rand(uvec2 p) {
  uint x = p.x * 1973u + p.y * 9277u + 26699u;
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
  return float(x >> 8) * (1.0 / 16777216.0);
}

// Whether x lies behind the opaque scene as the camera sees it (any point,
// such as one of a ray bent by an index grid).
bool behind_scene(vec3 x) {
  vec4 c = u_view_proj * vec4(x, 1.0);
  if (c.w <= 0.0) return false;
  vec3 ndc = c.xyz / c.w;
  vec2 uv = 0.5 * ndc.xy + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return false;
  return 0.5 * ndc.z + 0.5 > texture(u_scene_depth, uv).r;
}

bool in_focus_of(int l, vec3 x) {
  return u_light_focus_on[l] != 0 && all(greaterThanEqual(x, u_light_focus_lo[l])) && all(lessThanEqual(x, u_light_focus_hi[l]));
}

// Light l's source coordinate for x: its focus grid's where x lies in it,
// else the radiance grid's, each clamped to its own texel centres (the
// edge clamping of a texture of its own).
vec3 grid_coord(int l, vec3 x) {
  vec3 t;
  if (in_focus_of(l, x)) {
    vec3 lo = u_light_focus_lo[l], hi = u_light_focus_hi[l];
    t = clamp((x - lo) / (hi - lo) * vec3(u_focus_n), vec3(0.5), vec3(u_focus_n) - 0.5) + vec3(0.0, 0.0, u_grid_n.z);
  } else {
    t = clamp((x - u_grid_lo) / (u_grid_hi - u_grid_lo) * vec3(u_grid_n), vec3(0.5), vec3(u_grid_n) - 0.5);
  }
  return t / u_atlas;
}

// The view step at x: finer inside a light's focus grid (the finest of
// those x lies in), and a step outside them ends inside the first it
// would enter, `jitter` of a fine step past where the ray enters it
// (against banding there too).
float view_step_at(vec3 x, vec3 d, float jitter) {
  float inside = 1e30;
  for (int l = 0; l < kViewLights; ++l) {
    if (in_focus_of(l, x)) inside = min(inside, u_light_step_focus[l]);
  }
  if (inside < 1e30) return inside;
  float outside = u_view_step;
  for (int l = 0; l < kViewLights; ++l) {
    if (u_light_focus_on[l] == 0) continue;
    vec2 r = box_range(x, d, u_light_focus_lo[l], u_light_focus_hi[l]);
    if (r.y > r.x && r.x > 0.0) outside = min(outside, r.x + (1e-4 + jitter) * u_light_step_focus[l]);
  }
  return outside;
}

// The march's state: in-scatter, optical depth (all media; those the
// scene's colour takes), the Fresnel transmittance at object surfaces
// crossed, the path's length from the near plane, and, while no index grid
// has bent the ray, the length at which the pixel's straight ray meets the
// opaque scene.
vec3 L = vec3(0.0), tau = vec3(0.0), tau_scene = vec3(0.0);
float tr = 1.0, travelled = 0.0, scene_t = 0.0;
bool straight = true;

// Whether the step that ends at x, the path's length then `path`, ends
// behind the opaque scene. Along the pixel's own straight ray
// behind_scene(x) holds exactly where the length passes the scene's
// surface at this pixel (its depth is monotonic along the ray): one depth
// read a pixel instead of a projection and a read a step, until an index
// grid bends the ray.
bool ends_behind(vec3 x, float path) { return straight ? path > scene_t : behind_scene(x); }

// One step of the path, from x0 to x (length len, direction d0 at x0): its
// in-scatter and attenuation. clear: the caller knows that the step lies in
// no index grid and ends in front of the scene along the pixel's straight
// ray (a constant, so that the grids' and the scene's reads are not in the
// code at all).
void add_step(vec3 x0, vec3 x, vec3 d0, float len, const bool clear) {
  travelled += len;
  vec3 mid = 0.5 * (x0 + x);
  if (!clear && ends_behind(x, travelled)) {
    // Up to the surface: the part of the step in front of it.
    len *= 0.5;
    mid = x0 + 0.25 * (x - x0);
    travelled = 1e30;
  }
  bool wet = u_water_on != 0 && mid.y < u_water_level;
  Medium m = clear ? medium_outside_grids(mid, wet) : medium_at(mid, wet);
  if (any(greaterThan(m.ss, vec3(0.0)))) {
    if (in_box(mid, u_grid_lo, u_grid_hi)) {
      vec3 scattered = vec3(0.0);  // each light's source times its phase
      for (int l = 0; l < kViewLights; ++l) {
        vec3 gc = grid_coord(l, mid);
        vec3 S = texture(u_source[l], gc).rgb;
#if CAUSTIX_DIRECTIONS
        vec3 md = texture(u_direction[l], gc).xyz;
        float cos_a = dot(md, md) > 0.0 ? dot(normalize(md), -d0) : 0.0;
#else
        float cos_a = 0.0;
#endif
        scattered += phase_value(m, cos_a) * S;
      }
      // The step's own attenuation: the source at its midpoint.
      L += tr * scattered * exp(-(tau + 0.5 * m.st * len)) * len;
    }
  }
  tau += m.st * len;
  if (!(wet && u_water_excluded != 0)) tau_scene += m.st * len;
}

// The length of a straight step from x: the view step there, or the
// partial first step (`pending`, the start's jitter) when one is left.
float straight_len(vec3 x, vec3 d, float jitter, float pending) {
  float step_here = view_step_at(x, d, jitter);
  return pending > 0.0 ? min(pending, step_here) : step_here;
}

// Straight steps from x along d while they stay short of every index
// grid's box (its voxel coordinates are affine in x; less a margin for
// the two tests' rounding) and end in front of the scene: the steps the
// general step below would take, without its reads of the grids.
// pixel_ray: d is the pixel's own ray (a constant at each call).
void clear_steps(inout vec3 x, vec3 d, inout float pending, inout int it, float t1, float jitter, const bool pixel_ray) {
  float clear_to = pixel_ray ? scene_t : 1e30;
  for (int k = 0; k < kGlassCount; ++k) {
    vec2 rg = box_range(voxel_of(k, x), mat3(u_world_to_voxel[k]) * d, vec3(0.0), u_glass_size[k].xyz);
    if (rg.y > rg.x && rg.y > 0.0) clear_to = min(clear_to, travelled + max(rg.x, 0.0) - 1e-3 * u_view_step);
  }
  for (; it < u_max_steps && travelled < t1; ++it) {
    float len = straight_len(x, d, jitter, pending);
    if (travelled + len >= clear_to || (!pixel_ray && behind_scene(x + len * d))) break;
    pending = 0.0;
    vec3 x0 = x;
    x += len * d;
    add_step(x0, x, d, len, true);
  }
}

void main() {
  vec2 uv = (gl_FragCoord.xy - u_viewport_origin) / u_viewport_size;
  vec4 a = u_inv_view_proj * vec4(2.0 * uv - 1.0, -1.0, 1.0);
  vec4 b = u_inv_view_proj * vec4(2.0 * uv - 1.0, 1.0, 1.0);
  vec3 x = a.xyz / a.w;
  vec3 d = normalize(b.xyz / b.w - x);
  float far_t = length(b.xyz / b.w - x);
  vec4 s = u_inv_view_proj * vec4(2.0 * uv - 1.0, 2.0 * texture(u_scene_depth, uv).r - 1.0, 1.0);
  scene_t = dot(s.xyz / s.w - x, d);

  // Start where the ray meets the box of the media and index grids.
  vec3 lo = u_grid_lo, hi = u_grid_hi;
  if (u_fog_on != 0) { lo = min(lo, u_fog_lo); hi = max(hi, u_fog_hi); }
  if (u_water_on != 0) { lo = min(lo, u_water_lo); hi = max(hi, u_water_hi); }
  vec2 r = box_range(x, d, lo, hi);
  float t0 = max(r.x, 0.0), t1 = min(r.y, far_t);
  for (int g = 0; g < kGlassCount; ++g) {
    vec2 rg = box_range(voxel_of(g, x), mat3(u_world_to_voxel[g]) * d, vec3(0.0), u_glass_size[g].xyz);
    if (rg.y > rg.x) { t0 = min(t0, max(rg.x, 0.0)); t1 = max(t1, min(rg.y, far_t)); }
  }
  if (t1 > t0) {
    // Jittered start against banding (deterministic per pixel).
    float jitter = rand(uvec2(gl_FragCoord.xy));
    x += d * t0;
    travelled = t0;
    float pending = jitter * u_view_step;  // first sample after a partial step
    // Runs of steps, each a loop of its own: straight steps that stay
    // short of every index grid and of the scene's surface
    // (clear_steps), steps through a grid while the ray is in one, and
    // between them one step that may meet either. A rasteriser that shades
    // pixels in SIMD lanes (llvmpipe) runs a loop body's every branch for
    // all its lanes: one body for all steps paid for a grid's step (its
    // gradient's six reads), the grids' coverage and the scene's depth at
    // every step of every ray.
    int it = 0;
    vec3 u;
    while (it < u_max_steps && travelled < t1) {
      int g = glass_at(x, u);
      if (g >= 0) {
        bool crossed;
        do {
          straight = false;
          vec3 x0 = x, d0 = d;
          float t_s;
          float len = grid_march(g, u, x, d, u_step, u_octree != 0, view_step_at(x, d, jitter), t_s, crossed);
          tr *= t_s;
          add_step(x0, x, d0, len, false);
          ++it;
          if (crossed) break;
          g = glass_at(x, u);
        } while (it < u_max_steps && travelled < t1 && g >= 0);
        // The surface met: its normal once for all lanes that met it.
        if (crossed) tr *= surface_refract(g, x, d);
        continue;
      }
      // (Two copies: on the pixel's own ray the scene's surface is a
      // length; on a ray an index grid bent, each step's end is projected.)
      if (straight) {
        clear_steps(x, d, pending, it, t1, jitter, true);
      } else {
        clear_steps(x, d, pending, it, t1, jitter, false);
      }
      if (!(it < u_max_steps && travelled < t1)) break;
      float len = straight_len(x, d, jitter, pending);
      pending = 0.0;
      vec3 x0 = x;
      x += len * d;
      add_step(x0, x, d, len, false);
      ++it;
    }
  }
  o_transmittance = vec4(exp(-tau_scene), 0.0);
  if (u_composite == 2) {
    o_color = vec4(L * u_scale, 1.0);  // blended: L + dst x T, alpha 1
  } else if (u_composite != 0) {
    vec3 c = texelFetch(u_scene_color, ivec2(gl_FragCoord.xy - u_viewport_origin), 0).rgb;
    // The glass's own Fresnel is in its colour already (draw_glass); the
    // in-scatter behind its surfaces is seen through them (tr).
    o_color = vec4(c * exp(-tau_scene) + L * u_scale, 1.0);
  } else {
    o_color = vec4(L * u_scale, 1.0);
  }
}
