#version 450 core
// Dispersion in the water-caustics passes (docs/dispersion.md).
// After one wavelength's pass has drawn the caustics map's level 0 (E, E
// d.U/d.V, E d.W/d.V), add it into the sums over the traced wavelengths:
// the mean of the bin's three CIE-to-linear-sRGB weights times all three
// channels into u_sum, and the three weights times E into u_color (the
// spectral integral per channel). The weights of all bins sum to 1 per
// channel, so the mean weights do too: u_sum is an irradiance of the same
// scale as a one-wavelength map. On the last wavelength the sum is written
// back into the map, whose presence and mips the caller then makes as
// for one wavelength.
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = 0) uniform image2D u_map;
layout(rgba32f, binding = 1) uniform image2D u_sum;
layout(rgba32f, binding = 2) uniform image2D u_color;

uniform int u_size;
uniform vec3 u_rgb;  // this wavelength's bin weights
uniform int u_first;
uniform int u_last;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= u_size || p.y >= u_size) return;
  vec3 m = imageLoad(u_map, p).rgb;
  vec3 sum = u_first != 0 ? vec3(0.0) : imageLoad(u_sum, p).rgb;
  vec3 color = u_first != 0 ? vec3(0.0) : imageLoad(u_color, p).rgb;
  sum += (u_rgb.r + u_rgb.g + u_rgb.b) / 3.0 * m;
  color += u_rgb * m.r;
  imageStore(u_color, p, vec4(color, 0.0));
  if (u_last != 0) {
    imageStore(u_map, p, vec4(sum, 0.0));
  } else {
    imageStore(u_sum, p, vec4(sum, 0.0));
  }
}
