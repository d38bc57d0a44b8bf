// Light-transport-table look-up (seed 002 §4.1; prefixed after #version by
// the renderer). Mirrors caustix::lookup() in formats/src/light_transport.cpp
// with Interpolation::kBicubic: the hemi-octahedral grid around the vertex
// normal, Catmull-Rom over the 4 x 4 neighbouring grid directions where the
// inner 2 x 2 leave alike (the same number of internal reflections, exits
// within 30 degrees; an outer row or column that does not, or lies outside
// the grid, replaced by linear extrapolation); otherwise the path class of
// the heaviest leaving corner (same reflections, exits within 30 degrees)
// extrapolated linearly from that class's entries in the 4 x 4 (a
// weighted least-squares plane; bilinear over the class's corners where
// they lie on a line), with the transmittance scaled by the share of the
// weight that leaves.
layout(std430, binding = 1) readonly buffer Table { uint table[]; };

const float LTT_SAME_EXIT_COS = 0.8660254;  // kSameExitCos: 30 degrees

uniform int u_ltt_resolution;
uniform vec3 u_ltt_exit_min;
uniform vec3 u_ltt_exit_max;
uniform float u_ltt_max_path;

struct Transport {
  vec3 exit;         // object space
  vec3 dir;          // object space, unit
  float transmittance;
  float path;        // object-space metres inside
  bool leaves;
  uint bounces;      // the path's class: internal reflections and re-entries
};

// Duff et al. 2017, as tangent_frame() in C++.
void ltt_frame(vec3 n, out vec3 t, out vec3 b) {
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float c = n.x * n.y * a;
  t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
  b = vec3(c, s + n.y * n.y * a, -n.y);
}

vec3 ltt_oct_decode(vec2 e) {
  vec3 d = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (d.z < 0.0) d.xy = (1.0 - abs(d.yx)) * vec2(d.x >= 0.0 ? 1.0 : -1.0, d.y >= 0.0 ? 1.0 : -1.0);
  return normalize(d);
}

struct LttEntry {
  vec3 exit, dir;
  float transmittance, path;
  bool leaves;
  uint bounces;
};

// Two leaving entries of one path class: the same reflections, exits
// within 30 degrees (alike() in C++).
bool ltt_alike(LttEntry p, LttEntry q) {
  return p.leaves && q.leaves && p.bounces == q.bounces && dot(p.dir, q.dir) >= LTT_SAME_EXIT_COS;
}

LttEntry ltt_entry(uint vertex, int x, int y) {
  uint idx = 4u * ((vertex * uint(u_ltt_resolution) + uint(y)) * uint(u_ltt_resolution) + uint(x));
  uint w0 = table[idx], w1 = table[idx + 1u], w2 = table[idx + 2u], w3 = table[idx + 3u];
  LttEntry e;
  e.leaves = ((w3 >> 16) & 0xFFu) == 0u;
  e.bounces = w3 >> 24;
  vec3 q = vec3(float(w0 & 0xFFFFu), float(w0 >> 16), float(w1 & 0xFFFFu)) / 65535.0;
  e.exit = mix(u_ltt_exit_min, u_ltt_exit_max, q);
  e.transmittance = float(w1 >> 16) / 65535.0;
  e.dir = ltt_oct_decode(vec2(float(w2 & 0xFFFFu), float(w2 >> 16)) / 65535.0 * 2.0 - 1.0);
  e.path = float(w3 & 0xFFFFu) / 65535.0 * u_ltt_max_path;
  return e;
}

// Catmull-Rom weights of x0 - 1 .. x0 + 2; a missing outer sample's weight
// folded onto the inner two (linear extrapolation), as catmull_rom() in C++.
vec4 ltt_catmull_rom(float a, bool use_lo, bool use_hi) {
  float a2 = a * a, a3 = a2 * a;
  vec4 w = 0.5 * vec4(-a3 + 2.0 * a2 - a, 3.0 * a3 - 5.0 * a2 + 2.0, -3.0 * a3 + 4.0 * a2 + a, a3 - a2);
  if (!use_lo) w = vec4(0.0, w.y + 2.0 * w.x, w.z - w.x, w.w);
  if (!use_hi) w = vec4(w.x, w.y - w.w, w.z + 2.0 * w.w, 0.0);
  return w;
}

