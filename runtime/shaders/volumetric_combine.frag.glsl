#version 450 core
// Combines the illumination volume into one caustics map: each texel takes
// the slice that holds the receiver's surface nearest the light.
layout(binding = 0) uniform sampler2DArray u_slices;       // masks
layout(binding = 1) uniform sampler2DArray u_illumination;  // caustics per slice
uniform int u_count;
out vec4 o_irradiance;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  o_irradiance = vec4(0.0);
  for (int i = 0; i < u_count; ++i) {
    if (texelFetch(u_slices, ivec3(p, i), 0).r > 0.5) {
      o_irradiance = texelFetch(u_illumination, ivec3(p, i), 0);
      return;
    }
  }
}
