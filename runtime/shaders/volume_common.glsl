// volume_common.glsl: the scene's media as photon marching and the viewing
// pass see them (Pfeuti, Sun et al. 2008; docs/volume.md). Follows the
// engine's lighting prefix (caustix.glsl: Fresnel, the light's block and
// shadow maps); volume.cpp sets every uniform.

// ---- transparent objects: index grids (Pfeuti "Voxelization") ----
const int kMaxGlass = 4;
// The number of objects' index grids, fixed when the programs are built
// (volume.cpp defines CAUSTIX_GLASS_COUNT): a scene without any has no
// grid code at all, and with one its sampler is read at a constant index.
// (llvmpipe runs every branch of a body for all its SIMD lanes, taken or
// not, and reads a sampler array at a run-time index at several times a
// read's cost: fog_ball's photons through the glass took 400 ms at
// balanced instead of 297.)
const int kGlassCount = CAUSTIX_GLASS_COUNT;
// Whether some medium's phase function depends on the angle (Schlick with
// k != 0), also fixed when the programs are built: only then do photons
// keep their mean direction (3 of a deposit's 6 atomic adds) and view rays
// read it.
const bool kDirections = CAUSTIX_DIRECTIONS != 0;
#if CAUSTIX_GLASS_COUNT == 1
#define GLASS_INDEX(g) 0
#else
#define GLASS_INDEX(g) (g)
#endif
uniform mat4 u_world_to_voxel[kMaxGlass];  // world -> continuous voxel coordinates (voxel i spans [i, i + 1))
uniform vec4 u_glass_ior[kMaxGlass];       // x n_out, y n_in, z world length of a voxel, w 1 = octree levels stored
uniform vec4 u_glass_size[kMaxGlass];      // xyz voxels
uniform vec4 u_glass_ss[kMaxGlass];        // rgb sigma_s; w Schlick k
uniform vec4 u_glass_st[kMaxGlass];        // rgb sigma_t; w phase (1 isotropic, 2 Schlick)
// R: filtered coverage; G: octree level / 15 (texelFetch). Border 0 (outside).
// Units 0.. as many as there are grids (one at least; volume.cpp's
// CAUSTIX_GRID_UNITS): the viewing pass's light sources take the next.
layout(binding = 0) uniform sampler3D u_index[CAUSTIX_GRID_UNITS];

// ---- the other media ----
uniform int u_fog_on;  // the medium box
uniform vec3 u_fog_lo, u_fog_hi;
uniform vec4 u_fog_ss, u_fog_st;
uniform int u_water_on;  // water with scattering or absorption
uniform vec3 u_water_lo, u_water_hi;  // x, z extent; y from below the scene to the highest wave
uniform float u_water_level;
uniform vec4 u_water_ss, u_water_st;

// ---- the radiance grid ----
uniform vec3 u_grid_lo, u_grid_hi;
uniform ivec3 u_grid_n;
// The focus grid: a second grid of u_focus_n voxels over the
// box of this light where light through glass concentrates, stored in the
// same 3D textures after the radiance grid's slices (z from u_grid_n.z
// on); u_focus_on 0 where the light has none.
uniform int u_focus_on;
uniform vec3 u_focus_lo, u_focus_hi;
uniform ivec3 u_focus_n;

bool in_focus(vec3 x) {
  return u_focus_on != 0 && all(greaterThanEqual(x, u_focus_lo)) && all(lessThanEqual(x, u_focus_hi));
}

struct Medium {
  vec3 ss, st;
  float k, phase;
};

bool in_box(vec3 x, vec3 lo, vec3 hi) { return all(greaterThanEqual(x, lo)) && all(lessThanEqual(x, hi)); }

// Ray parameter interval [t0, t1] inside the box (t1 < t0: missed).
vec2 box_range(vec3 o, vec3 d, vec3 lo, vec3 hi) {
  vec3 inv = 1.0 / d;
  vec3 a = (lo - o) * inv, b = (hi - o) * inv;
  vec3 mn = min(a, b), mx = max(a, b);
  return vec2(max(max(mn.x, mn.y), mn.z), min(min(mx.x, mx.y), mx.z));
}

