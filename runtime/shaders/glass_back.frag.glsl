#version 450 core
// The glass's back faces seen from the camera (front faces culled, the
// nearest back face kept): world position and outward normal per pixel,
// for glass_nearby.frag's exit iteration (Wyman 2005, "An approximate
// image-space approach for interactive refraction": the back faces stand
// in for the far side of the object).
in vec3 v_world;
in vec3 v_normal;
layout(location = 0) out vec4 o_position;  // world, 1 where covered
layout(location = 1) out vec4 o_normal;    // world, outward
void main() {
  o_position = vec4(v_world, 1.0);
  o_normal = vec4(normalize(v_normal), 0.0);
}
