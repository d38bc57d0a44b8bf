#version 450 core
// causticmap_blur.comp: the two-pass baseline of the splats (the blog's
// 5 x 5 Gaussian after Wyman): photons splatted into one texel each, then
// a separable Gaussian of standard deviation u_sigma, truncated at 3 sigma
// and normalised, along x (u_axis 0) then y (1). Alpha (the receivers'
// coordinate along V) is copied from u_keep.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D u_source;
layout(binding = 1) uniform sampler2D u_keep;
layout(rgba32f, binding = 0) writeonly uniform image2D u_target;
uniform int u_axis;
uniform float u_sigma;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = textureSize(u_source, 0);
  if (any(greaterThanEqual(p, size))) return;
  int r = int(ceil(3.0 * u_sigma));
  vec3 sum = vec3(0.0);
  float wsum = 0.0;
  for (int k = -r; k <= r; ++k) {
    float w = u_sigma > 0.0 ? exp(-0.5 * float(k * k) / (u_sigma * u_sigma)) : 1.0;
    wsum += w;
    ivec2 q = p + (u_axis == 0 ? ivec2(k, 0) : ivec2(0, k));
    if (all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size))) sum += w * texelFetch(u_source, q, 0).rgb;
  }
  imageStore(u_target, p, vec4(sum / wsum, texelFetch(u_keep, p, 0).a));
}
