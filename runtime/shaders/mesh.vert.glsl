#version 450 core
// Object-space mesh -> world and clip space. Used by the receiver passes and
// the shadow-map passes (with the light's view-projection). u_clip_plane
// (world, a.x + b >= 0 kept) splits the scene at the water for the
// refraction and reflection textures (Mihalik 2008 §5.1-5.2); it acts only
// where the renderer enables GL_CLIP_DISTANCE0.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;  // texture coordinates where the mesh has them ((0, 0) otherwise)

uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_proj;
uniform vec4 u_clip_plane;
// Where the pass draws into a window of the frame (the glass view draws
// into a target that covers only the glass's rectangle): NDC x, y scaled
// and offset (identity by default).
uniform vec4 u_ndc_window = vec4(1.0, 1.0, 0.0, 0.0);

out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;

void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_uv = a_uv;
  gl_Position = u_view_proj * world;
  gl_Position.xy = gl_Position.xy * u_ndc_window.xy + u_ndc_window.zw * gl_Position.w;
  gl_ClipDistance[0] = dot(u_clip_plane, vec4(world.xyz, 1.0));
}
