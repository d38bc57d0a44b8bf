// A level map's position map as the baker stores it (formats/SPEC.md,
// LMAP's depth map): per texel the 16-bit code of the first surface's frame
// V, round(t 65534) with t = (half_v - v) / (2 half_v), and 65535 where
// there is no surface; an R16 texture reads it as s = code / 65535.
// Half the bytes of frame V as a float, and nothing lost against the bake:
// a map re-derived on the GPU is written in the same code (slab.frag,
// position_code), a step of 2 half_v / 65534 along V (0.15 mm for a 10 m
// tall frame).
const float kNoSurface = -1.0e30;
bool position_empty(float s) { return s >= 1.0; }
float position_v(float s, float half_v) {
  return position_empty(s) ? kNoSurface : half_v - s * (2.0 * half_v * (65535.0 / 65534.0));
}
// What an R16 target stores for frame V: round(t 65534), t clamped as the
// baker clamps it (a flat receiver's frame is micrometres tall, and a
// point's V rounded past its side must not come out as 65535, no surface).
float position_code(float v, float half_v) { return clamp((half_v - v) / (2.0 * half_v), 0.0, 1.0) * (65534.0 / 65535.0); }
// The position-map texel of surface sample (i, j), of samples x samples
// spread evenly over the caustics texel at frag (its gl_FragCoord), scale
// position-map texels to a caustics texel: the samples the level maps'
// windows, draw and presence take of a texel coarser than the position
// map's.
ivec2 texel_sample(vec2 frag, int i, int j, int samples, vec2 scale) {
  return ivec2((floor(frag) + (vec2(i, j) + 0.5) / float(samples)) * scale);
}
