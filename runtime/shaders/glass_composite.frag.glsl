#version 450 core
// The glass view, drawn into a target over the glass's rectangle of the
// frame (GlassEngine::draw_glass), copied into the caller's framebuffer:
// colour and depth where glass was drawn (alpha 1), nothing elsewhere.
layout(binding = 0) uniform sampler2D u_color;
layout(binding = 1) uniform sampler2D u_depth;
uniform ivec2 u_origin;  // the rectangle's corner in window pixels
out vec4 o_color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy) - u_origin;
  vec4 c = texelFetch(u_color, p, 0);
  if (c.a == 0.0) discard;
  o_color = c;
  gl_FragDepth = texelFetch(u_depth, p, 0).r;
}