vec3 voxel_of(int g, vec3 x) { return (u_world_to_voxel[g] * vec4(x, 1.0)).xyz; }
bool in_grid(int g, vec3 u) { return all(greaterThanEqual(u, vec3(0.0))) && all(lessThan(u, u_glass_size[g].xyz)); }
float coverage(int g, vec3 u) { return texture(u_index[GLASS_INDEX(g)], u / u_glass_size[g].xyz).r; }
float index_of(int g, float c) { return mix(u_glass_ior[g].x, u_glass_ior[g].y, c); }

// The first object whose index grid holds x, or -1.
int glass_at(vec3 x, out vec3 u) {
  for (int g = 0; g < kGlassCount; ++g) {
    u = voxel_of(g, x);
    if (in_grid(g, u)) return g;
  }
  return -1;
}

// Gradient of the coverage at voxel coordinate u, per voxel (central
// differences of the trilinear coverage, one voxel apart).
vec3 coverage_gradient(int g, vec3 u) {
  return 0.5 * vec3(coverage(g, u + vec3(1, 0, 0)) - coverage(g, u - vec3(1, 0, 0)),
                    coverage(g, u + vec3(0, 1, 0)) - coverage(g, u - vec3(0, 1, 0)),
                    coverage(g, u + vec3(0, 0, 1)) - coverage(g, u - vec3(0, 0, 1)));
}

// World gradient of n at voxel coordinate u.
vec3 index_gradient(int g, vec3 u) {
  // u = A x + b: grad_x = A^T grad_u.
  return (u_glass_ior[g].y - u_glass_ior[g].x) * (transpose(mat3(u_world_to_voxel[g])) * coverage_gradient(g, u));
}

// The octree node around voxel coordinate u (Pfeuti "Octree
// Construction"): its level, stored per voxel.
int octree_level(int g, vec3 u) {
  return int(texelFetch(u_index[GLASS_INDEX(g)], ivec3(floor(u)), 0).g * 15.0 + 0.5);
}

// The medium at x where x lies in no index grid: the water (photons that
// entered it; view rays below its rest level), else the medium box, else
// none.
Medium medium_outside_grids(vec3 x, bool wet) {
  if (u_water_on != 0 && wet && in_box(x, u_water_lo, u_water_hi)) return Medium(u_water_ss.rgb, u_water_st.rgb, u_water_ss.w, u_water_st.w);
  if (u_fog_on != 0 && in_box(x, u_fog_lo, u_fog_hi)) return Medium(u_fog_ss.rgb, u_fog_st.rgb, u_fog_ss.w, u_fog_st.w);
  return Medium(vec3(0.0), vec3(0.0), 0.0, 1.0);
}

// The medium at x: the object that holds x (coverage >= 1/2), else
// medium_outside_grids.
Medium medium_at(vec3 x, bool wet) {
  for (int g = 0; g < kGlassCount; ++g) {
    vec3 u = voxel_of(g, x);
    if (in_grid(g, u) && coverage(g, u) >= 0.5) return Medium(u_glass_ss[g].rgb, u_glass_st[g].rgb, u_glass_ss[g].w, u_glass_st[g].w);
  }
  return medium_outside_grids(x, wet);
}

// Pfeuti, "Viewing Pass": isotropic 1/(4 pi); Schlick
// (1/(4 pi)) (1 - k^2) / (1 - k cos a)^2, a between the light's direction
// of travel and the scattered direction.
float phase_value(Medium m, float cos_a) {
  const float inv_4pi = 0.0795774715;
  if (m.phase < 1.5) return inv_4pi;
  float d = 1.0 - m.k * cos_a;
  return inv_4pi * (1.0 - m.k * m.k) / (d * d);
}

