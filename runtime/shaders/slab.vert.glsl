#version 450 core
// Renders a receiver in its frame's orthographic view along -V (eq. 4-10..
// 4-13), keeping only the depths in [u_near, u_far] along V (u_near > u_far):
// the volumetric baseline's slice images, and the run-time position map.
layout(location = 0) in vec3 a_position;

uniform mat4 u_model;
uniform vec3 u_origin;
uniform vec3 u_U;
uniform vec3 u_V;
uniform vec3 u_W;
uniform vec3 u_half;
uniform float u_near;
uniform float u_far;

out float v_depth;

void main() {
  vec3 rel = (u_model * vec4(a_position, 1.0)).xyz - u_origin;
  vec3 c = vec3(dot(rel, u_U), dot(rel, u_V), dot(rel, u_W));
  v_depth = c.y;
  // Clip z: -1 at u_near (toward the light), +1 at u_far.
  gl_Position = vec4(c.x / u_half.x, c.z / u_half.z, 2.0 * (u_near - c.y) / (u_near - u_far) - 1.0, 1.0);
}
