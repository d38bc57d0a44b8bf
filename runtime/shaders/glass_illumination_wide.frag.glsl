// Glass focus windows (prefixed with #version, PRIM_STRIDE 6,
// TEXEL_MAP and caustics_coverage.glsl): a wide primitive's light in this
// texel (glass_window_split.glsl), as glass_illumination.frag computes it
// but for how the covered fraction is found. Most of a wide triangle's
// texels lie inside all three edges (1), or are crossed by one edge alone:
// then the fraction is the unit square's part on the inner side of that
// line, in closed form from the centre's distance d to it (a linear ramp
// while the line crosses two opposite sides, a quadratic corner piece
// where it cuts off a corner). Where two edges cross the texel (the
// triangle's corners) it is clipped exactly (caustics_coverage.glsl). The
// intensity and direction come interpolated to the texel's centre by the
// rasteriser, extrapolated linearly where the centre lies past an edge
// (glass_illumination.frag clamps it to the triangle there): on
// glass_ball's focus the two programs' images differ by 0.05 % (relative
// L1, 0.5 mm pixels). No clamping of the result: a wavelength bin's
// sRGB weights can be negative.
layout(binding = 0) uniform sampler2D u_target;  // xyz: world normal of the first surface, w: frame V (-1e30: none)

in vec3 v_intensity;
in vec3 v_direction;
flat in vec3 v_edge[3];
flat in vec4 v_corners01;
flat in vec2 v_corner2;
out vec4 o_intensity;

// The part of the texel (a unit square about its centre) at least d inside
// a line of unit normal n, 0..1.
float square_inside(float d, vec2 n) {
  float hi = max(abs(n.x), abs(n.y)), lo = min(abs(n.x), abs(n.y));
  float outer = 0.5 * (hi + lo), inner = 0.5 * (hi - lo);  // where the line leaves the square; where it stops crossing two sides
  if (abs(d) <= inner) return 0.5 + d / hi;
  float t = max(outer - abs(d), 0.0);
  float corner = t * t / (2.0 * hi * lo);  // a triangle cut off a corner (lo > 0 here: inner < outer)
  return d > 0.0 ? 1.0 - corner : corner;
}

void main() {
  vec3 x = vec3(gl_FragCoord.xy, 1.0);
  float covered = 1.0;
  int partial = 0;
  for (int e = 0; e < 3; ++e) {
    float d = dot(v_edge[e], x), reach = 0.5 * (abs(v_edge[e].x) + abs(v_edge[e].y));
    if (d <= -reach) discard;  // wholly outside this edge
    if (d < reach) {
      covered = square_inside(d, v_edge[e].xy);
      ++partial;
    }
  }
  if (partial > 1) {
    v_q0 = v_corners01.xy;
    v_q1 = v_corners01.zw;
    v_q2 = v_corner2;
    covered = texel_coverage();
    if (covered <= 0.0) discard;
  }
  ivec2 under = ivec2(floor(gl_FragCoord.xy / u_texel_map.z + u_texel_map.xy));
  if (any(lessThan(under, ivec2(0))) || any(greaterThanEqual(under, textureSize(u_target, 0)))) discard;
  vec4 target = texelFetch(u_target, under, 0);
  if (target.w < -1e29) discard;  // no target surface under this texel
  float cos_gamma = max(dot(normalize(target.xyz), -normalize(v_direction)), 0.0);
  o_intensity = vec4(v_intensity * covered * cos_gamma, 1.0);
}
