#version 450 core
// The water over a body rises by as much as the body's submerged length in
// its column grew since the last push (WaterSimulation::push), so the
// water's volume follows the bodies' submerged volume.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) buffer Heights { float h[]; };

layout(binding = 0) uniform sampler2D u_now;
layout(binding = 1) uniform sampler2D u_before;
uniform uvec2 u_vertices;

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= u_vertices.x || p.y >= u_vertices.y) return;
  ivec2 t = ivec2(p);
  h[p.y * u_vertices.x + p.x] += texelFetch(u_now, t, 0).r - texelFetch(u_before, t, 0).r;
}
