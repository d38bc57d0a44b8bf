// The acceptance windows of the level-map planes (Tipprasert 2006 §4.4,
// eq. 4-15), shared by caustics_cull.comp, caustics_windows.frag and
// caustics_levelmap.frag (prefixed to each, after #version). Windows are half-open, D - eps < v <= D + eps, so
// adjacent ones tile; where rounding puts a depth in two, it belongs to
// the first (the higher plane), so that every receiver point is lit
// through exactly one plane.

// Planned on the CPU or by caustics_plan.comp: the count, the lowest and
// highest window bounds along V, the widest window, then (offset, eps)
// sorted by offset, highest first. PLANE_COUNT, DEPTH_LO, DEPTH_HI and
// PLANE(k) read them. In a batch (BATCH: every level map of a light and a
// size in one set of calls) the buffer holds every map's planes, each at
// its own offset, and g_planes is the offset of the map at hand, in words
// (caustics_batch.glsl's CausticsMap::ints.y).
#ifdef BATCH
layout(std430, binding = 7) readonly buffer Planes { float plane_words[]; };
uint g_planes = 0u;
#define PLANE_COUNT floatBitsToUint(plane_words[g_planes])
#define DEPTH_LO plane_words[g_planes + 1u]
#define DEPTH_HI plane_words[g_planes + 2u]
#define PLANE(k) vec2(plane_words[g_planes + 4u + 2u * uint(k)], plane_words[g_planes + 5u + 2u * uint(k)])
#else
layout(std430, binding = 7) readonly buffer Planes {
  uint plane_count;
  float depth_lo;
  float depth_hi;
  float widest;
  vec2 planes[];
};
#define PLANE_COUNT plane_count
#define DEPTH_LO depth_lo
#define DEPTH_HI depth_hi
#define PLANE(k) planes[k]
#endif

bool in_window(float v, uint k) {
  vec2 p = PLANE(k);
  float d = v - p.x;
  return d <= p.y && d > -p.y;
}

// The plane whose window holds v, or 0xffffffff: the first window whose
// lower bound lies below v (the bounds fall with k, windows far wider than
// rounding), then it and its neighbours by the test above.
uint window_of(float v) {
  if (!(v > -1e29) || PLANE_COUNT == 0u) return 0xffffffffu;
  uint a = 0u, b = PLANE_COUNT;
  while (a < b) {
    uint m = (a + b) / 2u;
    vec2 p = PLANE(m);
    if (p.x - p.y < v) b = m;
    else a = m + 1u;
  }
  uint last = min(a + 1u, PLANE_COUNT - 1u);
  for (uint k = a > 0u ? a - 1u : 0u; k <= last; ++k) {
    if (in_window(v, k)) return k;
  }
  return 0xffffffffu;
}
