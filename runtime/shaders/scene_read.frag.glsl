#version 450 core
// Copies a rectangle of the caller's scene colour and depth (gl/scene_inputs.h:
// any floating-point or normalised colour format, any depth format, 2D or
// 2D multisample) into the bound target from (0, 0): the colour averaged
// over its samples, the depth the nearest of its samples (what the glass
// and the media test their fragments against). SceneReader prefixes
// CAUSTIX_COLOR_MS and CAUSTIX_DEPTH_MS for the multisampled variants.
#ifdef CAUSTIX_COLOR_MS
layout(binding = 0) uniform sampler2DMS u_color;
#else
layout(binding = 0) uniform sampler2D u_color;
#endif
#ifdef CAUSTIX_DEPTH_MS
layout(binding = 1) uniform sampler2DMS u_depth;
#else
layout(binding = 1) uniform sampler2D u_depth;
#endif
uniform ivec2 u_offset;  // the rectangle's corner in the caller's textures
uniform bool u_has_color;
uniform bool u_has_depth;
out vec4 o_color;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy) + u_offset;
  vec4 c = vec4(0.0);
  if (u_has_color) {
#ifdef CAUSTIX_COLOR_MS
    int n = textureSamples(u_color);
    for (int s = 0; s < n; ++s) c += texelFetch(u_color, p, s);
    c /= float(n);
#else
    c = texelFetch(u_color, p, 0);
#endif
  }
  o_color = c;
  float d = 1.0;
  if (u_has_depth) {
#ifdef CAUSTIX_DEPTH_MS
    int n = textureSamples(u_depth);
    for (int s = 0; s < n; ++s) d = min(d, texelFetch(u_depth, p, s).r);
#else
    d = texelFetch(u_depth, p, 0).r;
#endif
  }
  gl_FragDepth = d;
}
