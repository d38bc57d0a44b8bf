// Acceptance test of the level map (Tipprasert 2006 eq. 4-15, §4.5;
// prefixed with #version, caustics_coverage.glsl and position_code.glsl):
// keep a fragment of plane D only where the receiver's first surface (the
// position map) lies within the plane's window, which the depth test does. Windows are half-open,
// D - eps < v <= D + eps, like the depth levels (a level holds its top
// boundary), so adjacent windows tile without gap or overlap and each
// receiver point is lit through exactly one plane, even a surface lying
// exactly on a boundary. The texel gets the
// triangle's irradiance times the fraction of the texel it covers;
// additive blending sums the beams, as the vector (1, s_u, s_w) I_c of
// caustics_geometry.comp (the map's R is eq. 4-18's irradiance on the plane,
// G and B what casting needs for the local light direction).
//
// Beyond the thesis: a caustics texel larger than a position-map texel
// covers surface at several depths. Testing only its centre dropped the
// light of every other plane's surface there (flat_pool lost 91 % of its
// light at 2^2 texels, docs/robustness.md); the windows pass
// (caustics_windows.frag) gives each texel the mean depth of its surface
// samples (up to 4 x 4 position texels) and the one plane whose window
// holds it, and the cull lists every beam over the texel for that plane,
// so the texel's flux is kept.
//
// Also beyond the thesis: the beam is followed from the plane to the
// surface's own depth. The thesis deposits the beam's cross-section on
// plane D for every surface point within D +- eps, so converging beams land
// where they were at D, not where they meet the surface: fold lines on a
// curved receiver moved by up to eps tan(theta) (a sphere under waves: 23 %
// error at fold pixels with 8 planes, 8.5 % with 32, docs/caustics.md). Here
// each vertex of the triangle moves by (v - D) s_k, its own ray's direction
// (caustics_geometry.comp), v the texel's surface depth from the windows
// pass: the triangle becomes the beam's cross-section at v, and its irradiance the flux over that area
// (the beam's spread over v - D kept).
// Neighbouring beams share their vertices' rays, so their cross-sections
// tile at every depth. (Moving each triangle rigidly by its mean direction,
// as this shader once did, opened gaps and overlaps one texel wide along the
// water triangles' edges wherever neighbours' directions differed: a dark
// mesh in the caustics under waves at 4 planes and a coarse water grid.)
// The plane stays what buckets the beams and culls them.
// The depth test before shading keeps only the fragments of the plane
// whose window holds the texel's surface (caustics_windows.frag), and the
// texel's depth comes from the same pass: nothing is tested here.
layout(early_fragment_tests) in;
#ifdef BATCH
// The primitive's map (caustics_batch.glsl; caustics_geometry.comp packs
// it with the window) says where its surface is.
layout(binding = 1) uniform sampler2DArray u_window_surface;
vec2 u_texels_per_metre;
#define WINDOW_SURFACE_CODE(layer) texelFetch(u_window_surface, ivec3(gl_FragCoord.xy, layer), 0).r
#else
uniform float u_half_v;           // the frame's half-extent along V
uniform vec2 u_texels_per_metre;  // caustics map, along U and W
layout(binding = 1) uniform sampler2D u_window_surface;
#define WINDOW_SURFACE_CODE(layer) texelFetch(u_window_surface, ivec2(gl_FragCoord.xy), 0).r
#endif

out vec4 o_irradiance;

void main() {
  load_primitive();
#ifdef BATCH
  CausticsMap cm = batch_maps[batch_prim_map(prims[PRIM_STRIDE * v_prim + 1].w)];
  u_texels_per_metre = cm.texel.zw;
  float half_v = cm.half_size.y;
  int layer = int(cm.ints.x);
#else
  float half_v = u_half_v;
  int layer = 0;
#endif
  // The depth test kept this fragment: the texel's surface, at v, lies in
  // this plane's window.
  float dv = position_v(WINDOW_SURFACE_CODE(layer), half_v) - v_plane.x;
  float area_plane = abs(cross2(v_q1 - v_q0, v_q2 - v_q0));
  v_q0 += dv * v_s0 * u_texels_per_metre;
  v_q1 += dv * v_s1 * u_texels_per_metre;
  v_q2 += dv * v_s2 * u_texels_per_metre;
  float area = abs(cross2(v_q1 - v_q0, v_q2 - v_q0));
  float covered = texel_coverage();
  if (covered <= 0.0 || area <= 0.0) discard;
  covered *= corner_factor();  // smooth caustics (caustics_coverage.glsl)
  // The triangle's flux, I_c times its area on the plane, over its area here.
  o_irradiance = vec4(1.0, v_slopes, 0.0) * (v_irradiance * (area_plane / area) * covered);
}
