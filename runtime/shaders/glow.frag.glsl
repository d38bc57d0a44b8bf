#version 450 core
// Seed 001 §9.3: the glow texture is the highlight image filtered over the
// 13 texels on the two diagonals of a 7x7 grid, each weighted 1/13; added
// to the frame (additive blending).
in vec2 v_uv;
layout(binding = 0) uniform sampler2D u_highlight;
out vec4 o_color;

void main() {
  vec2 texel = 1.0 / vec2(textureSize(u_highlight, 0));
  vec3 sum = texture(u_highlight, v_uv).rgb;
  for (int k = 1; k <= 3; ++k) {
    sum += texture(u_highlight, v_uv + texel * vec2(k, k)).rgb + texture(u_highlight, v_uv + texel * vec2(-k, -k)).rgb +
           texture(u_highlight, v_uv + texel * vec2(k, -k)).rgb + texture(u_highlight, v_uv + texel * vec2(-k, k)).rgb;
  }
  o_color = vec4(sum / 13.0, 0.0);
}
