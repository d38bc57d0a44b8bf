#version 450 core
// Mihalik 2008 §9.3: the glow texture is the highlight image filtered over 13
// texels, each weighted 1/13, and added to the frame (additive blending).
// The paper's 13 lie on the two diagonals of a 7x7 grid (u_star): every
// isolated glint prints an X, as on thesis_teapot's pool wall.
// By default they lie on a disc instead: the centre, six at 1.5 texels and
// six at 3 texels turned by 30 degrees, so a glint glows round.
in vec2 v_uv;
layout(binding = 0) uniform sampler2D u_highlight;  // in units of u_scale (half floats)
uniform bool u_star;
uniform float u_scale;  // the sun's strength the highlight was divided by
out vec4 o_color;

void main() {
  vec2 texel = 1.0 / vec2(textureSize(u_highlight, 0));
  vec3 sum = texture(u_highlight, v_uv).rgb;
  if (u_star) {
    for (int k = 1; k <= 3; ++k) {
      sum += texture(u_highlight, v_uv + texel * vec2(k, k)).rgb + texture(u_highlight, v_uv + texel * vec2(-k, -k)).rgb +
             texture(u_highlight, v_uv + texel * vec2(k, -k)).rgb + texture(u_highlight, v_uv + texel * vec2(-k, k)).rgb;
    }
  } else {
    const float kPi = 3.14159265358979;
    for (int k = 0; k < 6; ++k) {
      float a = float(k) * kPi / 3.0;
      sum += texture(u_highlight, v_uv + texel * 1.5 * vec2(cos(a), sin(a))).rgb +
             texture(u_highlight, v_uv + texel * 3.0 * vec2(cos(a + kPi / 6.0), sin(a + kPi / 6.0))).rgb;
    }
  }
  o_color = vec4(sum * (u_scale / 13.0), 0.0);
}
