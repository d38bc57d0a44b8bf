// volume_photons.comp.glsl (after the lighting prefix and volume_common.glsl):
// photon generation and marching (Pfeuti, "Photon Generation", "Photon
// Marching"), one invocation per photon of one light. Each photon's power
// decays by e^(-sigma_t s) in every medium; what it loses to scattering is
// deposited into the radiance grid by exact voxel traversal (a
// track-length estimate), shared across the track by the photon's
// footprint, with its direction of travel where a phase function needs
// it, as fixed-point integers (GL 4.5 has integer atomics only). Photons
// stop on opaque surfaces (the light's shadow map), leave the media, or
// run out of steps.
layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Accumulator { int acc[]; };  // 6 per voxel: rgb scattered power, luminance-weighted direction
// 0 in, 1 scattered, 2 absorbed, 3 leaving, 4 reflected, 5 truncated
// (fixed point); 6/7 steps, 8/9 steps in index grids (uint, low/high).
layout(std430, binding = 1) buffer Tally { uint tally[]; };
layout(std430, binding = 2) readonly buffer WaterPositions { vec4 water_pos[]; };
layout(std430, binding = 3) readonly buffer WaterNormals { vec4 water_nrm[]; };

uniform uint u_side;           // photons per axis
uniform uint u_seed;
uniform int u_source;          // 0: the light's window at y = u_window_y; 1: the water surface; 2: the lens's square
uniform vec4 u_window;         // x0, z0, x1, z1 (source 0); the water's extent (source 1)
uniform float u_window_y;
// The lens's square (source 2, and the rays of source 0 it takes): centre,
// half-side vectors across the light, and its normal (towards the light's
// travel). It turns with the light about the lens's centre, so that a
// photon's path through the lens stays where it was as the light turns
// (docs/volume.md, "Photon generation").
uniform int u_square_on;
uniform vec3 u_square_c, u_square_u, u_square_v, u_square_n;
uniform uvec2 u_water_cells;
uniform float u_water_ior;
uniform vec3 u_light_color;    // linear colour x E0 (directional) or I (point), / E0 of the scene
uniform float u_scale;         // fixed-point units per unit of scattered power
uniform float u_tally_scale;   // fixed-point units per unit of tallied power
uniform float u_step;          // voxels, in index grids
uniform int u_octree;
uniform int u_max_steps;
// The photon's footprint across its track (metres): its source cell's
// width along x and z, the square root of its area along y.
vec3 foot;
uniform float u_eps;           // metres: pushes a ray past a boundary it reached

float rand(uint x) {
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
  return float(x >> 8) * (1.0 / 16777216.0);
}

bool occluded(vec3 x) {
  if (caustix_light.mode.y == 2) {
    vec3 d = x - caustix_light.light_position.xyz;
    return texture(caustix_shadow_cube, vec4(d, length(d) / caustix_light.water.z - 0.002)) < 0.5;
  }
  vec4 s = caustix_light.world_to_shadow * vec4(x, 1.0);
  s.xyz /= s.w;
  if (any(lessThan(s.xyz, vec3(0.0))) || any(greaterThan(s.xyz, vec3(1.0)))) return false;
  return texture(caustix_shadow_2d, vec3(s.xy, s.z - 0.002)) < 0.5;
}

// Stochastic rounding: unbiased however small a deposit is against the
// fixed-point unit.
uint g_rng;
float next_random() {
  g_rng ^= g_rng << 13; g_rng ^= g_rng >> 17; g_rng ^= g_rng << 5;
  return float(g_rng >> 8) * (1.0 / 16777216.0);
}
void add_fixed(int i, float v) {
  int q = int(floor(v * u_scale + next_random()));
  if (q != 0) atomicAdd(acc[i], q);
}

