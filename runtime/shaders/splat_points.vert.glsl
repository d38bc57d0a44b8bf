#version 450 core
// Mihalik 2008 ch. 8, GPU variant: the photon texture, copied into a vertex
// buffer, drawn as points at their uv (orthographic 0..1), carrying their
// irradiance; photons that missed go outside the view. Beyond the paper,
// the filter that spreads a photon over texels (splat_points.frag) is
// smooth, so that a texel's share of a photon changes with a continuous
// slope as the water moves it: the tent filter over 2 x 2 texels, whose
// slope jumps at every texel centre, made the pool's caustics change from
// frame to frame by more than the water's motion explains
// (docs/temporal.md). Photons fewer than one a texel along a side
// (u_wide) take the quadratic B-spline over the 3 x 3 texels around the
// photon's texel, which also smooths their grid's sampling noise; denser
// ones the cubic 1 - 3 d^2 + 2 |d|^3 over the 2 x 2 texels around the
// photon, narrower than the tent, which keeps the folds' peaks. Either's
// weights sum to 1, so no light is lost or gained, and a regular photon
// grid does not beat against the texels.
layout(location = 0) in uvec4 a_photon;  // u, v, irradiance (float bits), direction slopes (two halves)
uniform float u_size;                    // caustics map texels a side
uniform int u_wide;                      // 1: the B-spline over 3 x 3 texels; 0: the cubic over 2 x 2
out float v_irradiance;
out vec2 v_slopes;
out vec2 v_photon;  // in texels
void main() {
  v_irradiance = uintBitsToFloat(a_photon.z);
  v_slopes = unpackHalf2x16(a_photon.w);
  v_photon = uintBitsToFloat(a_photon.xy) * u_size;
  // The centre of the photon's texel, or the corner between the four
  // texel centres around it.
  vec2 centre = u_wide != 0 ? floor(v_photon) + 0.5 : floor(v_photon - 0.5) + 1.0;
  gl_Position = v_irradiance > 0.0 ? vec4(centre / u_size * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
  gl_PointSize = u_wide != 0 ? 3.0 : 2.0;
}
