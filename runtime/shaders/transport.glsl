// Light-transport-table look-up (Iwasaki et al. §4.1; prefixed after #version by
// the renderer). Mirrors caustix::lookup() in formats/src/light_transport.cpp
// with Interpolation::kBicubic: the hemi-octahedral grid around the vertex
// normal, Catmull-Rom over the 4 x 4 neighbouring grid directions where the
// inner 2 x 2 leave alike (the same number of internal reflections, exits
// within 30 degrees; an outer row or column that does not, or lies outside
// the grid, replaced by linear extrapolation); otherwise the path class of
// the heaviest leaving corner (same reflections, exits within 30 degrees;
// on the query's side of the switch where the table stores one, LTTW)
// extrapolated linearly from that class's entries in the 4 x 4 (a
// weighted least-squares plane, its slopes held near 0 where the entries
// lie on a line), with the transmittance scaled by the share of the
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
// within 30 degrees (leave_alike() in C++).
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

// The plane fitted by weighted least squares (weights 1 / (1/4 + r^2), r
// the grid offset from the query a) to the stencil's entries leaving alike
// with `ref`, at the query (linear_fit_weights() in C++): that path class
// extrapolated linearly. False where none does.
bool ltt_fit(LttEntry e[16], bool in_grid[16], LttEntry ref, vec2 a, out Transport o) {
  o.exit = vec3(0.0);
  o.dir = vec3(0.0);
  o.transmittance = 0.0;
  o.path = 0.0;
  o.leaves = false;
  o.bounces = ref.bounces;
  float wk[16];
  float m0 = 0.0, m1 = 0.0, m2 = 0.0, m3 = 0.0, m4 = 0.0, m5 = 0.0;
  for (int k = 0; k < 16; ++k) {
    wk[k] = 0.0;
    if (!(in_grid[k] && ltt_alike(e[k], ref))) continue;
    float x = float(k & 3) - 1.0 - a.x, y = float(k >> 2) - 1.0 - a.y;
    wk[k] = 1.0 / (0.25 + x * x + y * y);
    m0 += wk[k];
    m1 += wk[k] * x;
    m2 += wk[k] * y;
    m3 += wk[k] * x * x;
    m4 += wk[k] * x * y;
    m5 += wk[k] * y * y;
  }
  if (m0 == 0.0) return false;
  // A slope held near 0 where the entries do not fix it (all on a line:
  // constant across it; one entry: its value).
  m3 += 1e-3 * m0;
  m5 += 1e-3 * m0;
  float c0 = m3 * m5 - m4 * m4, c1 = m2 * m4 - m1 * m5, c2 = m1 * m4 - m2 * m3;
  float det = m0 * c0 + m1 * c1 + m2 * c2;
  for (int k = 0; k < 16; ++k) {
    if (wk[k] == 0.0) continue;
    float x = float(k & 3) - 1.0 - a.x, y = float(k >> 2) - 1.0 - a.y;
    float lambda = wk[k] * (c0 + c1 * x + c2 * y) / det;
    o.exit += lambda * e[k].exit;
    o.dir += lambda * e[k].dir;
    o.path += lambda * e[k].path;
    o.transmittance += lambda * e[k].transmittance;
  }
  o.path = max(o.path, 0.0);
  o.transmittance = clamp(o.transmittance, 0.0, 1.0);
  o.dir = normalize(o.dir);
  o.leaves = true;
  return true;
}

// Where the path class switches on the grid edge from entry (x, y) to the
// next column (axis 0) or row (axis 1), as a fraction of the edge (the
// baker's bisection, the LTTW chunk, stored after the entries from word
// u_ltt_switch_base); -1 where none is stored.
uniform uint u_ltt_switch_base;  // 0: the table has no switches

float ltt_switch(uint vertex, int x, int y, uint axis) {
  if (u_ltt_switch_base == 0u) return -1.0;
  uint i = 2u * ((vertex * uint(u_ltt_resolution) + uint(y)) * uint(u_ltt_resolution) + uint(x)) + axis;
  uint b = (table[u_ltt_switch_base + i / 4u] >> (8u * (i % 4u))) & 0xFFu;
  return b == 0u ? -1.0 : float(b) / 256.0;
}

