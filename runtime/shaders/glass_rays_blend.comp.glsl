#version 450 core
// Dispersive glass between two light-transport tables (
// docs/dispersion.md): the outgoing rays of one traced wavelength from the
// rays of the two tables whose indices n_a, n_b bracket its index n,
// t = (n - n_a) / (n_b - n_a) -- per vertex, the linear term of the rays'
// Taylor expansion in n, the "per-entry derivative" measured against
// tables baked at the wavelength itself. Where both leave alike (exit
// directions within 30 degrees, LTT_SAME_EXIT_COS) exit point, direction
// (renormalised) and colour are interpolated; elsewhere the path changes
// class between the tables (total internal reflection begins, another
// face) and the nearer table's ray is taken whole.
layout(local_size_x = 64) in;

layout(std430, binding = 2) buffer RaysA { vec4 rays_a[]; };           // table a's rays in, the blend out
layout(std430, binding = 5) readonly buffer RaysB { vec4 rays_b[]; };  // table b's rays

uniform uint u_vertex_count;
uniform float u_t;

// One ray (exit + valid, dir + class, colour + w) of each table blended
// into rays_a at `base` (0: the vertex's own class, 3: the other class).
// The colour's w (the distance to the switch) is interpolated where both
// know it, else the nearer table's.
void blend(uint base) {
  vec4 ea = rays_a[base], eb = rays_b[base];
  vec4 da = rays_a[base + 1u], db = rays_b[base + 1u];
  vec4 ca = rays_a[base + 2u], cb = rays_b[base + 2u];
  if (ea.w > 0.0 && eb.w > 0.0 && da.w == db.w && dot(da.xyz, db.xyz) > 0.8660254) {
    rays_a[base] = vec4(mix(ea.xyz, eb.xyz, u_t), 1.0);
    rays_a[base + 1u] = vec4(normalize(mix(da.xyz, db.xyz, u_t)), da.w);
    // signed: a bin's weight can be negative
    float w = ca.w >= 0.0 && cb.w >= 0.0 ? mix(ca.w, cb.w, u_t) : (u_t >= 0.5 ? cb.w : ca.w);
    rays_a[base + 2u] = vec4(mix(ca.rgb, cb.rgb, u_t), w);
  } else if (u_t >= 0.5) {
    rays_a[base] = eb;
    rays_a[base + 1u] = db;
    rays_a[base + 2u] = cb;
  }
}

void main() {
  uint v = gl_GlobalInvocationID.x;
  if (v >= u_vertex_count) return;
  blend(6u * v);
  blend(6u * v + 3u);
}
