#version 450 core
// The sample's receivers: an object's mesh (Engine::draw_object's
// attributes) to world and clip space. u_clip_plane (world, a.x + b >= 0
// kept) splits the scene at the water for draw_water()'s refraction and
// reflection textures, where the engine enables GL_CLIP_DISTANCE0.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;  // texture coordinates where the mesh has them ((0, 0) otherwise)
layout(location = 3) in vec4 a_color;  // vertex colour where the mesh has one (the renderer sets (1, 1, 1, 1) otherwise)

uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_proj;
uniform vec4 u_clip_plane;

out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
out vec4 v_color;

void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_uv = a_uv;
  v_color = a_color;
  gl_Position = u_view_proj * world;
  gl_ClipDistance[0] = dot(u_clip_plane, world);
}
