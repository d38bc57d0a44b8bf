#version 450 core
// causticmap_capture.frag (after mesh.vert): the scene seen from the light
// for the image-space caustic maps (timofy 2009; Shah et al. 2007, §3.1).
// Casters (u_caster = 1): world position and object index + 1 (0: empty),
// and the world normal. Receivers (u_caster = 0): into the caustic map its
// alpha, the coordinate along V of the first receiver surface (the
// include's visibility test), and into the receiver map the normal and the
// same coordinate (the landing iteration and the splats' cosine read it).
in vec3 v_world;
in vec3 v_normal;
uniform int u_caster;
uniform float u_object;  // object index + 1
uniform vec3 u_origin;   // the light frame's origin and V (towards the light)
uniform vec3 u_v;
layout(location = 0) out vec4 o_first;
layout(location = 1) out vec4 o_second;
void main() {
  vec3 n = normalize(v_normal);
  float v = dot(v_world - u_origin, u_v);
  if (u_caster != 0) {
    o_first = vec4(v_world, u_object);
    o_second = vec4(n, v);
  } else {
    o_first = vec4(0.0, 0.0, 0.0, v);
    o_second = vec4(n, v);
  }
}
