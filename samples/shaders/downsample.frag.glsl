#version 450 core
// Supersampling's resolve (docs/display.md): each output pixel the mean of
// its factor x factor block of the frame rendered that much larger -- the
// pixel-box filter, in linear radiance before any tone mapping.
layout(binding = 0) uniform sampler2D u_frame;
uniform int u_factor;
out vec4 o_color;

void main() {
  const ivec2 base = ivec2(gl_FragCoord.xy) * u_factor;
  vec4 sum = vec4(0.0);
  for (int j = 0; j < u_factor; ++j) {
    for (int i = 0; i < u_factor; ++i) sum += texelFetch(u_frame, base + ivec2(i, j), 0);
  }
  o_color = sum / float(u_factor * u_factor);
}
