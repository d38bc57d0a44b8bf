#version 450 core
// Smart reference planes on the GPU (Tipprasert 2006 §4.7.2, eq. 4-21 and 4-22)
// from the depth histogram profile.comp wrote after a light or receiver
// moved, so that re-profiling needs no read-back. It is
// formats/src/slicing.cpp's find_sub_boxes and smart_planes in double
// precision, to the bit (tests/frame_cost_test.cpp compares the two), and
// writes the planes with the header the cull pass reads. One invocation:
// the work is a few passes over the L levels. Where eps must be raised
// (more than kMaxPlanes planes) the count of planes at an eps is summed
// over the distinct sub-box heights, each times how many sub-boxes have it,
// rather than over the levels: Mesa's llvmpipe stops a shader's loops after
// 65535 iterations in all, and 200 bisection steps over thousands of
// levels would pass that (this way about 10 000 levels fit).
layout(local_size_x = 1) in;

layout(std430, binding = 9) readonly buffer Histogram { uint bins[]; };
// Scratch, 2 L + 2 words, cleared by the caller: [len] sub-boxes of len
// levels (1..L), then (len, count) pairs of the distinct lengths.
layout(std430, binding = 10) buffer Lengths { uint lengths[]; };
// Header: plane count, lowest and highest window bounds along V (the cull's
// depth range), the widest half-width; then (offset, eps) per plane,
// sorted by offset, highest first.
layout(std430, binding = 7) writeonly buffer Planes {
  uint plane_count;
  float depth_lo;
  float depth_hi;
  float widest;
  vec2 planes[];
};

uniform uint u_levels;     // L
uniform double u_height;   // h: the frame's extent along V
uniform double u_epsilon;  // eps asked
const uint kMaxPlanes = 4097u;  // formats/level_map.h

// Eq. 4-22, rounded up, at least one (2^40 for an absurdly small eps).
double planes_for(double h_i, double eps) {
  double n = ceil(h_i / (2.0 * eps) - 1e-9LF);
  if (!(n < 1e12LF)) return 1099511627776.0LF;
  return max(1.0LF, n);
}

uint distinct = 0u;  // pairs (length, count) at lengths[u_levels + 1 + 2 k]

// The planes eq. 4-22 gives every sub-box at eps, summed (an integer).
double total_planes(double h, double eps) {
  double t = 0.0LF;
  for (uint k = 0u; k < distinct; ++k) {
    uint len = lengths[u_levels + 1u + 2u * k], n = lengths[u_levels + 2u + 2u * k];
    t += double(n) * planes_for(h * double(len) / double(u_levels), eps);
  }
  return t;
}

void main() {
  // Sub-boxes are the runs of adjacent non-empty levels (find_sub_boxes).
  uint start = 0u;
  bool run = false;
  for (uint l = 0u; l <= u_levels; ++l) {
    bool filled = l < u_levels && bins[l] != 0u;
    if (filled && !run) {
      start = l;
      run = true;
    } else if (!filled && run) {
      lengths[l - start] += 1u;
      run = false;
    }
  }
  for (uint len = 1u; len <= u_levels; ++len) {
    if (lengths[len] == 0u) continue;
    lengths[u_levels + 1u + 2u * distinct] = len;
    lengths[u_levels + 2u + 2u * distinct] = lengths[len];
    ++distinct;
  }
  double h = u_height, eps = u_epsilon;
  if (total_planes(h, eps) > double(kMaxPlanes)) {
    double lo = eps, hi = max(h, eps);
    for (int it = 0; it < 200; ++it) {
      double mid = 0.5LF * (lo + hi);
      if (mid == lo || mid == hi) break;  // converged: the steps left change nothing
      if (total_planes(h, mid) > double(kMaxPlanes)) lo = mid; else hi = mid;
    }
    eps = hi;
  }
  uint count = 0u;
  float lo_v = 1e30, hi_v = -1e30, wide = 0.0;
  uint first = 0u;
  bool open = false;
  for (uint l = 0u; l <= u_levels; ++l) {
    bool filled = l < u_levels && bins[l] != 0u;
    if (filled && !open) {
      first = l;
      open = true;
    } else if (!filled && open) {
      open = false;
      double h_i = h * double(l - first) / double(u_levels);  // eq. 4-21
      double n_i = planes_for(h_i, eps);                      // eq. 4-22
      double top = h / 2.0LF - h * double(first) / double(u_levels);
      double slab = h_i / n_i;
      for (double k = 0.0LF; k < n_i && count < kMaxPlanes; k += 1.0LF) {
        vec2 p = vec2(float(top - slab * (k + 0.5LF)), float(slab / 2.0LF));
        planes[count++] = p;
        lo_v = min(lo_v, p.x - p.y);
        hi_v = max(hi_v, p.x + p.y);
        wide = max(wide, p.y);
      }
    }
  }
  plane_count = count;
  depth_lo = lo_v;
  depth_hi = hi_v;
  widest = wide;
}
