// Light-transport-table look-up (seed 002 §4.1; prefixed after #version by
// the renderer). Mirrors caustix::lookup() in formats/src/light_transport.cpp:
// the hemi-octahedral grid around the vertex normal, bilinear between the
// four neighbouring grid directions; entries that do not leave count with
// transmittance 0 and are left out of the averaged exit point and direction.
layout(std430, binding = 1) readonly buffer Table { uint table[]; };

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

Transport ltt_lookup(uint vertex, vec3 n, vec3 to_light) {
  vec3 t, b;
  ltt_frame(n, t, b);
  vec3 l = vec3(dot(to_light, t), dot(to_light, b), max(dot(to_light, n), 0.0));
  vec2 p = l.xy / max(abs(l.x) + abs(l.y) + l.z, 1e-20);
  vec2 st = vec2(p.x + p.y, p.x - p.y);
  float r1 = float(u_ltt_resolution - 1);
  vec2 f = clamp((st + 1.0) * 0.5 * r1, 0.0, r1);
  vec2 f0 = min(floor(f), vec2(r1 - 1.0));
  vec2 a = f - f0;
  Transport o;
  o.exit = vec3(0.0);
  o.dir = vec3(0.0);
  o.transmittance = 0.0;
  o.path = 0.0;
  float wsum = 0.0;
  for (int k = 0; k < 4; ++k) {
    int dx = k & 1, dy = k >> 1;
    float w = (dx == 1 ? a.x : 1.0 - a.x) * (dy == 1 ? a.y : 1.0 - a.y);
    uint idx = 4u * ((vertex * uint(u_ltt_resolution) + uint(f0.y) + uint(dy)) * uint(u_ltt_resolution) + uint(f0.x) + uint(dx));
    uint w0 = table[idx], w1 = table[idx + 1u], w2 = table[idx + 2u], w3 = table[idx + 3u];
    if (((w3 >> 16) & 0xFFu) != 0u || w <= 0.0) continue;
    vec3 q = vec3(float(w0 & 0xFFFFu), float(w0 >> 16), float(w1 & 0xFFFFu)) / 65535.0;
    wsum += w;
    o.exit += w * mix(u_ltt_exit_min, u_ltt_exit_max, q);
    o.transmittance += w * float(w1 >> 16) / 65535.0;
    o.dir += w * ltt_oct_decode(vec2(float(w2 & 0xFFFFu), float(w2 >> 16)) / 65535.0 * 2.0 - 1.0);
    o.path += w * float(w3 & 0xFFFFu) / 65535.0 * u_ltt_max_path;
  }
  o.leaves = wsum > 0.0;
  if (o.leaves) {
    o.exit /= wsum;
    o.path /= wsum;
    o.dir = normalize(o.dir);
  }
  return o;
}
