#version 450 core
// The water grid from the application's heights (Engine::set_water_heights*):
// positions at level + h over the grid, normals from central differences of
// h (one-sided at the border), one invocation per grid vertex, into the same
// SSBOs water_update.comp fills from the wave list. Non-finite heights read
// as 0 (GPU-side data cannot be checked on the CPU without a read-back).
layout(local_size_x = 64) in;

layout(std430, binding = 0) writeonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) writeonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 2) readonly buffer Heights { float heights[]; };

uniform uvec2 u_cells;
uniform vec4 u_extent;  // x0, z0, x1, z1
uniform float u_level;

float h_at(uint i, uint j) {
  float h = heights[j * (u_cells.x + 1u) + i];
  return isnan(h) || isinf(h) ? 0.0 : h;
}

void main() {
  uint k = gl_GlobalInvocationID.x;
  uint nx = u_cells.x + 1u;
  if (k >= nx * (u_cells.y + 1u)) return;
  uint i = k % nx, j = k / nx;
  vec2 f = vec2(float(i) / float(u_cells.x), float(j) / float(u_cells.y));
  vec2 xz = mix(u_extent.xy, u_extent.zw, f);
  vec2 cell = (u_extent.zw - u_extent.xy) / vec2(u_cells);
  uint i0 = i > 0u ? i - 1u : i, i1 = min(i + 1u, u_cells.x);
  uint j0 = j > 0u ? j - 1u : j, j1 = min(j + 1u, u_cells.y);
  vec2 grad = vec2((h_at(i1, j) - h_at(i0, j)) / (float(i1 - i0) * cell.x),
                   (h_at(i, j1) - h_at(i, j0)) / (float(j1 - j0) * cell.y));
  positions[k] = vec4(xz.x, u_level + h_at(i, j), xz.y, 1.0);
  normals[k] = vec4(normalize(vec3(-grad.x, 1.0, -grad.y)), 0.0);
}