// Integral over [a, b] of p e^(-st s) ds, per channel.
vec3 power_length(vec3 p, vec3 st, float a, float b) {
  vec3 out_v;
  for (int c = 0; c < 3; ++c) {
    out_v[c] = st[c] * (b - a) < 1e-6 ? p[c] * (b - a) * exp(-st[c] * a) : p[c] * (exp(-st[c] * a) - exp(-st[c] * b)) / st[c];
  }
  return out_v;
}

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The length (metres) of a step through object g's index grid from voxel
// coordinate u along unit d: across the octree node around u when it is
// uniform and `octree` is set (Pfeuti "Photon Marching": as large as the
// octree allows), else `step` voxels; at most max_len.
float grid_step_length(int g, vec3 u, vec3 d, float step, bool octree, float max_len) {
  float h = u_glass_ior[g].z;
  float len_voxels = step;
  int level = octree ? octree_level(g, u) : 0;
  if (level > 0) {
    // To the far side of the aligned cube of 2^level voxels around u.
    float side = float(1 << level);
    vec3 lo = floor(u / side) * side;
    vec3 du = mat3(u_world_to_voxel[g]) * d;  // voxels per metre along d
    vec2 r = box_range(u, du, lo, lo + side);
    len_voxels = max(r.y / h, step) + 0.01;
  }
  return min(len_voxels * h, max_len);
}

// One step of a ray through object g's index grid from x along unit d
// (Pfeuti "Photon Marching": x += (ds / n) v, v += ds grad n, |v| = n), of
// grid_step_length. Returns the length; x and d are advanced, `c0`/`c1`
// are the coverage before and after (a crossing of 1/2 is the object's
// surface: Fresnel, crossing_transmittance).
float grid_step(int g, vec3 u, inout vec3 x, inout vec3 d, float step, bool octree, float max_len, out float c0, out float c1) {
  float len = grid_step_length(g, u, d, step, octree, max_len);
  c0 = coverage(g, u);
  vec3 v = index_of(g, c0) * d + len * index_gradient(g, u);
  x += len * d;
  d = normalize(v);
  c1 = coverage(g, voxel_of(g, x));
  return len;
}

// The transmittance across the object's surface (exact Fresnel) for a ray
// that crossed coverage 1/2 between c0 and c1 with direction d; the
// normal is the index gradient. Under total internal reflection the
// filtered index turns the ray itself, so nothing is taken.
float surface_transmittance(int g, float c0, float c1, vec3 d, vec3 grad) {
  if ((c0 - 0.5) * (c1 - 0.5) > 0.0 || dot(grad, grad) < 1e-20) return 1.0;
  bool entering = c1 > c0;
  float eta = entering ? u_glass_ior[g].x / u_glass_ior[g].y : u_glass_ior[g].y / u_glass_ior[g].x;
  float cos_i = abs(dot(d, normalize(grad)));
  float r = caustix_fresnel_reflectance(cos_i, eta);
  return r >= 1.0 ? 1.0 : 1.0 - r;
}

// surface_transmittance for the step from x0 (direction d0) to x1
// (direction d1) of grid_step, with the normal and the direction where the
// coverage crosses 1/2 along the step (linearly between its ends). Taken at
// the step's start, they changed at once when the ray moved a little and
// the crossing fell into the next step: a ray grazing the surface, whose
// transmittance changes fastest with its angle, then jumped in power as
// the light turned.
float crossing_transmittance(int g, vec3 x0, vec3 x1, vec3 d0, vec3 d1, float c0, float c1) {
  if ((c0 - 0.5) * (c1 - 0.5) > 0.0) return 1.0;
  float f = clamp((0.5 - c0) / (c1 - c0), 0.0, 1.0);
  return surface_transmittance(g, c0, c1, normalize(mix(d0, d1, f)), index_gradient(g, voxel_of(g, mix(x0, x1, f))));
}

