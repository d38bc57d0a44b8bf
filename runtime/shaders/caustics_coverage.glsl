// Shared by the caustics fragment shaders (prefixed with #version): the
// exact area of the intersection triangle inside this fragment's texel,
// and its centroid, from the triangle's three edges by Green's theorem
// (edge_moments).
// PRIM_STRIDE: vec4s per primitive (4 for water caustics, 6 for glass).
#ifndef PRIM_STRIDE
#define PRIM_STRIDE 4
#endif
flat in int v_prim;
layout(std430, binding = 8) readonly buffer Primitives { vec4 prims[]; };
#if PRIM_STRIDE == 4
// Water caustics' pairs of half floats (caustics_geometry.comp), read as
// the words they are.
layout(std430, binding = 8) readonly buffer PrimitiveWords { uint prim_words[]; };
vec2 primitive_halves(int word) { return unpackHalf2x16(prim_words[4 * PRIM_STRIDE * v_prim + word]); }
#endif

// This fragment's primitive (caustics_geometry.comp).
vec2 v_q0, v_q1, v_q2, v_plane, v_slopes;
vec2 v_s0, v_s1, v_s2;  // water caustics: each vertex's direction (s_u, s_w)
float v_irradiance;
#ifdef TEXEL_MAP
uniform vec3 u_texel_map;  // as caustics_intersect.vert: this texture's texels are (q - xy) * z
#endif
void load_primitive() {
  vec4 a = prims[PRIM_STRIDE * v_prim], b = prims[PRIM_STRIDE * v_prim + 1], c = prims[PRIM_STRIDE * v_prim + 2];
  v_q0 = a.xy;
  v_q1 = a.zw;
  v_q2 = b.xy;
#ifdef TEXEL_MAP
  v_q0 = (v_q0 - u_texel_map.xy) * u_texel_map.z;
  v_q1 = (v_q1 - u_texel_map.xy) * u_texel_map.z;
  v_q2 = (v_q2 - u_texel_map.xy) * u_texel_map.z;
#endif
  v_irradiance = b.z;
  v_plane = c.xy;
#if PRIM_STRIDE == 4
  v_s0 = primitive_halves(11);
  v_s1 = primitive_halves(12);
  v_s2 = primitive_halves(13);
  v_slopes = (v_s0 + v_s1 + v_s2) / 3.0;  // the beam's mean direction
#endif
}

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// A sliver (height under its longest edge below kSliver texels, as near
// folds where refracted rays cross) is taken as a line density along that
// edge, its "spine" a -> b: the cross-section height rises linearly from 0
// at a to h at the foot of c (parameter tc) and falls to 0 at b, so the
// area over t in [0, t] is L G(t), G(t) = h/2 t^2/tc before tc and
// h/2 (tc + (t - tc)(2 - t - tc)/(1 - tc)) after, G(1) = h/2. A texel gets
// L (G(t1) - G(t0)) for the part [t0, t1] of the spine inside it (half-open
// texels, so pieces tile the spine exactly). Clipping the texel square
// against a sliver instead needs edge functions of size L x 1 to resolve
// heights of 1e-5 texels: float rounding then gives each texel a noisy
// piece, and dropping the negative ones (max(twice, 0)) added up to +4 %
// of the light at 4096^2 on a wave of slope 0.5 (docs/robustness.md).
const float kSliver = 1.0 / 16.0;

// The tent's height at t.
float tent_height(float t, float tc, float h) {
  return t <= tc ? (tc > 0.0 ? h * t / tc : h) : h * (1.0 - t) / max(1.0 - tc, 1e-30);
}

float tent_integral(float t, float tc, float h) {
  if (t <= tc) return tc > 0.0 ? 0.5 * h * t * t / tc : 0.0;
  return 0.5 * h * (tc + (t - tc) * (2.0 - t - tc) / max(1.0 - tc, 1e-30));
}

// The centroid of the part of the triangle inside the texel, set by
// texel_coverage_shifted, in the triangle's own texel coordinates (those of
// v_q0..v_q2, before the shift): a linear function's integral over the
// part is its area times the function there (corner_factor).
vec2 g_centroid;

