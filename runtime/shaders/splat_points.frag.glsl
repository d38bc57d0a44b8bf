#version 450 core
// Additive blending sums the photons that land in a texel (Mihalik 2008 ch. 8),
// each weighted by the filter of splat_points.vert. Both filters' weights
// at texel centres one apart sum to 1 wherever the photon lies (no light
// lost or gained) and change with a continuous slope as the photon moves.
in float v_irradiance;
in vec2 v_slopes;
in vec2 v_photon;
out vec4 o_color;
uniform int u_wide;  // as splat_points.vert's
// The quadratic B-spline at distance d (texels), over three texels.
float bspline2(float d) {
  d = abs(d);
  return d < 0.5 ? 0.75 - d * d : d < 1.5 ? 0.5 * (1.5 - d) * (1.5 - d) : 0.0;
}
void main() {
  vec2 d = gl_FragCoord.xy - v_photon;
  // Over two texels: the cubic 1 - 3 d^2 + 2 |d|^3.
  vec2 w = u_wide != 0 ? vec2(bspline2(d.x), bspline2(d.y)) : 1.0 - smoothstep(0.0, 1.0, abs(d));
  o_color = vec4(1.0, v_slopes, 0.0) * (v_irradiance * w.x * w.y);  // as caustics_levelmap.frag
}
