#version 450 core
// Bodies pushing the interactive water (WaterSimulation::push): the mesh
// seen from above by an orthographic projection whose pixel centres are the
// water grid's vertices; each fragment carries its world height.
layout(location = 0) in vec3 a_position;

uniform mat4 u_model;
uniform vec4 u_extent;  // x0 - dx/2, z0 - dz/2, x1 + dx/2, z1 + dz/2

out float v_y;

void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_y = world.y;
  vec2 ndc = 2.0 * (world.xz - u_extent.xy) / (u_extent.zw - u_extent.xy) - 1.0;
  gl_Position = vec4(ndc, 0.0, 1.0);
}