// a, b, c relative to the texel's corner: the texel is [0, 1]^2.
float sliver_coverage(vec2 a, vec2 b, vec2 c) {
  vec2 d = b - a;
  float len2 = dot(d, d);
  if (len2 <= 0.0) return 0.0;
  float h = abs(cross2(d, c - a)) / sqrt(len2);
  float tc = clamp(dot(c - a, d) / len2, 0.0, 1.0);
  // Liang-Barsky: the part of a + t d, t in [0, 1], with 0 <= p < 1.
  float t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0.0) {
      if (a[k] < 0.0 || a[k] >= 1.0) return 0.0;
    } else {
      float ta = -a[k] / d[k], tb = (1.0 - a[k]) / d[k];
      t0 = max(t0, min(ta, tb));
      t1 = min(t1, max(ta, tb));
    }
  }
  if (t1 <= t0) return 0.0;
  // The centroid of the piece (relative to the corner; the caller adds it):
  // over each linear part of the tent, a trapezoid standing on the spine
  // with heights h0 -> h1 over [ta, tb] has its centroid at
  // ta + (tb - ta)(h0 + 2 h1) / (3 (h0 + h1)) along the spine and
  // (h0^2 + h0 h1 + h1^2) / (3 (h0 + h1)) off it, towards c.
  float mass = 0.0, along = 0.0, off = 0.0;
  for (int part = 0; part < 2; ++part) {
    float ta = part == 0 ? t0 : max(t0, tc), tb = part == 0 ? min(t1, tc) : t1;
    if (tb <= ta) continue;
    float h0 = tent_height(ta, tc, h), h1 = tent_height(tb, tc, h), sum = h0 + h1;
    if (sum <= 0.0) continue;
    float m = 0.5 * sum * (tb - ta);
    mass += m;
    along += m * (ta + (tb - ta) * (h0 + 2.0 * h1) / (3.0 * sum));
    off += m * (h0 * h0 + h0 * h1 + h1 * h1) / (3.0 * sum);
  }
  vec2 toward_c = cross2(d, c - a) >= 0.0 ? vec2(-d.y, d.x) : vec2(d.y, -d.x);
  g_centroid = mass > 0.0 ? a + d * (along / mass) + normalize(toward_c) * (off / mass) : a + d * (0.5 * (t0 + t1));
  return sqrt(len2) * (tent_integral(t1, tc, h) - tent_integral(t0, tc, h));
}

// One edge a -> b's share of the area and first moments of a polygon's
// part inside the texel [0, 1]^2 (Green's theorem): with F(y) = clamp(y, 0,
// 1) and x taken only within [0, 1], a counter-clockwise boundary gives
//   area = -sum of  int F(y) dx,   int x dA = -sum of  int x F(y) dx,
//   int y dA = -sum of  int F(y)^2 / 2 dx
// over its edges. An edge's integrals depend on its ends alone and vary
// continuously with them, so a vertex on or near a texel line cannot make
// two edges disagree. Split where y crosses 0 and 1, F(y) is linear along
// each piece (ends (xs, cs) and (xe, ce)), and the integrals are exact:
//   (xe - xs)(cs + ce) / 2,  (xe - xs)(2 cs xs + cs xe + ce xs + 2 ce xe) / 6,
//   (xe - xs)(cs^2 + cs ce + ce^2) / 6.
// Returns (area, x moment, y moment) as the sums' terms, before the sign.
vec3 edge_piece(vec2 p, vec2 q) {
  float dx = q.x - p.x;
  vec2 c = clamp(vec2(p.y, q.y), 0.0, 1.0);
  return dx * vec3(0.5 * (c.x + c.y), (2.0 * c.x * p.x + c.x * q.x + c.y * p.x + 2.0 * c.y * q.x) / 6.0,
                   (c.x * c.x + c.x * c.y + c.y * c.y) / 6.0);
}

vec3 edge_moments(vec2 a, vec2 b) {
  float dx = b.x - a.x;
  if (dx == 0.0) return vec3(0.0);
  // The part with x in [0, 1], its ends at x exactly 0 or 1 where clipped.
  float xs = clamp(a.x, 0.0, 1.0), xe = clamp(b.x, 0.0, 1.0);
  if (xs == xe) return vec3(0.0);
  vec2 p = vec2(xs, mix(a.y, b.y, (xs - a.x) / dx)), q = vec2(xe, mix(a.y, b.y, (xe - a.x) / dx));
  // Where y crosses 0 and 1 along p -> q.
  float dy = q.y - p.y;
  vec2 u = dy != 0.0 ? clamp(vec2(-p.y, 1.0 - p.y) / dy, 0.0, 1.0) : vec2(0.0);
  float u0 = min(u.x, u.y), u1 = max(u.x, u.y);
  vec2 r0 = mix(p, q, u0), r1 = mix(p, q, u1);
  return edge_piece(p, r0) + edge_piece(r0, r1) + edge_piece(r1, q);
}

