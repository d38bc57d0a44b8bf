#version 450 core
// log(delta + L) per pixel (Reinhard et al. 2002, eq. 1; delta keeps black
// pixels finite), L the Rec. 709 luminance of the linear frame; its mip
// chain averages it for the auto exposure (present.frag). The exposure
// meters the lit scene, not the sky: a pixel where nothing was drawn
// (depth 1) weighs 1/1000 of one that shows a surface, so the sky counts
// only in a frame that is all sky. R is the weighted log luminance, G the
// weight: their means' ratio is the weighted log-average.
in vec2 v_uv;
layout(binding = 0) uniform sampler2D u_hdr;
layout(binding = 2) uniform sampler2D u_depth;
out vec2 o_log_luminance;

void main() {
  const vec3 c = max(texture(u_hdr, v_uv).rgb, vec3(0.0));
  const float w = texture(u_depth, v_uv).r < 1.0 ? 1.0 : 1e-3;
  o_log_luminance = w * vec2(log(1e-4 + dot(c, vec3(0.2126, 0.7152, 0.0722))), 1.0);
}
