// Acceptance test of the level map (seed 000 eq. 4-15, §4.5; prefixed with
// #version and caustics_coverage.glsl): keep a fragment of plane D only
// where the receiver's first surface (the position map) lies within the
// plane's window. Windows are half-open, D - eps < v <= D + eps, like the
// depth levels (a level holds its top boundary), so adjacent windows tile
// without gap or overlap and each receiver point is lit through exactly one
// plane, even a surface lying exactly on a boundary. The texel gets the
// triangle's irradiance times the fraction of the texel it covers;
// additive blending sums the beams.
layout(binding = 0) uniform sampler2D u_position_map;  // frame V of the first surface; -1e30 where none
uniform vec2 u_map_scale;                               // position-map texels per caustics-map texel

out float o_irradiance;

void main() {
  load_primitive();
  float v = texelFetch(u_position_map, ivec2(gl_FragCoord.xy * u_map_scale), 0).r;
  float d = v - v_plane.x;
  if (!(d <= v_plane.y && d > -v_plane.y)) discard;
  float covered = texel_coverage();
  if (covered <= 0.0) discard;
  o_irradiance = v_irradiance * covered;
}