// Everything below is computed relative to the texel's corner, so that the
// integrals' terms are of order 1: with absolute texel coordinates (up to
// the map size) the shoelace sum of the clipped polygon this once built
// cancelled products of ~10^7 (4096^2 maps) to ~10^8 (8192^2) down to an
// area below 1, and the rounding, with max(twice, 0) dropping the negative
// half, lit texels along triangle edges up to +30 % (docs/robustness.md).
// `shift` moves the triangle by that many texels first.
float texel_coverage_shifted(vec2 shift) {
  vec2 lo = floor(gl_FragCoord.xy) - shift;
  vec2 q0 = v_q0 - lo, q1 = v_q1 - lo, q2 = v_q2 - lo;
  {
    vec2 a = q0, b = q1, c = q2;
    vec2 e01 = q1 - q0, e12 = q2 - q1, e20 = q0 - q2;
    float l01 = dot(e01, e01), l12 = dot(e12, e12), l20 = dot(e20, e20), longest = l01;
    if (l12 > longest) { a = q1; b = q2; c = q0; longest = l12; }
    if (l20 > longest) { a = q2; b = q0; c = q1; longest = l20; }
    if (abs(cross2(b - a, c - a)) < kSliver * sqrt(longest)) {
      float area = sliver_coverage(a, b, c);
      g_centroid += lo;
      return area;
    }
  }
  g_centroid = lo + vec2(0.5);
  float twice = cross2(q1 - q0, q2 - q0);
  if (twice == 0.0) return 0.0;
  // Fast paths: the texel wholly inside every edge, or wholly outside one.
  float s = sign(twice);
  bool inside = true;
  for (int e = 0; e < 3; ++e) {
    vec2 a = e == 0 ? q0 : e == 1 ? q1 : q2, d = (e == 0 ? q1 : e == 1 ? q2 : q0) - a;
    vec4 c = s * vec4(cross2(d, -a), cross2(d, vec2(1, 0) - a), cross2(d, vec2(1, 1) - a), cross2(d, vec2(0, 1) - a));
    if (max(max(c.x, c.y), max(c.z, c.w)) < 0.0) return 0.0;
    inside = inside && min(min(c.x, c.y), min(c.z, c.w)) >= 0.0;
  }
  if (inside) return 1.0;
  // The part inside by Green's theorem, each edge on its own (no clipped
  // polygon to build: straight-line code, no arrays).
  vec3 m = edge_moments(q0, q1) + edge_moments(q1, q2) + edge_moments(q2, q0);
  float area = -s * m.x;
  if (area <= 0.0) return 0.0;
  g_centroid = lo + clamp(-s * m.yz / area, 0.0, 1.0);
  return min(area, 1.0);
}

float texel_coverage() { return texel_coverage_shifted(vec2(0.0)); }

#if PRIM_STRIDE == 4
// Water caustics (caustics_geometry.comp's words 14 and 15): the factor on the
// triangle's irradiance over the part texel_coverage*() just measured -- its
// corners' ratios interpolated at that part's centroid (barycentric: exact
// for the part's mean of the linear interpolant), over their mean, so that
// the triangle keeps its flux; 1 where the triangle keeps the constant.
float corner_factor() {
  vec3 c = vec3(primitive_halves(14), primitive_halves(15).x);
  if (c.x < 0.0) return 1.0;  // the triangle's own irradiance (caustics_geometry.comp)
  vec2 x = g_centroid;
  float twice = cross2(v_q1 - v_q0, v_q2 - v_q0);
  if (abs(twice) <= 1e-12) return 1.0;
  vec3 bary = max(vec3(cross2(v_q1 - x, v_q2 - x), cross2(v_q2 - x, v_q0 - x), cross2(v_q0 - x, v_q1 - x)) / twice, 0.0);
  bary /= max(bary.x + bary.y + bary.z, 1e-12);
  return dot(bary, c.xyz) * 3.0 / max(c.x + c.y + c.z, 1e-12);
}
#endif