Transport ltt_lookup(uint vertex, vec3 n, vec3 to_light) {
  vec3 t, b;
  ltt_frame(n, t, b);
  vec3 l = vec3(dot(to_light, t), dot(to_light, b), max(dot(to_light, n), 0.0));
  vec2 p = l.xy / max(abs(l.x) + abs(l.y) + l.z, 1e-20);
  vec2 st = vec2(p.x + p.y, p.x - p.y);
  int r = u_ltt_resolution;
  float r1 = float(r - 1);
  vec2 f = clamp((st + 1.0) * 0.5 * r1, 0.0, r1);
  vec2 f0 = min(floor(f), vec2(r1 - 1.0));
  vec2 a = f - f0;
  int x0 = int(f0.x), y0 = int(f0.y);
  Transport o;
  o.exit = vec3(0.0);
  o.dir = vec3(0.0);
  o.transmittance = 0.0;
  o.path = 0.0;
  o.bounces = 0u;

  // Bicubic: stencil k = (column x0 - 1 + (k & 3), row y0 - 1 + (k >> 2)).
  LttEntry e[16];
  bool ok[16], ok_grid[16];
  for (int k = 0; k < 16; ++k) {
    int x = x0 + (k & 3) - 1, y = y0 + (k >> 2) - 1;
    ok[k] = x >= 0 && y >= 0 && x < r && y < r;
    ok_grid[k] = ok[k];
    if (ok[k]) {
      e[k] = ltt_entry(vertex, x, y);
      ok[k] = e[k].leaves;
    }
  }
  uint bounces = e[5].bounces;
  for (int k = 0; k < 16; ++k) ok[k] = ok[k] && e[k].bounces == bounces && dot(e[k].dir, e[5].dir) >= LTT_SAME_EXIT_COS;
  if (ok[5] && ok[6] && ok[9] && ok[10]) {
    bool row0 = ok[1] && ok[2], row3 = ok[13] && ok[14];
    bool col0 = ok[4] && ok[8] && (!row0 || ok[0]) && (!row3 || ok[12]);
    bool col3 = ok[7] && ok[11] && (!row0 || ok[3]) && (!row3 || ok[15]);
    vec4 wx = ltt_catmull_rom(a.x, col0, col3);
    vec4 wy = ltt_catmull_rom(a.y, row0, row3);
    for (int k = 0; k < 16; ++k) {
      float w = wx[k & 3] * wy[k >> 2];
      if (w == 0.0) continue;
      o.exit += w * e[k].exit;
      o.dir += w * e[k].dir;
      o.transmittance += w * e[k].transmittance;
      o.path += w * e[k].path;
    }
    o.transmittance = clamp(o.transmittance, 0.0, 1.0);
    o.path = max(o.path, 0.0);
    o.dir = normalize(o.dir);
    o.leaves = true;
    o.bounces = bounces;
    return o;
  }

  // Bilinear fallback over the inner 2 x 2 (stencil 5, 6, 9, 10): only the
  // corners leaving alike with the heaviest leaving one, renormalised; the
  // transmittance scaled by the leaving share of the weight.
  float w[4];
  int best = -1;
  for (int k = 0; k < 4; ++k) {
    int dx = k & 1, dy = k >> 1;
    w[k] = (dx == 1 ? a.x : 1.0 - a.x) * (dy == 1 ? a.y : 1.0 - a.y);
    if (!e[5 + dx + 4 * dy].leaves) w[k] = 0.0;
    if (w[k] > 0.0 && (best < 0 || w[k] > w[best])) best = k;
  }
  o.leaves = best >= 0;
  if (!o.leaves) return o;
  LttEntry heavy = e[5 + (best & 1) + 4 * (best >> 1)];
  o.bounces = heavy.bounces;
  float leaving = 0.0, same = 0.0;
  for (int k = 0; k < 4; ++k) {
    if (w[k] <= 0.0) continue;
    LttEntry c = e[5 + (k & 1) + 4 * (k >> 1)];
    leaving += w[k];
    if (!ltt_alike(c, heavy)) continue;
    same += w[k];
    o.exit += w[k] * c.exit;
    o.transmittance += w[k] * c.transmittance;
    o.dir += w[k] * c.dir;
    o.path += w[k] * c.path;
  }
  // The plane fitted to the stencil's entries of the heavy corner's class
  // (linear_fit_weights() in C++), where they do not lie on a line.
  float wk[16];
  float m0 = 0.0, m1 = 0.0, m2 = 0.0, m3 = 0.0, m4 = 0.0, m5 = 0.0;
  for (int k = 0; k < 16; ++k) {
    wk[k] = 0.0;
    if (!(ok_grid[k] && ltt_alike(e[k], heavy))) continue;
    float x = float(k & 3) - 1.0 - a.x, y = float(k >> 2) - 1.0 - a.y;
    wk[k] = 1.0 / (0.25 + x * x + y * y);
    m0 += wk[k];
    m1 += wk[k] * x;
    m2 += wk[k] * y;
    m3 += wk[k] * x * x;
    m4 += wk[k] * x * y;
    m5 += wk[k] * y * y;
  }
  float c0 = m3 * m5 - m4 * m4, c1 = m2 * m4 - m1 * m5, c2 = m1 * m4 - m2 * m3;
  float det = m0 * c0 + m1 * c1 + m2 * c2;
  if (det > 1e-6 * m0 * m0 * m0) {
    o.exit = vec3(0.0);
    o.dir = vec3(0.0);
    o.path = 0.0;
    float tr = 0.0;
    for (int k = 0; k < 16; ++k) {
      if (wk[k] == 0.0) continue;
      float x = float(k & 3) - 1.0 - a.x, y = float(k >> 2) - 1.0 - a.y;
      float lambda = wk[k] * (c0 + c1 * x + c2 * y) / det;
      o.exit += lambda * e[k].exit;
      o.dir += lambda * e[k].dir;
      o.path += lambda * e[k].path;
      tr += lambda * e[k].transmittance;
    }
    o.path = max(o.path, 0.0);
    o.transmittance = clamp(tr, 0.0, 1.0) * leaving / same;
    o.dir = normalize(o.dir);
    return o;
  }
  o.exit /= same;
  o.path /= same;
  o.transmittance *= leaving / same;
  o.dir = normalize(o.dir);
  return o;
}