// Refraction at the surface (VolumeOptions::surface_refraction). The index
// grids the baker makes hold two indices, n_out outside and n_in inside,
// blurred across the mesh's surface; a ray goes straight where the coverage
// stays on one side of 1/2 and refracts by Snell's law, with the exact
// Fresnel transmittance, where it crosses 1/2. grid_step's curved path
// (x += (ds / n) v, v += ds grad n) is first order in ds: its error
// through the blurred surface depends on the steps' length and phase, and
// the phase moves with the light (docs/volume.md, docs/temporal.md).

// The point on the segment x + s d, s in [a, b], where the coverage
// crosses 1/2, given its values there less 1/2 (fa, fb, of opposite
// signs): one step of regula falsi (the interpolated point's value read,
// then the interpolation within the part that holds the crossing), which
// moves continuously with the segment.
float coverage_root(int g, vec3 x, vec3 d, float a, float b, float fa, float fb) {
  float s = (a * fb - b * fa) / (fb - fa);
  float fs = coverage(g, x + s * d) - 0.5;
  if (fs * fb > 0.0) {
    b = s;
    fb = fs;
  } else {
    a = s;
    fa = fs;
  }
  return (a * fb - b * fa) / (fb - fa);
}

// The surface's normal at voxel coordinate u on it, in voxel coordinates,
// towards growing coverage (gc: the coverage's gradient there). The
// gradient of the blurred coverage follows the voxelised mesh's flat
// facets (sphere.obj's are 7.5 degrees wide: the gradient was 1.3 degrees
// off the sphere's normal on average) and, taken by central differences
// across a ramp about as wide as their spacing, leans away from the grid's
// axes; a ball refracting by it focused fog_ball's line 7 cm short. This
// is the normal of the plane through four points of the surface 4 voxels
// around u, each found along the gradient's direction between the
// coverage's values a voxel either side (coverage_root: the ramp's shape
// shifts the four alike, which moves the plane and not its normal): the
// facets average out. Where the surface is not met within a voxel of
// that plane (a thin or sharp part), or the plane's normal is more than
// 15 degrees from the gradient's (an edge, which the plane would round),
// the gradient's direction.
vec3 surface_normal_voxels(int g, vec3 u, vec3 gc) {
  if (dot(gc, gc) < 1e-20) return vec3(0.0);
  vec3 n0 = normalize(gc);
  vec3 t1 = normalize(abs(n0.x) < 0.9 ? cross(n0, vec3(1, 0, 0)) : cross(n0, vec3(0, 1, 0)));
  vec3 t2 = cross(n0, t1);
  const float rho = 4.0;
  vec3 p[4];
  for (int k = 0; k < 4; ++k) {
    vec3 q = u + rho * (k == 0 ? t1 : k == 1 ? t2 : k == 2 ? -t1 : -t2);
    float f0 = coverage(g, q - n0) - 0.5, f1 = coverage(g, q + n0) - 0.5;
    if (f0 >= 0.0 || f1 < 0.0) return n0;
    p[k] = q + coverage_root(g, q, n0, -1.0, 1.0, f0, f1) * n0;
  }
  vec3 n = cross(p[0] - p[2], p[1] - p[3]);
  if (dot(n, n) == 0.0) return n0;
  n = normalize(n) * sign(dot(n, n0));
  return dot(n, n0) > 0.966 ? n : n0;
}

// The straight step from x along d through object g's index grid (u: x in
// voxels), of grid_step's length (the octree's node, else `step` voxels, at
// most max_len metres). A step that crosses coverage 1/2 ends there and
// sets `crossed`: surface_refract turns the ray. The crossing is
// interpolated linearly between the step's ends: the blurred coverage's
// ramp is straightest at 1/2, its inflection, so across a step of half a
// voxel the point is off by some 0.005 voxels (in the octree's uniform
// nodes the coverage does not cross 1/2), and a search here would run for
// every SIMD lane whenever one lane crosses. Returns the length.
float surface_advance(int g, vec3 u, inout vec3 x, vec3 d, float step, bool octree, float max_len, out bool crossed) {
  float len = grid_step_length(g, u, d, step, octree, max_len);
  vec3 du = mat3(u_world_to_voxel[g]) * d;
  float f0 = coverage(g, u) - 0.5, f1 = coverage(g, u + len * du) - 0.5;
  crossed = (f0 >= 0.0) != (f1 >= 0.0);
  if (crossed) len *= f0 / (f0 - f1);
  x += len * d;
  return len;
}

