#version 450 core
// log(delta + L) per pixel (Reinhard et al. 2002, eq. 1; delta keeps black
// pixels finite), L the Rec. 709 luminance of the linear frame; its mip
// chain averages it for the auto exposure (present.frag).
in vec2 v_uv;
layout(binding = 0) uniform sampler2D u_hdr;
out float o_log_luminance;

void main() {
  const vec3 c = max(texture(u_hdr, v_uv).rgb, vec3(0.0));
  o_log_luminance = log(1e-4 + dot(c, vec3(0.2126, 0.7152, 0.0722)));
}