// Length to the next boundary ahead along the straight ray: a face of the
// radiance grid, the medium box, the water or an index grid; -1 if none.
float next_event(vec3 x, vec3 d, bool wet) {
  float t = 1e30;
  vec2 r = box_range(x, d, u_grid_lo, u_grid_hi);
  if (r.y > r.x) t = min(t, r.x > 0.0 ? r.x : (r.y > 0.0 ? r.y : 1e30));
  if (u_fog_on != 0) {
    r = box_range(x, d, u_fog_lo, u_fog_hi);
    if (r.y > r.x) t = min(t, r.x > 0.0 ? r.x : (r.y > 0.0 ? r.y : 1e30));
  }
  if (u_water_on != 0) {
    r = box_range(x, d, u_water_lo, u_water_hi);
    if (r.y > r.x) t = min(t, r.x > 0.0 ? r.x : (r.y > 0.0 ? r.y : 1e30));
  }
  for (int g = 0; g < kGlassCount; ++g) {
    r = box_range(voxel_of(g, x), mat3(u_world_to_voxel[g]) * d, vec3(0.0), u_glass_size[g].xyz);
    if (r.y > r.x && r.x > 0.0) t = min(t, r.x);
  }
  return t >= 1e29 ? -1.0 : t + u_eps;
}

// A photon stands for the beam through its cell of the source window,
// `foot` voxels wide across its track (at most 1 is used). Returns, of a
// footprint centred at t along an axis of its voxel (which spans [0, 1]),
// the share in the nearer neighbour (x) and that neighbour's offset, -1 or
// +1 (y). In its voxel alone, a track nearly parallel to a grid axis moved
// all its light to the next column of voxels at once as it drifted across
// their face, and the in-scatter changed by steps as the light turned;
// shared by its footprint, the light moves over as the track does.
vec2 footprint_share(float t, float foot) {
  float f = clamp(foot, 1e-4, 1.0);
  return t < 0.5 ? vec2(max(0.5 * f - t, 0.0) / f, -1.0) : vec2(max(t + 0.5 * f - 1.0, 0.0) / f, 1.0);
}

// In the focus grid the glass's photons have converged: their beams are
// narrower than their source cells (a footprint the cell's width took
// fog_ball's focal line peak from -6 % to -8 % of the optics'), and a
// quarter of the cell, narrower than a focus voxel, gave a voxel a share
// that rose from 0 to all of a track's light over half a voxel, with kinks
// at both ends, while the focal line moves 0.6 of a voxel a frame under a
// sun turning 0.2 degrees a frame. There a track's light goes to the two
// voxel centres around it along each axis across it by the cubic
// 1 - 3 d^2 + 2 |d|^3 of its distance d from them (in voxels; as photon
// splatting's filter): the shares move with the track with no kink, and
// the line keeps its peak (-6.9 % of optics against -6.1 %; docs/volume.md).
// Returns what footprint_share does.
vec2 smooth_share(float t) {
  float dd = abs(t - 0.5);
  return vec2(dd * dd * (3.0 - 2.0 * dd), t < 0.5 ? -1.0 : 1.0);
}

// The accumulator index of voxel c of a grid of n voxels whose first is at
// `base`.
int voxel_at(ivec3 c, ivec3 n, int base) { return base + 6 * ((c.z * n.y + c.y) * n.x + c.x); }

void deposit_voxel(int v, vec3 sc, vec3 d) {
  add_fixed(v, sc.r);
  add_fixed(v + 1, sc.g);
  add_fixed(v + 2, sc.b);
  if (!kDirections) return;
  float l = luminance(sc);
  add_fixed(v + 3, l * d.x);
  add_fixed(v + 4, l * d.y);
  add_fixed(v + 5, l * d.z);
}