// Turns the ray at x on object g's surface (where surface_advance stopped
// it, between a step's ends): one Newton step along the ray onto coverage
// 1/2, then Snell's law at the surface's normal, or, beyond the critical
// angle, reflection; x then moves off the surface to the side the ray now
// goes, as far as it takes (a ray left on the side it came from would
// refract again at its next step). Returns the Fresnel transmittance (1
// when reflected whole).
float surface_refract(int g, inout vec3 x, inout vec3 d) {
  mat3 a = mat3(u_world_to_voxel[g]);
  float h = u_glass_ior[g].z;
  vec3 u = voxel_of(g, x);
  vec3 gc = coverage_gradient(g, u);
  vec3 du = a * d;
  float slope = dot(gc, du);  // coverage per metre along the ray
  if (abs(slope) * h > 1e-4) {
    float s = clamp((0.5 - coverage(g, u)) / slope, -h, h);
    x += s * d;
    u += s * du;
  }
  bool entering = slope > 0.0;  // the coverage grows along the ray
  vec3 nu = surface_normal_voxels(g, u, gc);
  if (dot(nu, nu) == 0.0) return 1.0;
  // A normal is a covector: world = A^T n for u = A x + b.
  vec3 n_in = normalize(transpose(a) * nu);
  vec3 nrm = entering ? -n_in : n_in;  // against the ray
  float eta = entering ? u_glass_ior[g].x / u_glass_ior[g].y : u_glass_ior[g].y / u_glass_ior[g].x;
  float cos_i = -dot(d, nrm);
  float tr = 1.0;
  bool reflected = false;
  // (cos_i <= 0: the ray grazes the plane from its far side; it goes on.)
  if (cos_i > 0.0) {
    vec3 t = refract(d, nrm, eta);
    reflected = dot(t, t) == 0.0;
    if (reflected) {
      d = reflect(d, nrm);
    } else {
      float r = caustix_fresnel_reflectance(cos_i, eta);
      tr = r >= 1.0 ? 1.0 : 1.0 - r;
      d = normalize(t);
    }
  }
  bool inside = entering != reflected;
  vec3 off = (inside ? h : -h) * n_in;
  float push = 0.02;
  for (int i = 0; i < 2 && (coverage(g, voxel_of(g, x + push * off)) >= 0.5) != inside; ++i) push *= 8.0;
  x += push * off;
  return tr;
}

// One step through object g's index grid by the model the options pick,
// fixed when the program is built (volume.cpp defines
// CAUSTIX_SURFACE_REFRACTION). Refraction at the surface: a straight
// step, `crossed` where it ends on the surface (the caller then calls
// surface_refract: outside its loop of steps, so that a rasteriser running
// SIMD lanes pays for the normal once a crossing and not at every step
// some lane crosses). The seed's curved path: grid_step, `crossed` never
// set. `tr`: the Fresnel transmittance taken in the step.
float grid_march(int g, vec3 u, inout vec3 x, inout vec3 d, float step, bool octree, float max_len, out float tr, out bool crossed) {
  tr = 1.0;
#if CAUSTIX_SURFACE_REFRACTION
  return surface_advance(g, u, x, d, step, octree, max_len, crossed);
#else
  crossed = false;
  vec3 x0 = x, d0 = d;
  float c0, c1;
  float len = grid_step(g, u, x, d, step, octree, max_len, c0, c1);
  tr = crossing_transmittance(g, x0, x, d0, d, c0, c1);
  return len;
#endif
}
