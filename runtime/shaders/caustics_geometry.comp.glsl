#version 450 core
// The intersection triangle of each listed (illumination volume, reference
// plane) pair (seed 000 §4.4-4.5), in caustics-map texels, and its
// irradiance on the plane by eq. 4-18,
//   I_c = E_in T (A_w cos theta_i) / A_d,
// with A_d its area on the plane (perpendicular to V); cos theta_t and
// e^(-K d) are applied where the map is cast (§4.6), per receiver point.
// A_d is kept above beam / max_magnification so folds where rays cross stay
// finite (docs/caustics.md states the bound). Computed here rather than per
// vertex: compute runs in parallel where vertex processing may not.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 2) readonly buffer Indices { uint indices[]; };
layout(std430, binding = 3) readonly buffer Refracted { vec4 refracted[]; };
layout(std430, binding = 4) readonly buffer Flux { vec2 flux[]; };
layout(std430, binding = 5) readonly buffer List { uint list[]; };
layout(std430, binding = 6) readonly buffer Command { uint cmd[]; };
layout(std430, binding = 7) readonly buffer Planes { vec2 planes[]; };
// Per primitive: (q0, q1), (q2, irradiance, reached), (plane offset, eps, s_u, s_w).
// s_u, s_w: the beam's mean direction of travel d as (d.U / d.V, d.W / d.V),
// so that a receiver with normal n gets I_c (n.V + s_u n.U + s_w n.W) = I_c
// n.d / V.d (beyond the thesis, whose casting takes n.V: under waves the
// light does not arrive along V, docs/caustics.md "Local light direction").
layout(std430, binding = 8) writeonly buffer Primitives { vec4 prims[]; };

uniform vec3 u_origin;
uniform vec3 u_U;
uniform vec3 u_V;
uniform vec3 u_W;
uniform vec3 u_half;
uniform int u_pairs;      // list holds (volume, plane) pairs; else volumes and plane u_plane
uniform int u_plane;
uniform float u_max_magnification;
uniform float u_map_size;

void main() {
  uint p = gl_GlobalInvocationID.x;
  if (p >= cmd[10]) return;
  uint t = u_pairs != 0 ? list[2u * p] : list[p];
  vec2 plane = planes[u_pairs != 0 ? list[2u * p + 1u] : uint(u_plane)];
  vec2 to_texels = u_map_size / (2.0 * u_half.xz);
  vec2 q[3];
  vec2 slopes = vec2(0.0);
  bool reached = true;
  for (int k = 0; k < 3; ++k) {
    uint i = indices[3u * t + uint(k)];
    vec3 rel = positions[i].xyz - u_origin;
    vec3 dir = refracted[i].xyz;
    float s = (dot(rel, u_V) - plane.x) / -dot(dir, u_V);
    reached = reached && s >= 0.0;  // a plane above the water point is not lit through it
    slopes += vec2(dot(dir, u_U), dot(dir, u_W)) / min(dot(dir, u_V), -1e-6) / 3.0;
    vec3 pt = rel + s * dir;
    q[k] = (vec2(dot(pt, u_U), dot(pt, u_W)) + u_half.xz) * to_texels;  // texel coordinates
  }
  // Areas in texels; the irradiance is flux over the area in metres.
  float texel_area = 1.0 / (to_texels.x * to_texels.y);
  float area = 0.5 * abs((q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y));
  vec2 f = flux[t];
  float irradiance = f.x / max(area * texel_area, f.y / u_max_magnification);
  prims[3u * p] = vec4(q[0], q[1]);
  prims[3u * p + 1u] = vec4(q[2], irradiance, reached ? 1.0 : 0.0);
  prims[3u * p + 2u] = vec4(plane, slopes);
}
