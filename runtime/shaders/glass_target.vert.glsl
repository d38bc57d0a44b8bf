#version 450 core
// Object -> the virtual camera of a target (seed 002 §4.2): orthographic
// along -V over the frame's U, W extents; nearer the light = smaller depth.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform vec3 u_origin;
uniform vec3 u_U;
uniform vec3 u_V;
uniform vec3 u_W;
uniform vec3 u_half;

out vec3 v_world;
out vec3 v_normal;

void main() {
  vec3 w = (u_model * vec4(a_position, 1.0)).xyz;
  v_world = w;
  v_normal = u_normal_matrix * a_normal;
  vec3 r = w - u_origin;
  gl_Position = vec4(dot(r, u_U) / u_half.x, dot(r, u_W) / u_half.z, -dot(r, u_V) / (1.01 * u_half.y), 1.0);
}
