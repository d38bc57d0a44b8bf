// The acceptance windows of the level-map planes (Tipprasert 2006 §4.4,
// eq. 4-15), shared by caustics_cull.comp, caustics_windows.frag and
// caustics_levelmap.frag (prefixed to each, after #version). Windows are half-open, D - eps < v <= D + eps, so
// adjacent ones tile; where rounding puts a depth in two, it belongs to
// the first (the higher plane), so that every receiver point is lit
// through exactly one plane.

// Planned on the CPU or by caustics_plan.comp: the count, the lowest and
// highest window bounds along V, the widest window, then (offset, eps)
// sorted by offset, highest first.
layout(std430, binding = 7) readonly buffer Planes {
  uint plane_count;
  float depth_lo;
  float depth_hi;
  float widest;
  vec2 planes[];
};

bool in_window(float v, uint k) {
  float d = v - planes[k].x;
  return d <= planes[k].y && d > -planes[k].y;
}

// Whether the surface depth v is plane k's.
bool sample_window(float v, uint k) { return in_window(v, k) && (k == 0u || !in_window(v, k - 1u)); }

// The plane whose window holds v, or 0xffffffff: the first window whose
// lower bound lies below v (the bounds fall with k, windows far wider than
// rounding), then it and its neighbours by the test above.
uint window_of(float v) {
  if (!(v > -1e29) || plane_count == 0u) return 0xffffffffu;
  uint a = 0u, b = plane_count;
  while (a < b) {
    uint m = (a + b) / 2u;
    if (planes[m].x - planes[m].y < v) b = m;
    else a = m + 1u;
  }
  uint last = min(a + 1u, plane_count - 1u);
  for (uint k = a > 0u ? a - 1u : 0u; k <= last; ++k) {
    if (in_window(v, k)) return k;
  }
  return 0xffffffffu;
}
