#version 450 core
// Linear HDR -> display (docs/display.md): exposure, optionally the auto
// exposure's key, a tone curve, sRGB encoding.
in vec2 v_uv;
layout(binding = 0) uniform sampler2D u_hdr;
// Mip-mapped log luminance of the frame (luminance.frag); its last level is
// the log-average (Reinhard et al. 2002, eq. 1).
layout(binding = 1) uniform sampler2D u_log_luminance;
uniform float u_exposure;      // 2^EV
uniform bool u_auto_exposure;
uniform float u_last_level;
uniform int u_tone_map;        // 0 filmic, 1 exponential
out vec4 o_color;

vec3 srgb_encode(vec3 c) {
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

// ACES's reference rendering and output transforms as fitted by Narkowicz
// (2015, "ACES Filmic Tone Mapping Curve"), with his 0.6 pre-scale so that
// an input of 1 lands where ACES puts it: a toe below ~0.1, mid grey 0.18
// -> 0.14 (sRGB 0.41), 1 -> 0.67, a shoulder reaching 0.90 at 3 and 0.97
// at 6 (1 - e^-x is at 0.63, 0.95 and 0.998 there).
vec3 filmic(vec3 x) {
  x *= 0.6;
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

void main() {
  vec3 c = max(texture(u_hdr, v_uv).rgb, vec3(0.0)) * u_exposure;
  if (u_auto_exposure) {
    const vec2 m = textureLod(u_log_luminance, vec2(0.5), u_last_level).rg;
    c *= 0.18 / exp(m.r / max(m.g, 1e-6));
  }
  c = u_tone_map == 0 ? filmic(c) : 1.0 - exp(-c);
  o_color = vec4(srgb_encode(c), 1.0);
}