// Deposits sigma_s x power x length of the chord o + s d, s in [a, b],
// into every voxel of the grid over [lo, hi] (n voxels, its first at
// `base` in the accumulator) that it crosses (Amanatides-Woo traversal,
// the exact decay in each voxel), p the power at s = 0, each piece
// shared with its neighbours across the track by the photon's footprint
// (its source cell's), or by smooth_share where `smooth_kernel` is set (the
// focus grid). With `stop_at_surfaces`
// it ends where an opaque surface is met and returns that s, else b.
float deposit(vec3 o, vec3 d, float a, float b, vec3 lo, vec3 hi, ivec3 n, int base, vec3 p, Medium m, bool stop_at_surfaces, bool smooth_kernel) {
  vec3 h = (hi - lo) / vec3(n);
  vec3 ad = abs(d);
  int main_axis = ad.x >= ad.y && ad.x >= ad.z ? 0 : (ad.y >= ad.z ? 1 : 2);
  int a1 = main_axis == 0 ? 1 : 0, a2 = main_axis == 2 ? 1 : 2;  // the axes across the track
  vec2 width = vec2(foot[a1] / h[a1], foot[a2] / h[a2]);  // the footprint, voxels
  vec3 start = o + d * (0.5 * (a + min(b, a + 1e-6)));
  ivec3 cell = clamp(ivec3(floor((start - lo) / h)), ivec3(0), n - 1);
  ivec3 stp;
  vec3 next, delta;
  for (int k = 0; k < 3; ++k) {
    stp[k] = d[k] > 0.0 ? 1 : -1;
    if (abs(d[k]) < 1e-12) {
      next[k] = 1e30;
      delta[k] = 1e30;
    } else {
      float boundary = lo[k] + (float(cell[k]) + (d[k] > 0.0 ? 1.0 : 0.0)) * h[k];
      next[k] = (boundary - o[k]) / d[k];
      delta[k] = h[k] / abs(d[k]);
    }
  }
  float s = a;
  for (int guard = 0; guard < 4096 && s < b; ++guard) {
    int axis = next.x < next.y ? (next.x < next.z ? 0 : 2) : (next.y < next.z ? 1 : 2);
    float e = min(next[axis], b);
    if (e > s) {
      if (stop_at_surfaces && occluded(o + d * e)) return s;
      vec3 sc = m.ss * power_length(p, m.st, s, e);
      // The footprint's shares across the track at the piece's midpoint:
      // the neighbour on the nearer side in each of the two axes across
      // the track's main one, kept in the piece's voxel at the grid's side.
      vec3 t = (o + d * (0.5 * (s + e)) - lo) / h - vec3(cell);
      vec2 fa = smooth_kernel ? smooth_share(t[a1]) : footprint_share(t[a1], width.x);
      vec2 fb = smooth_kernel ? smooth_share(t[a2]) : footprint_share(t[a2], width.y);
      ivec3 ca = cell, cb = cell;
      ca[a1] += int(fa.y);
      cb[a2] += int(fb.y);
      if (ca[a1] < 0 || ca[a1] >= n[a1]) fa.x = 0.0;
      if (cb[a2] < 0 || cb[a2] >= n[a2]) fb.x = 0.0;
      ivec3 cab = ca;
      cab[a2] = cb[a2];
      deposit_voxel(voxel_at(cell, n, base), (1.0 - fa.x) * (1.0 - fb.x) * sc, d);
      if (fa.x > 0.0) deposit_voxel(voxel_at(ca, n, base), fa.x * (1.0 - fb.x) * sc, d);
      if (fb.x > 0.0) deposit_voxel(voxel_at(cb, n, base), (1.0 - fa.x) * fb.x * sc, d);
      if (fa.x > 0.0 && fb.x > 0.0) deposit_voxel(voxel_at(cab, n, base), fa.x * fb.x * sc, d);
    }
    s = e;
    cell[axis] += stp[axis];
    next[axis] += delta[axis];
    if (cell[axis] < 0 || cell[axis] >= n[axis]) break;
  }
  return b;
}

// The chord o + s d, s in [0, len], in medium m with power p at s = 0:
// deposits into the radiance grid (and the focus grid where it crosses
// it), stops where an opaque surface is met, and leaves p attenuated at
// its end. `along_light`: the chord lies on a ray from the light (the
// photon has not been refracted). Returns whether a surface stopped it.
bool march_chord(vec3 o, vec3 d, float len, bool along_light, inout vec3 p, Medium m, inout float scattered, inout float absorbed) {
  float end = len;
  bool blocked = false;
  vec2 r = box_range(o, d, u_grid_lo, u_grid_hi);
  float a = max(r.x, 0.0), b = min(r.y, len);
  if (any(greaterThan(m.ss, vec3(0.0))) && b > a) {
    // Along one of the light's own rays every point has the same shadow
    // map coordinates and depth grows, so if the chord's end is lit all of
    // it is, and its voxels need no test each.
    bool test_each = !along_light || occluded(o + d * b);
    float stop = deposit(o, d, a, b, u_grid_lo, u_grid_hi, u_grid_n, 0, p, m, test_each, false);
    if (stop < b) {
      end = stop;
      blocked = true;
    }
    if (u_focus_on != 0) {
      vec2 f = box_range(o, d, u_focus_lo, u_focus_hi);
      float fa = max(f.x, 0.0), fb = min(f.y, min(end, b));
      if (fb > fa) deposit(o, d, fa, fb, u_focus_lo, u_focus_hi, u_focus_n, 6 * u_grid_n.x * u_grid_n.y * u_grid_n.z, p, m, false,
                              true);
    }
  }
  if (!blocked && occluded(o + d * len)) blocked = true;
  vec3 after = p * exp(-m.st * end);
  vec3 lost = p - after;
  vec3 ratio = vec3(m.st.r > 0.0 ? m.ss.r / m.st.r : 0.0, m.st.g > 0.0 ? m.ss.g / m.st.g : 0.0, m.st.b > 0.0 ? m.ss.b / m.st.b : 0.0);
  scattered += luminance(lost * ratio);
  absorbed += luminance(lost * (1.0 - ratio));
  p = after;
  return blocked;
}

