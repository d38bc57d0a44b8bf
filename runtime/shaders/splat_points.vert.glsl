#version 450 core
// Mihalik 2008 ch. 8, GPU variant: the photon texture, copied into a vertex
// buffer, drawn as points at their uv (orthographic 0..1), carrying their
// irradiance; photons that missed go outside the view. Each point covers
// the 2 x 2 texels around its photon, which splat_points.frag weights
// bilinearly (a tent filter: the weights sum to 1, so no light is lost or
// gained, and a regular photon grid does not beat against the texels).
layout(location = 0) in uvec4 a_photon;  // u, v, irradiance (float bits), direction slopes (two halves)
uniform float u_size;                    // caustics map texels a side
out float v_irradiance;
out vec2 v_slopes;
out vec2 v_photon;  // in texels
void main() {
  v_irradiance = uintBitsToFloat(a_photon.z);
  v_slopes = unpackHalf2x16(a_photon.w);
  v_photon = uintBitsToFloat(a_photon.xy) * u_size;
  vec2 corner = floor(v_photon - 0.5) + 1.0;  // between the four nearest texel centres
  gl_Position = v_irradiance > 0.0 ? vec4(corner / u_size * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
  gl_PointSize = 2.0;
}
