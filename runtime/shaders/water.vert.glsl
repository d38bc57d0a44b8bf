#version 450 core
// The water surface as animated by water_update.comp (vertex pulling from
// its buffers, so every pass sees the same surface).
layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) readonly buffer Normals { vec4 normals[]; };

uniform mat4 u_view_proj;

out vec3 v_world;
out vec3 v_normal;

void main() {
  v_world = positions[gl_VertexID].xyz;
  v_normal = normals[gl_VertexID].xyz;
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
