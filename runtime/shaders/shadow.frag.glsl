#version 450 core
// Shadow-map pass. Directional lights keep the rasterised depth; point lights
// store distance / far so one cube map covers every direction.
in vec3 v_world;
in vec3 v_normal;

uniform int u_linear_depth;
uniform vec3 u_light_position;
uniform float u_far;

void main() {
  if (u_linear_depth != 0) gl_FragDepth = length(v_world - u_light_position) / u_far;
  else gl_FragDepth = gl_FragCoord.z;
}
