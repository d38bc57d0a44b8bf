// Acceptance test of the level map (Tipprasert 2006 eq. 4-15, §4.5;
// prefixed with #version, caustics_coverage.glsl and caustics_windows.glsl):
// keep a fragment of plane D only where the receiver's first surface (the
// position map) lies within the plane's window. Windows are half-open,
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
// covers surface at several depths, possibly in several planes' windows.
// Testing only its centre dropped the pieces of every other plane (flat_pool
// lost 91 % of its light at 2^2 texels, docs/robustness.md), so the test
// samples up to 4 x 4 position texels inside the caustics texel and keeps
// the fraction of the surface there that lies in this window; over the
// planes the fractions sum to 1 and the texel's flux is kept.
//
// Also beyond the thesis: the beam is followed from the plane to the
// surface's own depth. The thesis deposits the beam's cross-section on
// plane D for every surface point within D +- eps, so converging beams land
// where they were at D, not where they meet the surface: fold lines on a
// curved receiver moved by up to eps tan(theta) (a sphere under waves: 23 %
// error at fold pixels with 8 planes, 8.5 % with 32, docs/caustics.md). Here
// each vertex of the triangle moves by (v - D) s_k, its own ray's direction
// (caustics_geometry.comp), v the mean depth of the surface samples in the
// window: the triangle becomes the beam's cross-section at v, and its
// irradiance the flux over that area (the beam's spread over v - D kept).
// Neighbouring beams share their vertices' rays, so their cross-sections
// tile at every depth. (Moving each triangle rigidly by its mean direction,
// as this shader once did, opened gaps and overlaps one texel wide along the
// water triangles' edges wherever neighbours' directions differed: a dark
// mesh in the caustics under waves at 4 planes and a coarse water grid.)
// The plane stays what buckets the beams and culls them.
// The depth test before shading keeps only the fragments whose texel's
// surface lies in this plane's window, or in several windows
// (caustics_windows.frag); the test below decides there as it would alone.
// In the first, the samples' mean depth comes from the windows pass.
layout(early_fragment_tests) in;
#ifdef BATCH
// The primitive's map (caustics_batch.glsl; caustics_geometry.comp packs
// it with the window) says where its surface is.
layout(binding = 0) uniform sampler2DArray u_position_map;
layout(binding = 1) uniform sampler2DArray u_window_surface;
vec2 u_map_scale, u_texels_per_metre;
int u_samples, g_position, g_layer;
float g_half_v;
#define POSITION(at) position_v(texelFetch(u_position_map, ivec3(at, g_position), 0).r, g_half_v)
#define WINDOW_SURFACE_CODE() texelFetch(u_window_surface, ivec3(gl_FragCoord.xy, g_layer), 0).r
#define HALF_V g_half_v
#else
layout(binding = 0) uniform sampler2D u_position_map;  // frame V of the first surface (position_code.glsl)
uniform float u_half_v;                                 // the frame's half-extent along V
uniform vec2 u_map_scale;                               // position-map texels per caustics-map texel
uniform int u_samples;                                  // per axis: 1, or up to 4 when u_map_scale > 1
uniform vec2 u_texels_per_metre;                        // caustics map, along U and W
layout(binding = 1) uniform sampler2D u_window_surface;
#define POSITION(at) position_v(texelFetch(u_position_map, at, 0).r, u_half_v)
#define WINDOW_SURFACE_CODE() texelFetch(u_window_surface, ivec2(gl_FragCoord.xy), 0).r
#define HALF_V u_half_v
#endif
// 0: the draw of the texels whose surface samples lie in one window, each
// texel's mean frame V of them from the windows pass (u_window_surface);
// 1: the draw of those in several, which tests every sample here where
// this plane is among the texel's (u_window_surface says which).
uniform int u_several_windows;

out vec4 o_irradiance;

void main() {
  load_primitive();
  // This plane's index (caustics_geometry.comp: w is the index + 1).
  float window = prims[PRIM_STRIDE * v_prim + 1].w;
#ifdef BATCH
  CausticsMap cm = batch_maps[batch_prim_map(window)];
  u_map_scale = vec2(cm.u.w);
  u_texels_per_metre = cm.texel.zw;
  window = batch_prim_window(window);
  u_samples = int(cm.ints.z);
  g_position = int(cm.ints.w);
  g_planes = cm.ints.y;
  g_layer = int(cm.ints.x);
  g_half_v = cm.half_size.y;
#endif
  uint k = uint(window) - 1u;
  float inside = 0.0, surface = 0.0, depth = 0.0;
  if (u_several_windows == 0) {
    // The depth test kept this fragment: every surface sample of the texel
    // lies in this plane's window (caustics_windows.frag).
    inside = surface = 1.0;
    depth = position_v(WINDOW_SURFACE_CODE(), HALF_V) - v_plane.x;
  } else if (several_windows_holds(WINDOW_SURFACE_CODE(), k)) {
    for (int j = 0; j < u_samples; ++j) {
      for (int i = 0; i < u_samples; ++i) {
        float v = POSITION(texel_sample(gl_FragCoord.xy, i, j, u_samples, u_map_scale));
        if (v > -1e29) surface += 1.0;
        if (sample_window(v, k)) {
          inside += 1.0;
          depth += v - v_plane.x;
        }
      }
    }
  }
  if (inside == 0.0) discard;
  float dv = depth / inside;
  float area_plane = abs(cross2(v_q1 - v_q0, v_q2 - v_q0));
  v_q0 += dv * v_s0 * u_texels_per_metre;
  v_q1 += dv * v_s1 * u_texels_per_metre;
  v_q2 += dv * v_s2 * u_texels_per_metre;
  float area = abs(cross2(v_q1 - v_q0, v_q2 - v_q0));
  float covered = texel_coverage();
  if (covered <= 0.0 || area <= 0.0) discard;
  covered *= corner_factor();  // smooth caustics (caustics_coverage.glsl)
  // The triangle's flux, I_c times its area on the plane, over its area here.
  o_irradiance = vec4(1.0, v_slopes, 0.0) * (v_irradiance * (area_plane / area) * covered * (inside / surface));
}
