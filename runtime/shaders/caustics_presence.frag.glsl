#version 450 core
// The caustics map's alpha: 1 where the receiver has a first
// surface seen from the light (its position map holds a depth), 0 where the
// frame is empty. Written after the irradiance (colour mask: alpha only)
// and before the mip chain, whose levels then hold the covered fraction;
// caustix.glsl divides the filtered irradiance by it, so filtering at the
// receiver's outline seen from the light (a sphere's terminator) does not
// mix in empty texels.
layout(binding = 0) uniform sampler2D u_position;  // nearest
in vec2 v_uv;
out vec4 o_irradiance;
void main() {
  o_irradiance = vec4(0.0, 0.0, 0.0, texture(u_position, v_uv).r > -1.0e29 ? 1.0 : 0.0);
}
