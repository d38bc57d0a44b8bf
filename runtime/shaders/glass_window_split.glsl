// Glass focus windows (prefixed to caustics_intersect.vert for
// the glass). A window's texels are finer than the main layers' by a
// dozen or more a side, so a primitive's fragments there are that squared.
// Where light concentrates primitives are small; the wide ones cross the
// window with weaker light, and on glass_teapot with the light moving
// they were most of its fragments, each clipping the texel against the
// triangle (caustics_coverage.glsl). So a window's layers are drawn by two
// programs: the wide primitives -- at least u_wide_texels of the window's
// texels high across their longest edge -- by GLASS_WIDE
// (glass_illumination_wide.frag: the same light, the texels along one
// edge covered in closed form from its distance, the rest exactly),
// the others by glass_illumination.frag.
// 0: every primitive exactly (the main layers).
uniform float u_wide_texels;

// Both programs decide alike, so that each primitive is drawn once:
// `precise` keeps either compilation from contracting the arithmetic
// differently.
bool glass_window_wide(vec2 q0, vec2 q1, vec2 q2) {
  if (u_wide_texels <= 0.0) return false;
  precise vec2 e01 = q1 - q0, e12 = q2 - q1, e20 = q0 - q2;
  precise float longest = sqrt(max(max(dot(e01, e01), dot(e12, e12)), dot(e20, e20)));
  precise float twice = abs(e01.x * e20.y - e01.y * e20.x);
  return twice >= u_wide_texels * longest;  // its height over the longest edge, twice / longest
}

#ifdef GLASS_WIDE
uniform int u_smooth;  // CausticsOptions::glass_smooth
// What glass_illumination.frag interpolates across the triangle -- the
// intensity (times the corner ratios with glass_smooth) and the
// transmitted direction -- at this grown corner, extrapolated linearly,
// so that the rasteriser interpolates it; and the edges, flat.
out vec3 v_intensity;
out vec3 v_direction;
flat out vec3 v_edge[3];  // dot(v_edge[e], (x, 1)): texel centre x's distance inside edge e (xy: the unit inward normal)
flat out vec4 v_corners01;
flat out vec2 v_corner2;

// q: the triangle in the window's texels; p: this vertex (grown);
// b..f: the primitive's vec4s 1..5 (glass_geometry.comp).
void glass_wide_corner(vec2 q0, vec2 q1, vec2 q2, vec2 p, vec4 b, vec4 c, vec4 d0, vec4 d1, vec4 d2) {
  vec2 q[3] = vec2[3](q0, q1, q2);
  v_corners01 = vec4(q0, q1);
  v_corner2 = q2;
  float twice = (q1.x - q0.x) * (q2.y - q0.y) - (q1.y - q0.y) * (q2.x - q0.x);
  for (int e = 0; e < 3; ++e) {
    vec2 d = q[(e + 1) % 3] - q[e];
    vec2 n = sign(twice) * vec2(-d.y, d.x) / length(d);  // inward
    v_edge[e] = vec3(n, -dot(q[e], n));
  }
  // p's barycentric weights (outside the triangle some are negative).
  vec3 w = vec3((q1.x - p.x) * (q2.y - p.y) - (q1.y - p.y) * (q2.x - p.x), (q2.x - p.x) * (q0.y - p.y) - (q2.y - p.y) * (q0.x - p.x),
                (q0.x - p.x) * (q1.y - p.y) - (q0.y - p.y) * (q1.x - p.x)) / twice;
  vec3 ratio = vec3(1.0);
  if (u_smooth != 0 && b.z > 0.0) ratio = vec3(d0.w, d1.w, d2.w) * 3.0 / max(d0.w + d1.w + d2.w, 1e-12);
  v_intensity = c.rgb * dot(w, ratio);
  v_direction = w.x * d0.xyz + w.y * d1.xyz + w.z * d2.xyz;
}
#endif
