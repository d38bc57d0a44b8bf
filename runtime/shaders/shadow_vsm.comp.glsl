#version 450 core
// shadow_vsm.comp: variance shadow maps (Donnelly & Lauritzen 2006,
// "Variance shadow maps", §3; timofy 2009's blog: "you must filter the depth
// map ... a filter width of 5"). The moments (d, d^2) of a directional
// light's shadow depth, box-filtered over u_radius texels each way in two
// separable passes: 0 reads the depth map, filters along x; 1 filters the
// result along y into the moments map the include samples (caustix.glsl,
// Chebyshev's bound).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D u_depth;  // pass 0 (a sampler without comparison)
layout(binding = 1) uniform sampler2D u_src;    // pass 1: pass 0's moments
layout(rg32f, binding = 0) writeonly uniform image2D u_out;
uniform int u_pass;
uniform int u_radius;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(u_out);
  if (any(greaterThanEqual(p, size))) return;
  ivec2 axis = u_pass == 0 ? ivec2(1, 0) : ivec2(0, 1);
  vec2 sum = vec2(0.0);
  for (int k = -u_radius; k <= u_radius; ++k) {
    ivec2 q = clamp(p + k * axis, ivec2(0), size - 1);
    if (u_pass == 0) {
      float d = texelFetch(u_depth, q, 0).r;
      sum += vec2(d, d * d);
    } else {
      sum += texelFetch(u_src, q, 0).rg;
    }
  }
  imageStore(u_out, p, vec4(sum / float(2 * u_radius + 1), 0.0, 0.0));
}
