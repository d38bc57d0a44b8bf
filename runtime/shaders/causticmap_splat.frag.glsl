#version 450 core
// causticmap_splat.frag: a photon's share of a texel as irradiance on the
// receiver there. The texel covers u_texel_area m^2 across the light's
// direction, so |n . V| / u_texel_area of it on the receiver: E = Phi w
// |n . V| / a (flux per receiver area; Shah et al. weight by the surface's
// cosine). Additive blending sums the photons (rgb); alpha keeps the
// receiver's coordinate along V (written by the capture pass). In the
// focus window (causticmap_splat.vert) the receiver is the main map's
// texel under the fragment, and the texel's area u_texel_area v_map.z^2.
in vec3 v_flux;
in vec2 v_centre;
in float v_norm;
in float v_sigma;
flat in vec3 v_map;
uniform vec2 u_origin;
uniform float u_texel_area;
uniform vec3 u_v;
layout(binding = 0) uniform sampler2D u_receivers;  // normal, V
out vec4 o_color;
float gauss(float d) { return v_sigma > 0.0 ? exp(-0.5 * d * d / (v_sigma * v_sigma)) : 1.0; }
void main() {
  vec2 d = gl_FragCoord.xy - v_centre;
  float w = gauss(d.x) * gauss(d.y) * v_norm;
  ivec2 under = ivec2(floor((gl_FragCoord.xy - u_origin) * v_map.z + v_map.xy));
  vec3 n = texelFetch(u_receivers, clamp(under, ivec2(0), textureSize(u_receivers, 0) - 1), 0).xyz;
  o_color = vec4(v_flux * (w * abs(dot(n, u_v)) / (u_texel_area * v_map.z * v_map.z)), 0.0);
}
