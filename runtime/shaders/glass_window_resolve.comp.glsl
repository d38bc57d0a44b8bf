#version 450 core
// Glass focus windows drawn coarse (docs/glass-focus.md, "A window
// per wavelength"): where glass disperses the window's layers were drawn
// at half their texels a side, into a square of the same layers
// beside the window (glass.cpp, window_squares); here each window texel
// takes that light, bilinearly interpolated at its centre. The coarse
// texels tile the window's exactly (coarse texel m covers window texels 2m
// and 2m + 1 per axis), and a coarse texel's weights over the window
// texels sum to 4 (0.25, 0.75, 0.75, 0.25 per axis; 1, 0.75, 0.25 at a
// clamped edge), the ratio of their areas: the light is kept exactly, and
// an irradiance linear across the coarse texels is kept too (their box
// means are its values at their centres). The square is cleared after, so
// that the mips see none of it.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform image2DArray u_layers;

uniform int u_side;         // the window's texels a side, from (0, 0)
uniform int u_coarse;       // the coarse square's lower-left texel: (u_coarse, u_coarse)
uniform int u_coarse_side;  // its texels a side: (u_side + 1) / 2
uniform int u_first_layer;  // the window's first layer (the planes' count)

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= u_side || p.y >= u_side) return;
  int layer = u_first_layer + int(gl_GlobalInvocationID.z);
  // This texel's centre in coarse texels, relative to their centres.
  vec2 c = (vec2(p) + 0.5) * 0.5 - 0.5;
  ivec2 c0 = ivec2(floor(c));
  vec2 f = c - vec2(c0);
  ivec2 lo = clamp(c0, ivec2(0), ivec2(u_coarse_side - 1)) + u_coarse;
  ivec2 hi = clamp(c0 + 1, ivec2(0), ivec2(u_coarse_side - 1)) + u_coarse;
  vec3 a = imageLoad(u_layers, ivec3(lo.x, lo.y, layer)).rgb, b = imageLoad(u_layers, ivec3(hi.x, lo.y, layer)).rgb;
  vec3 d = imageLoad(u_layers, ivec3(lo.x, hi.y, layer)).rgb, e = imageLoad(u_layers, ivec3(hi.x, hi.y, layer)).rgb;
  imageStore(u_layers, ivec3(p, layer), vec4(mix(mix(a, b, f.x), mix(d, e, f.x), f.y), 1.0));
}
