// The window of every caustics texel, as depth, before the level-map draw
// (beyond the thesis: rejection before shading; prefixed with #version and
// caustics_windows.glsl). caustics_levelmap.frag keeps a fragment of plane
// k only where some of the texel's surface samples are k's; most fragments
// of a plane's triangles fall where the surface is another plane's, and
// were shaded only to be discarded. This pass looks at the same samples
// once per texel and writes whose they are:
// - no plane's (no surface): the cleared depth 0, which no primitive has;
// - plane k's alone: depth (k + 1) / 65535, the depth caustics_intersect.vert
//   gives plane k's primitives, so that the draw's depth test (GL_EQUAL,
//   before shading) keeps exactly plane k's fragments there;
// - several planes' (a caustics texel coarser than the position map's
//   texels, over a depth step): depth 1, which only a second draw, every
//   primitive at depth 1, meets; the fragment shader then tests the
//   samples as it always does. That second draw's indirect command has no
//   vertices unless some texel is written here at depth 1 (its count is
//   then the first draw's), so a map whose texels each lie in one window
//   pays nothing for it.
// The pass also writes the caustics map's alpha, 1 where any sample has a
// surface (what caustics_presence.frag gives the level maps' texels, from
// the same samples), so that no presence pass follows.
// A texel of one window also gets the mean frame V of its surface samples,
// as a position code, in u_window_surface: the first draw reads it once
// instead of testing every sample again; a texel of several gets which
// (caustics_windows.glsl's several_windows_code), so that the second draw
// tests samples only for the planes among them. A texel with a surface sample in
// no window (the draw then keeps the fraction in windows) counts as one of
// several windows.
// Nothing here depends on the water: a map drawn alone keeps the depth,
// the surface, the alpha and the several-windows flag until its planes,
// its position map or its side change, and the pass does not run between
// (caustics.cpp, MapGpu::windows_made); nor in a batch, while every map
// of it is drawn and keeps its windows (the batch's own flag per layer).
// The fragments kept, in their order, and so the caustics map are the
// draw's alone. Exact: the depth buffer holds 16-bit integers, and
// (k + 1) / 65535 (k < 4097) and 1 are within a ten-thousandth of a step
// of one, whatever rounding the rasteriser's float arithmetic adds.
#ifdef BATCH
// Every map of the batch, an instance each (caustics_batch.vert): the
// pass also clears the map's irradiance, so that maps of the array that
// this update keeps are not touched.
layout(binding = 0) uniform sampler2DArray u_position_map;
layout(binding = 0, r16) uniform writeonly image2DArray u_window_surface;  // a layer per map, as the caustics
flat in uint v_map;
#define POSITION(at) position_v(texelFetch(u_position_map, ivec3(at, int(batch_maps[v_map].ints.w)), 0).r, batch_maps[v_map].half_size.y)
#else
layout(binding = 0) uniform sampler2D u_position_map;  // frame V of the first surface (position_code.glsl)
uniform float u_half_v;                                 // the frame's half-extent along V
uniform vec2 u_map_scale;                               // position-map texels per caustics-map texel
uniform int u_samples;                                  // per axis, as caustics_levelmap.frag's
layout(binding = 0, r16) uniform writeonly image2D u_window_surface;
#define POSITION(at) position_v(texelFetch(u_position_map, at, 0).r, u_half_v)
#endif
layout(std430, binding = 6) buffer Command { uint cmd[]; };  // caustics_fixup.comp's layout
out vec4 o_irradiance;  // a batch clears the map's irradiance too; drawn alone, alpha only

void main() {
#ifdef BATCH
  CausticsMap cm = batch_maps[v_map];
  vec2 u_map_scale = vec2(cm.u.w);
  int u_samples = int(cm.ints.z);
  g_planes = cm.ints.y;
#endif
  // A window is an interval of depth: where the deepest and the highest
  // surface samples lie in one window, so do all between them, and two
  // window searches decide the texel. Else every sample is searched.
  float least = 1e30, most = -1e30, sum = 0.0, n = 0.0;
  for (int j = 0; j < u_samples; ++j) {
    for (int i = 0; i < u_samples; ++i) {
      float v = POSITION(texel_sample(gl_FragCoord.xy, i, j, u_samples, u_map_scale));
      if (v > -1e29) {
        least = min(least, v);
        most = max(most, v);
        sum += v;
        n += 1.0;
      }
    }
  }
  bool present = n > 0.0;
  uint lo = 0xffffffffu, hi = 0u;
  bool lost = false;  // a surface sample in no window
  uint k = present ? window_of(least) : 0xffffffffu;
  if (k != 0xffffffffu && window_of(most) == k) {
    lo = hi = k;
  } else if (present) {
    sum = n = 0.0;
    for (int j = 0; j < u_samples; ++j) {
      for (int i = 0; i < u_samples; ++i) {
        float v = POSITION(texel_sample(gl_FragCoord.xy, i, j, u_samples, u_map_scale));
        uint kv = window_of(v);
        if (kv != 0xffffffffu) {
          lo = min(lo, kv);
          hi = max(hi, kv);
          sum += v;
          n += 1.0;
        } else {
          lost = lost || v > -1e29;
        }
      }
    }
  }
  o_irradiance = vec4(0.0, 0.0, 0.0, present ? 1.0 : 0.0);
  if (lo > hi) {
#ifndef BATCH
    if (!present) discard;
#endif
    gl_FragDepth = 0.0;  // no window: the depth a cleared map has
    return;
  }
  bool one = lo == hi && !lost;
  gl_FragDepth = one ? float(lo + 1u) / 65535.0 : 1.0;
#ifdef BATCH
  float surface = one ? position_code(sum / n, batch_maps[v_map].half_size.y) : several_windows_code(lo, hi);
  imageStore(u_window_surface, ivec3(gl_FragCoord.xy, batch_maps[v_map].ints.x), vec4(surface));
  if (!one) {
    cmd[batch_draw2(v_map)] = cmd[batch_draw(v_map)];  // the same value from every such texel
    cmd[batch_several(batch_maps[v_map].ints.x)] = 1u;   // for later draws that keep this pass's result
  }
#else
  imageStore(u_window_surface, ivec2(gl_FragCoord.xy), vec4(one ? position_code(sum / n, u_half_v) : several_windows_code(lo, hi)));
  if (!one) {
    cmd[11] = cmd[0];  // the same value from every such texel
    cmd[15] = 1u;      // for later draws that keep this pass's result
  }
#endif
}
