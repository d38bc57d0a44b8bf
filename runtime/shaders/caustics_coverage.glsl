// Shared by the caustics fragment shaders (prefixed with #version): the
// exact area of the intersection triangle inside this fragment's texel, by
// clipping the texel square against the triangle's three edges
// (Sutherland-Hodgman; at most 7 vertices).
// PRIM_STRIDE: vec4s per primitive (3 for water caustics, 6 for glass).
#ifndef PRIM_STRIDE
#define PRIM_STRIDE 3
#endif
flat in int v_prim;
layout(std430, binding = 8) readonly buffer Primitives { vec4 prims[]; };

// This fragment's primitive (caustics_geometry.comp).
vec2 v_q0, v_q1, v_q2, v_plane;
float v_irradiance;
void load_primitive() {
  vec4 a = prims[PRIM_STRIDE * v_prim], b = prims[PRIM_STRIDE * v_prim + 1], c = prims[PRIM_STRIDE * v_prim + 2];
  v_q0 = a.xy;
  v_q1 = a.zw;
  v_q2 = b.xy;
  v_irradiance = b.z;
  v_plane = c.xy;
}

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

float texel_coverage() {
  vec2 tri[3] = vec2[3](v_q0, v_q1, v_q2);
  if (cross2(v_q1 - v_q0, v_q2 - v_q0) < 0.0) tri = vec2[3](v_q0, v_q2, v_q1);  // counter-clockwise
  vec2 lo = floor(gl_FragCoord.xy);
  // Fast paths: the texel wholly inside every edge, or wholly outside one.
  bool inside = true;
  for (int e = 0; e < 3; ++e) {
    vec2 a = tri[e], d = tri[(e + 1) % 3] - a;
    float s0 = cross2(d, lo - a), s1 = cross2(d, lo + vec2(1, 0) - a);
    float s2 = cross2(d, lo + vec2(1, 1) - a), s3 = cross2(d, lo + vec2(0, 1) - a);
    if (max(max(s0, s1), max(s2, s3)) < 0.0) return 0.0;
    inside = inside && min(min(s0, s1), min(s2, s3)) >= 0.0;
  }
  if (inside) return 1.0;
  vec2 poly[8];
  poly[0] = lo;
  poly[1] = lo + vec2(1.0, 0.0);
  poly[2] = lo + vec2(1.0, 1.0);
  poly[3] = lo + vec2(0.0, 1.0);
  int n = 4;
  for (int e = 0; e < 3 && n > 0; ++e) {
    vec2 a = tri[e], d = tri[(e + 1) % 3] - a;
    vec2 next[8];
    int m = 0;
    for (int i = 0; i < n; ++i) {
      vec2 p = poly[i], q = poly[(i + 1) % n];
      float sp = cross2(d, p - a), sq = cross2(d, q - a);  // >= 0: inside (left of the edge)
      if (sp >= 0.0) next[m++] = p;
      if ((sp >= 0.0) != (sq >= 0.0)) next[m++] = p + (q - p) * (sp / (sp - sq));
    }
    for (int i = 0; i < m; ++i) poly[i] = next[i];
    n = m;
  }
  float twice = 0.0;
  for (int i = 0; i < n; ++i) twice += cross2(poly[i], poly[(i + 1) % n]);
  return 0.5 * max(twice, 0.0);
}
