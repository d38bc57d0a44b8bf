// The window of every caustics texel, as depth, before the level-map draw
// (beyond the thesis: rejection before shading; prefixed with #version and
// caustics_windows.glsl). The level map keeps a fragment of plane k only
// where the receiver's surface lies in k's window (Tipprasert 2006 eq.
// 4-15); most fragments of a plane's triangles fall where the surface is
// another plane's, and were shaded only to be discarded. This pass looks
// at the texel's surface samples (up to 4 x 4 position texels where the
// caustics texel is coarser) once and writes the texel's depth v, the mean
// frame V of its samples, and the plane it is lit through, the one whose
// window holds v:
// - no plane (no surface, or none in a window): the cleared depth 0, which
//   no primitive has;
// - plane k: depth (k + 1) / 65535, the depth caustics_intersect.vert
//   gives plane k's primitives, so that the draw's depth test (GL_EQUAL,
//   before shading) keeps exactly plane k's fragments there, and v as a
//   position code in u_window_surface, the depth caustics_levelmap.frag
//   follows each beam to.
// Every texel is one plane's, so one draw of the list lights it. Where a
// coarse texel's samples lie in several windows (a step or a steep slope
// within the texel) the texel still gets every beam through it once:
// the cull lists a beam for each plane whose window meets the surface
// depths under its footprint widened by a caustics texel, and v lies
// within the texel's samples' depths. What it gives up is the beams' spread
// between the samples' own depths; the beams are followed to v, as
// everywhere within a window. (A second draw once lit such texels plane
// by plane from each plane's samples: on the 64-object pool it cost as
// much as the first, for 0.05 % of a ball's irradiance, docs/caustics.md.)
// Where v falls between two windows (planes are placed where the depth
// histogram has surface, so windows need not touch), the texel takes the
// window and depth of its sample nearest v.
// The pass also writes the caustics map's alpha, 1 where any sample has a
// surface (what caustics_presence.frag gives the level maps' texels, from
// the same samples), so that no presence pass follows.
// Nothing here depends on the water: a map drawn alone keeps the depth,
// the surface and the alpha until its planes, its position map or its side
// change, and the pass does not run between (caustics.cpp,
// MapGpu::windows_made); nor in a batch, while every map of it is drawn and
// keeps its windows. The fragments kept, in their order, and so the
// caustics map are the draw's alone. Exact: the depth buffer holds 16-bit
// integers, and (k + 1) / 65535 (k < 4097) is within a ten-thousandth of
// a step of one, whatever rounding the rasteriser's float arithmetic adds.
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
out vec4 o_irradiance;  // a batch clears the map's irradiance too; drawn alone, alpha only

void main() {
#ifdef BATCH
  CausticsMap cm = batch_maps[v_map];
  vec2 u_map_scale = vec2(cm.u.w);
  int u_samples = int(cm.ints.z);
  g_planes = cm.ints.y;
#endif
  float sum = 0.0, n = 0.0;
  for (int j = 0; j < u_samples; ++j) {
    for (int i = 0; i < u_samples; ++i) {
      float v = POSITION(texel_sample(gl_FragCoord.xy, i, j, u_samples, u_map_scale));
      if (v > -1e29) {
        sum += v;
        n += 1.0;
      }
    }
  }
  bool present = n > 0.0;
  float v = present ? sum / n : -1e30;
  uint k = window_of(v);
  if (present && k == 0xffffffffu) {
    // Between windows: the sample nearest the mean that a window holds.
    float nearest = 1e30, at = v;
    for (int j = 0; j < u_samples; ++j) {
      for (int i = 0; i < u_samples; ++i) {
        float s = POSITION(texel_sample(gl_FragCoord.xy, i, j, u_samples, u_map_scale));
        uint ks = window_of(s);
        if (ks != 0xffffffffu && abs(s - at) < nearest) {
          nearest = abs(s - at);
          v = s;
          k = ks;
        }
      }
    }
  }
  o_irradiance = vec4(0.0, 0.0, 0.0, present ? 1.0 : 0.0);
  if (k == 0xffffffffu) {
#ifndef BATCH
    if (!present) discard;
#endif
    gl_FragDepth = 0.0;  // no window: the depth a cleared map has
    return;
  }
  gl_FragDepth = float(k + 1u) / 65535.0;
#ifdef BATCH
  imageStore(u_window_surface, ivec3(gl_FragCoord.xy, cm.ints.x), vec4(position_code(v, cm.half_size.y)));
#else
  imageStore(u_window_surface, ivec2(gl_FragCoord.xy), vec4(position_code(v, u_half_v)));
#endif
}
