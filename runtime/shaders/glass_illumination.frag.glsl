// Illumination textures (Iwasaki et al. §4.2, eq. 3; prefixed with #version,
// PRIM_STRIDE 6 and caustics_coverage.glsl): each texel gets the
// intersection triangle's intensity -- with glass_smooth, for a whole
// triangle its corners' intensities interpolated at the centroid of its
// part in the texel (glass_corner_intensity.comp) -- times the exact fraction of the texel it
// covers, times cos(gamma) per texel from the target's normal map and the
// transmitted direction interpolated across the triangle. The same program
// draws the focus windows' layers (u_texel_map; (0, 0, 1) for the main ones).
//
// The tent (CausticsOptions::glass_focus_tent, focus windows only): the
// texel takes the light of the triangle within a texel of its centre,
// weighted by (1 - |dx|)(1 - |dy|), the linear B-spline, instead of the
// light inside it. The four unit squares between this texel's centre and
// its neighbours' each hold one part of the triangle (clipped exactly);
// a part's light goes to the four texels at its square's corners by the
// tent at its centroid, weights that sum to 1 there, so the triangle's
// flux is kept. A point of light then moves its share between texels
// linearly as it moves, where the box moved all of it at once at a
// texel's edge: a focus narrower than a texel that drifts across the
// window changes the texels smoothly (docs/temporal.md).
layout(binding = 0) uniform sampler2D u_target;  // xyz: world normal of the first surface, w: frame V (-1e30: none)
uniform int u_smooth;  // CausticsOptions::glass_smooth
uniform int u_tent;    // the tent (caustics_intersect.vert dilates the primitive by a texel more)

out vec4 o_intensity;

void main() {
  load_primitive();
  // The target's texel under this one: the same in the main textures; in
  // a focus window's (u_texel_map) the main texel it lies in.
  ivec2 under = ivec2(floor(gl_FragCoord.xy / u_texel_map.z + u_texel_map.xy));
  if (any(lessThan(under, ivec2(0))) || any(greaterThanEqual(under, textureSize(u_target, 0)))) discard;
  vec4 target = texelFetch(u_target, under, 0);
  if (target.w < -1e29) discard;  // no target surface under this texel
  vec3 normal = normalize(target.xyz);
  vec2 centre = floor(gl_FragCoord.xy) + 0.5;
  float twice = cross2(v_q1 - v_q0, v_q2 - v_q0);
  vec3 light = vec3(0.0);
  bool kept = false;
  for (int k = 0; k < (u_tent != 0 ? 4 : 1); ++k) {
    // The box: the texel itself; the tent: the squares [centre - 1, centre]
    // to [centre, centre + 1] along each axis, one at a time.
    vec2 shift = u_tent != 0 ? vec2((k & 1) != 0 ? -0.5 : 0.5, (k & 2) != 0 ? -0.5 : 0.5) : vec2(0.0);
    float covered = texel_coverage_shifted(shift);
    if (covered <= 0.0) continue;
    kept = true;
    // Barycentric weights of the centroid of the triangle's part
    // (texel_coverage_shifted sets it; the square's centre where it lies
    // wholly inside): the corner intensities' linear interpolant has its
    // mean over the part there, so the parts of a triangle keep its flux
    // whatever their phase. At the texel's centre, clamped to the
    // triangle, a triangle smaller than a texel lent all its texels its
    // nearest corners' weights: on glass_ball's focus, where corner
    // intensities differ many times over one triangle, the light within
    // 1 cm rose and fell by 0.8 % as the focus crossed each 0.7 mm texel.
    vec2 x = g_centroid;
    vec2 from_centre = abs(x - centre);
    float weight = u_tent != 0 ? max(1.0 - from_centre.x, 0.0) * max(1.0 - from_centre.y, 0.0) : 1.0;
    vec3 bary = abs(twice) > 1e-12 ? vec3(cross2(v_q1 - x, v_q2 - x), cross2(v_q2 - x, v_q0 - x), cross2(v_q0 - x, v_q1 - x)) / twice
                                   : vec3(1.0 / 3.0);
    bary = max(bary, 0.0);
    bary /= max(bary.x + bary.y + bary.z, 1e-12);
    vec3 d = normalize(bary.x * prims[6 * v_prim + 3].xyz + bary.y * prims[6 * v_prim + 4].xyz + bary.z * prims[6 * v_prim + 5].xyz);
    float cos_gamma = max(dot(normal, -d), 0.0);
    vec3 intensity = prims[6 * v_prim + 2].rgb;
    if (u_smooth != 0 && prims[6 * v_prim + 1].z > 0.0) {
      // Corner ratios to the triangle's own intensity, scaled to keep its
      // flux (the mean of a linear function over a triangle is its corners').
      vec3 c = vec3(prims[6 * v_prim + 3].w, prims[6 * v_prim + 4].w, prims[6 * v_prim + 5].w);
      intensity *= dot(bary, c) * 3.0 / max(c.x + c.y + c.z, 1e-12);
    }
    light += intensity * covered * weight * cos_gamma;
  }
  if (!kept) discard;
  o_intensity = vec4(light, 1.0);
}
