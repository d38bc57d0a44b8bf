#version 450 core
// One substep of the interactive water (water_sim.h; docs/water-simulation.md):
// the linear wave equation dv/dt = c^2 lap(h) - gamma v, dh/dt = v, by
// semi-implicit Euler with implicit damping, plus a diffusion of h,
// nu lap(h), that damps the shortest waves (rate nu k^2).
//
// The Laplacian: on square cells the isotropic nine-point stencil
// (4 x edges + 1 x diagonals - 20 h) / (6 d^2) (rings stay round where the
// five-point one squares them); else the five-point one. Both are sums of
// fluxes w (h_q - h_p), and a neighbour beyond the border reads the mirror
// image across the wall half a spacing out, i.e. the nearest vertex inside:
// every flux enters two vertices with opposite signs, so sum(h) is
// conserved, and the walls reflect.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer HeightsIn { float h_in[]; };
layout(std430, binding = 1) writeonly buffer HeightsOut { float h_out[]; };
layout(std430, binding = 2) buffer Velocities { float vel[]; };

uniform uvec2 u_vertices;  // columns, rows
uniform vec2 u_inv_d2;     // 1 / dx^2, 1 / dz^2
uniform bool u_isotropic;  // square cells: the nine-point stencil (with 1 / (dx dz))
uniform float u_dt;
uniform float u_c2;        // c^2
uniform float u_damping;   // gamma
uniform float u_diffusion; // nu

float h_at(ivec2 p) {
  p = clamp(p, ivec2(0), ivec2(u_vertices) - 1);
  return h_in[uint(p.y) * u_vertices.x + uint(p.x)];
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= int(u_vertices.x) || p.y >= int(u_vertices.y)) return;
  uint k = uint(p.y) * u_vertices.x + uint(p.x);
  float h = h_in[k];
  float lap;
  if (u_isotropic) {
    float edges = (h_at(p + ivec2(1, 0)) - h) + (h_at(p - ivec2(1, 0)) - h) + (h_at(p + ivec2(0, 1)) - h) +
                  (h_at(p - ivec2(0, 1)) - h);
    float corners = (h_at(p + ivec2(1, 1)) - h) + (h_at(p + ivec2(-1, 1)) - h) + (h_at(p + ivec2(1, -1)) - h) +
                    (h_at(p - ivec2(1, 1)) - h);
    lap = (4.0 * edges + corners) * (sqrt(u_inv_d2.x * u_inv_d2.y) / 6.0);
  } else {
    lap = ((h_at(p + ivec2(1, 0)) - h) + (h_at(p - ivec2(1, 0)) - h)) * u_inv_d2.x +
          ((h_at(p + ivec2(0, 1)) - h) + (h_at(p - ivec2(0, 1)) - h)) * u_inv_d2.y;
  }
  float v = (vel[k] + u_dt * u_c2 * lap) / (1.0 + u_dt * u_damping);
  vel[k] = v;
  h_out[k] = h + u_dt * (v + u_diffusion * lap);
}
