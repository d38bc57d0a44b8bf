#version 450 core
// One substep of the interactive water (water_sim.h; docs/water-simulation.md):
// the linear wave equation dv/dt = c^2 lap(h) - gamma v, dh/dt = v, by
// semi-implicit Euler with implicit damping. The Laplacian is a sum of
// fluxes (h_neighbour - h) / d^2 over the neighbours that exist: the grid's
// border has no flux across it (reflecting walls), and every flux enters
// its two vertices with opposite signs, so sum(h) is conserved.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer HeightsIn { float h_in[]; };
layout(std430, binding = 1) writeonly buffer HeightsOut { float h_out[]; };
layout(std430, binding = 2) buffer Velocities { float vel[]; };

uniform uvec2 u_vertices;  // columns, rows
uniform vec2 u_inv_d2;     // 1 / dx^2, 1 / dz^2
uniform float u_dt;
uniform float u_c2;        // c^2
uniform float u_damping;   // gamma

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= u_vertices.x || p.y >= u_vertices.y) return;
  uint k = p.y * u_vertices.x + p.x;
  float h = h_in[k];
  float lap_x = 0.0, lap_z = 0.0;
  if (p.x > 0u) lap_x += h_in[k - 1u] - h;
  if (p.x + 1u < u_vertices.x) lap_x += h_in[k + 1u] - h;
  if (p.y > 0u) lap_z += h_in[k - u_vertices.x] - h;
  if (p.y + 1u < u_vertices.y) lap_z += h_in[k + u_vertices.x] - h;
  float lap = lap_x * u_inv_d2.x + lap_z * u_inv_d2.y;
  float v = (vel[k] + u_dt * u_c2 * lap) / (1.0 + u_dt * u_damping);
  vel[k] = v;
  h_out[k] = h + u_dt * v;
}
