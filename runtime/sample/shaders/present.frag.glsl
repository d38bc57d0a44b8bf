#version 450 core
// Linear HDR -> display: exposure, a soft shoulder (1 - e^-x), sRGB encoding.
in vec2 v_uv;
layout(binding = 0) uniform sampler2D u_hdr;
uniform float u_exposure;
out vec4 o_color;

vec3 srgb_encode(vec3 c) {
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  vec3 c = texture(u_hdr, v_uv).rgb * u_exposure;
  c = 1.0 - exp(-max(c, vec3(0.0)));
  o_color = vec4(srgb_encode(c), 1.0);
}
