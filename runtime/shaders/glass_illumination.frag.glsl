// Illumination textures (Iwasaki et al. §4.2, eq. 3; prefixed with #version,
// PRIM_STRIDE 6 and caustics_coverage.glsl): each texel gets the
// intersection triangle's intensity -- with glass_smooth, for a whole
// triangle its corners' intensities interpolated at the centroid of its
// part in the texel (glass_corner_intensity.comp) -- times the exact fraction of the texel it
// covers, times cos(gamma) per texel from the target's normal map and the
// transmitted direction interpolated across the triangle. The same program
// draws the focus windows' layers (u_texel_map; (0, 0, 1) for the main ones).
layout(binding = 0) uniform sampler2D u_target;  // xyz: world normal of the first surface, w: frame V (-1e30: none)
uniform int u_smooth;  // CausticsOptions::glass_smooth

out vec4 o_intensity;

void main() {
  load_primitive();
  // The target's texel under this one: the same in the main textures; in
  // a focus window's (u_texel_map) the main texel it lies in.
  ivec2 under = ivec2(floor(gl_FragCoord.xy / u_texel_map.z + u_texel_map.xy));
  if (any(lessThan(under, ivec2(0))) || any(greaterThanEqual(under, textureSize(u_target, 0)))) discard;
  vec4 target = texelFetch(u_target, under, 0);
  if (target.w < -1e29) discard;  // no target surface under this texel
  float covered = texel_coverage();
  if (covered <= 0.0) discard;
  // Barycentric weights of the centroid of the triangle's part in this
  // texel (texel_coverage sets it; the texel's centre where the texel lies
  // wholly inside): the corner intensities' linear interpolant has its
  // mean over the part there, so the texels of a triangle keep its flux
  // whatever their phase. At the texel's centre, clamped to the triangle,
  // a triangle smaller than a texel lent all its texels its nearest
  // corners' weights: on glass_ball's focus, where corner intensities
  // differ many times over one triangle, the light within 1 cm rose and
  // fell by 0.8 % as the focus crossed each 0.7 mm texel.
  vec2 x = g_centroid;
  float twice = cross2(v_q1 - v_q0, v_q2 - v_q0);
  vec3 bary = abs(twice) > 1e-12 ? vec3(cross2(v_q1 - x, v_q2 - x), cross2(v_q2 - x, v_q0 - x), cross2(v_q0 - x, v_q1 - x)) / twice
                                 : vec3(1.0 / 3.0);
  bary = max(bary, 0.0);
  bary /= max(bary.x + bary.y + bary.z, 1e-12);
  vec3 d = normalize(bary.x * prims[6 * v_prim + 3].xyz + bary.y * prims[6 * v_prim + 4].xyz + bary.z * prims[6 * v_prim + 5].xyz);
  float cos_gamma = max(dot(normalize(target.xyz), -d), 0.0);
  vec3 intensity = prims[6 * v_prim + 2].rgb;
  if (u_smooth != 0 && prims[6 * v_prim + 1].z > 0.0) {
    // Corner ratios to the triangle's own intensity, scaled to keep its
    // flux (the mean of a linear function over a triangle is its corners').
    vec3 c = vec3(prims[6 * v_prim + 3].w, prims[6 * v_prim + 4].w, prims[6 * v_prim + 5].w);
    intensity *= dot(bary, c) * 3.0 / max(c.x + c.y + c.z, 1e-12);
  }
  o_intensity = vec4(intensity * covered * cos_gamma, 1.0);
}
