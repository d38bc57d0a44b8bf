#version 450 core
// The target as the virtual camera sees it (Iwasaki et al. §4.2, §4.3): world
// normal of the first surface, facing the light, and its frame-V coordinate
// (depth from the virtual camera), for cos(gamma) and for shadows.
in vec3 v_world;
in vec3 v_normal;

uniform vec3 u_origin;
uniform vec3 u_V;

out vec4 o_target;

void main() {
  vec3 n = normalize(v_normal);
  if (dot(n, u_V) < 0.0) n = -n;  // open surfaces are lit from either side
  o_target = vec4(n, dot(v_world - u_origin, u_V));
}
