#version 450 core
// Additive blending sums the photons that land in a texel (Mihalik 2008 ch. 8),
// each weighted by the tent filter of splat_points.vert.
in float v_irradiance;
in vec2 v_slopes;
in vec2 v_photon;
out vec4 o_color;
void main() {
  vec2 w = max(1.0 - abs(gl_FragCoord.xy - v_photon), 0.0);
  o_color = vec4(1.0, v_slopes, 0.0) * (v_irradiance * w.x * w.y);  // as caustics_levelmap.frag
}