void tally_add(int i, float v) {
  uint q = uint(max(floor(v * u_tally_scale + 0.5), 0.0));
  if (q != 0u) atomicAdd(tally[i], q);
}

void count_add(int i, uint n) {
  uint old = atomicAdd(tally[i], n);
  if (old + n < old) atomicAdd(tally[i + 1], 1u);
}

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= u_side * u_side) return;
  uint ix = id % u_side, iz = id / u_side;
  g_rng = (id + 1u) * 0x9E3779B9u ^ u_seed;
  if (g_rng == 0u) g_rng = 1u;
  // Stratified: one photon per cell of a side x side grid, jittered.
  vec2 f = (vec2(ix, iz) + vec2(rand(id * 2u + u_seed), rand(id * 2u + 1u + u_seed * 7919u))) / float(u_side);
  vec2 xz = mix(u_window.xy, u_window.zw, f);
  float area = (u_window.z - u_window.x) * (u_window.w - u_window.y) / float(u_side * u_side);
  vec2 cell_size = (u_window.zw - u_window.xy) / float(u_side);
  foot = vec3(cell_size.x, sqrt(area), cell_size.y);
  bool point = caustix_light.mode.y == 2;
  vec3 lp = caustix_light.light_position.xyz;
  vec3 x, d;
  vec3 p;
  bool wet = false;
  bool along_light = true;  // until refracted
  if (u_source == 0) {
    x = vec3(xz.x, u_window_y, xz.y);
    d = point ? normalize(x - lp) : caustix_light.light_direction.xyz;
    if (u_square_on != 0) {
      // Where this ray crosses the lens's square, the square's photons
      // stand for it.
      vec3 q = x + d * (dot(u_square_c - x, u_square_n) / dot(d, u_square_n)) - u_square_c;
      if (abs(dot(q, u_square_u)) < dot(u_square_u, u_square_u) && abs(dot(q, u_square_v)) < dot(u_square_v, u_square_v)) return;
    }
    float e = point ? abs(d.y) / dot(x - lp, x - lp) * caustix_spot_factor(d, caustix_light.light_direction.xyz, caustix_light.spot.xyz) : abs(d.y);
    p = u_light_color * (e * area);
  } else if (u_source == 2) {
    // A cell of the square across the light, the ray through it started
    // back at the window's height: power = the light's intensity x the
    // cell's solid angle (a point) or irradiance x its area (the sun).
    vec3 q = u_square_c + (2.0 * f.x - 1.0) * u_square_u + (2.0 * f.y - 1.0) * u_square_v;
    area = 4.0 * length(u_square_u) * length(u_square_v) / float(u_side * u_side);
    foot = vec3(2.0 * length(u_square_u) / float(u_side), sqrt(area), 2.0 * length(u_square_v) / float(u_side));
    d = point ? normalize(q - lp) : caustix_light.light_direction.xyz;
    x = q + d * ((u_window_y - q.y) / d.y);
    float e = point ? abs(dot(d, u_square_n)) / dot(q - lp, q - lp) * caustix_spot_factor(d, caustix_light.light_direction.xyz, caustix_light.spot.xyz) : 1.0;
    p = u_light_color * (e * area);
  } else {
    // On the water surface as the caustics see it this frame (Pfeuti:
    // photons start at the surface, refracted, with Fresnel).
    vec2 c = f * vec2(u_water_cells);
    uvec2 c0 = uvec2(min(floor(c), vec2(u_water_cells) - 1.0));
    vec2 t = c - vec2(c0);
    uint nx = u_water_cells.x + 1u;
    uint i00 = c0.y * nx + c0.x, i10 = i00 + 1u, i01 = i00 + nx, i11 = i01 + 1u;
    float y = mix(mix(water_pos[i00].y, water_pos[i10].y, t.x), mix(water_pos[i01].y, water_pos[i11].y, t.x), t.y);
    vec3 n = normalize(mix(mix(water_nrm[i00].xyz, water_nrm[i10].xyz, t.x), mix(water_nrm[i01].xyz, water_nrm[i11].xyz, t.x), t.y));
    x = vec3(xz.x, y, xz.y);
    vec3 din = point ? normalize(x - lp) : caustix_light.light_direction.xyz;
    float cos_i = -dot(din, n);
    if (point && lp.y <= y) return;
    if (cos_i <= 0.0) return;
    float e = point ? abs(din.y) / dot(x - lp, x - lp) * caustix_spot_factor(din, caustix_light.light_direction.xyz, caustix_light.spot.xyz) : abs(din.y);
    float tr = 1.0 - caustix_fresnel_reflectance(cos_i, 1.0 / u_water_ior);
    d = refract(din, n, 1.0 / u_water_ior);
    p = u_light_color * (e * area * tr);
    wet = true;
    along_light = false;
  }

  float t_in = 0.0, t_sc = 0.0, t_ab = 0.0, t_lv = 0.0, t_rf = 0.0, t_tr = 0.0;
  uint steps = 0u, grid_steps = 0u;
  bool in_medium = false;
  float p_start = luminance(p);
  int it = 0;
  // Runs of steps, each ended where the photon stops or meets an object's
  // surface (refraction at the surface: grid_march); the surface's normal
  // is taken after the run, once for all lanes that met it, not at every
  // step that some lane of a SIMD rasteriser's meets one.
  int crossed_grid;
  do {
    crossed_grid = -1;
    for (; it < u_max_steps; ++it) {
      vec3 u;
      int g = glass_at(x, u);
      vec3 x0 = x, d0 = d;
      float tr = 1.0;
      bool crossed = false;
      if (g >= 0) {
        grid_march(g, u, x, d, u_step, u_octree != 0, 1e30, tr, crossed);
        along_light = false;
        ++grid_steps;
      } else {
        float len = next_event(x, d, wet);
        if (len < 0.0) break;
        x += len * d;
      }
      ++steps;
      vec3 chord = x - x0;
      float len = length(chord);
      vec3 cd = len > 0.0 ? chord / len : d0;
      Medium m = medium_at(x0 + 0.5 * chord, wet);
      bool blocked;
      if (any(greaterThan(m.st, vec3(0.0)))) {
        if (!in_medium) t_in += luminance(p);
        in_medium = true;
        blocked = march_chord(x0, cd, len, along_light, p, m, t_sc, t_ab);
      } else {
        if (in_medium) t_lv += luminance(p);
        in_medium = false;
        blocked = occluded(x);
      }
      if (blocked) break;
      if (tr < 1.0) {
        if (in_medium) t_rf += luminance(p) * (1.0 - tr);
        p *= tr;
      }
      // Light above the water stops where it reaches it (the water's own
      // photons start at its surface).
      if (u_water_on != 0 && !wet && in_box(x, u_water_lo, u_water_hi)) break;
      if (luminance(p) < 1e-7 * p_start) break;
      if (crossed) {
        crossed_grid = g;
        ++it;
        break;
      }
    }
    if (crossed_grid >= 0) {
      float tr = surface_refract(crossed_grid, x, d);
      if (in_medium) t_rf += luminance(p) * (1.0 - tr);
      p *= tr;
    }
  } while (crossed_grid >= 0);
  if (in_medium) {
    if (it >= u_max_steps) t_tr += luminance(p);
    else t_lv += luminance(p);
  }
  tally_add(0, t_in);
  tally_add(1, t_sc);
  tally_add(2, t_ab);
  tally_add(3, t_lv);
  tally_add(4, t_rf);
  tally_add(5, t_tr);
  count_add(6, steps);
  count_add(8, grid_steps);
}