// The heaviest leaving corner of the query's cell (k: (k & 1, k >> 1);
// weights w) on the query's side of the switch through the cell, where
// the table stores the switch on exactly two of the cell's edges (the
// class at the query direction itself, not the heaviest corner's, which at
// the cell's middle is a tie); else `best`, the heaviest of all.
// lookup() in C++ decides alike.
int ltt_side_of_switch(uint vertex, int x0, int y0, LttEntry e[16], vec2 a, float w[4], int best) {
  // Edges: bottom 0-1, top 2-3 (along the columns), left 0-2, right 1-3.
  ivec2 ends[4] = ivec2[4](ivec2(0, 1), ivec2(2, 3), ivec2(0, 2), ivec2(1, 3));
  vec2 pts[2];
  int count = 0;
  for (int s = 0; s < 4; ++s) {
    int i = ends[s].x, j = ends[s].y;
    LttEntry p = e[5 + (i & 1) + 4 * (i >> 1)], q = e[5 + (j & 1) + 4 * (j >> 1)];
    if (!(p.leaves && q.leaves) || ltt_alike(p, q)) continue;
    float fr = ltt_switch(vertex, x0 + (i & 1), y0 + (i >> 1), s < 2 ? 0u : 1u);
    if (fr < 0.0 || count == 2) return best;
    pts[count++] = vec2(i & 1, i >> 1) + (s < 2 ? vec2(fr, 0.0) : vec2(0.0, fr));
  }
  if (count != 2) return best;
  vec2 d = pts[1] - pts[0];
  float side = d.x * (a.y - pts[0].y) - d.y * (a.x - pts[0].x);
  int pick = -1;
  for (int k = 0; k < 4; ++k) {
    float sk = d.x * (float(k >> 1) - pts[0].y) - d.y * (float(k & 1) - pts[0].x);
    if (w[k] > 0.0 && (sk > 0.0) == (side > 0.0) && (pick < 0 || w[k] > w[pick])) pick = k;
  }
  return pick < 0 ? best : pick;
}

float ltt_segment_distance(vec2 p, vec2 q) {  // from the origin
  vec2 d = q - p;
  float h = clamp(-dot(p, d) / max(dot(d, d), 1e-12), 0.0, 1.0);
  return length(p + h * d);
}

// Look-up at `vertex` (normal n) for the direction to the light, and, with
// `want_other`, what a triangle torn between two path classes needs to be
// cut at the switch (glass_geometry.comp): `other`, the nearest other
// leaving class of the 4 x 4 stencil extrapolated to the query (leaves
// false where there is none), and `dist`, the distance in grid cells from
// the query to the switch between the two classes, along the segments
// through the stored switch points of the stencil's cells (-1 where none
// is stored).
Transport ltt_lookup_ex(uint vertex, vec3 n, vec3 to_light, bool want_other, out Transport other, out float dist) {
  vec3 t, b;
  ltt_frame(n, t, b);
  vec3 l = vec3(dot(to_light, t), dot(to_light, b), max(dot(to_light, n), 0.0));
  vec2 p = l.xy / max(abs(l.x) + abs(l.y) + l.z, 1e-20);
  vec2 st = vec2(p.x + p.y, p.x - p.y);
  int r = u_ltt_resolution;
  float r1 = float(r - 1);
  vec2 f = clamp((st + 1.0) * 0.5 * r1, 0.0, r1);
  // A direction on or below the horizon (l.z = 0) maps onto the grid's
  // border, where float rounding leaves f a few ulps inside: snap it there,
  // as lookup()'s double arithmetic has it, so that the row or column
  // beyond gets no weight (a trapped horizon row stays trapped).
  f = mix(f, vec2(0.0), lessThan(f, vec2(1e-5)));
  f = mix(f, vec2(r1), greaterThan(f, vec2(r1 - 1e-5)));
  vec2 f0 = min(floor(f), vec2(r1 - 1.0));
  vec2 a = f - f0;
  int x0 = int(f0.x), y0 = int(f0.y);
  Transport o;
  o.exit = vec3(0.0);
  o.dir = vec3(0.0);
  o.transmittance = 0.0;
  o.path = 0.0;
  o.bounces = 0u;
  o.leaves = false;
  other = o;
  dist = -1.0;

  // Bicubic: stencil k = (column x0 - 1 + (k & 3), row y0 - 1 + (k >> 2)).
  LttEntry e[16];
  bool ok[16], in_grid[16];
  for (int k = 0; k < 16; ++k) {
    int x = x0 + (k & 3) - 1, y = y0 + (k >> 2) - 1;
    in_grid[k] = x >= 0 && y >= 0 && x < r && y < r;
    e[k].leaves = false;
    if (in_grid[k]) e[k] = ltt_entry(vertex, x, y);
    ok[k] = in_grid[k] && e[k].leaves;
  }
  uint bounces = e[5].bounces;
  for (int k = 0; k < 16; ++k) ok[k] = ok[k] && e[k].bounces == bounces && dot(e[k].dir, e[5].dir) >= LTT_SAME_EXIT_COS;
  LttEntry ref = e[5];
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
  } else {
    // Where the inner 2 x 2 (stencil 5, 6, 9, 10) does not leave alike: the
    // class of the heaviest leaving corner fitted over the stencil, the
    // transmittance scaled by the leaving share of the bilinear weight.
    float w[4];
    int best = -1;
    for (int k = 0; k < 4; ++k) {
      int dx = k & 1, dy = k >> 1;
      w[k] = (dx == 1 ? a.x : 1.0 - a.x) * (dy == 1 ? a.y : 1.0 - a.y);
      if (!e[5 + dx + 4 * dy].leaves) w[k] = 0.0;
      if (w[k] > 0.0 && (best < 0 || w[k] > w[best])) best = k;
    }
    if (best < 0) return o;
    best = ltt_side_of_switch(vertex, x0, y0, e, a, w, best);
    ref = e[5 + (best & 1) + 4 * (best >> 1)];
    float leaving = w[0] + w[1] + w[2] + w[3];
    ltt_fit(e, in_grid, ref, a, o);  // ref itself is one of them
    o.transmittance *= leaving;
  }
  if (!want_other) return o;

  // The nearest leaving entry of another class, and that class's fit.
  int near = -1;
  float near_d2 = 1e9;
  for (int k = 0; k < 16; ++k) {
    if (!(in_grid[k] && e[k].leaves) || ltt_alike(e[k], ref)) continue;
    vec2 q = vec2(float(k & 3) - 1.0, float(k >> 2) - 1.0) - a;
    if (dot(q, q) < near_d2) {
      near_d2 = dot(q, q);
      near = k;
    }
  }
  if (near < 0 || !ltt_fit(e, in_grid, e[near], a, other)) return o;
  // The switch between the two classes: per cell of the stencil the points
  // stored on its edges whose ends are one of each class; two make a
  // segment, other counts are taken as points.
  LttEntry oref = e[near];
  for (int cell = 0; cell < 9; ++cell) {
    int k00 = (cell % 3) + 4 * (cell / 3);
    int ends[8] = int[8](k00, k00 + 1, k00 + 4, k00 + 5, k00, k00 + 4, k00 + 1, k00 + 5);
    vec2 pts[4];
    int count = 0;
    for (int s = 0; s < 4; ++s) {
      int i = ends[2 * s], j = ends[2 * s + 1];
      if (!(in_grid[i] && in_grid[j])) continue;
      bool ij = ltt_alike(e[i], ref) && ltt_alike(e[j], oref), ji = ltt_alike(e[i], oref) && ltt_alike(e[j], ref);
      if (!(ij || ji)) continue;
      uint axis = s < 2 ? 0u : 1u;
      float fr = ltt_switch(vertex, x0 + (i & 3) - 1, y0 + (i >> 2) - 1, axis);
      if (fr < 0.0) continue;
      pts[count++] = vec2(float(i & 3) - 1.0, float(i >> 2) - 1.0) - a + (axis == 0u ? vec2(fr, 0.0) : vec2(0.0, fr));
    }
    float dc = 1e9;
    if (count == 2) {
      dc = ltt_segment_distance(pts[0], pts[1]);
    } else {
      for (int s = 0; s < count; ++s) dc = min(dc, length(pts[s]));
    }
    if (count > 0 && (dist < 0.0 || dc < dist)) dist = dc;
  }
  return o;
}

Transport ltt_lookup(uint vertex, vec3 n, vec3 to_light) {
  Transport other;
  float dist;
  return ltt_lookup_ex(vertex, n, to_light, false, other, dist);
}
