#include "caustix/bake/depth_profile.h"

#include <cmath>

namespace caustix::bake {
namespace {

// Planes a sub-box of height h_i needs for half-width eps: eq. 4-22, rounded
// up, at least one.
std::uint64_t planes_for(double h_i, double eps) {
  const double n = std::ceil(h_i / (2.0 * eps) - 1e-9);
  if (!(n < 1e12)) return std::uint64_t{1} << 40;  // absurdly small eps: caller caps
  return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(n));
}

}  // namespace

void build_depth_profile(LevelMap& m, const SlicingOptions& o, std::string* warning) {
  const double h = 2.0 * m.frame.half[1];
  const std::uint32_t levels = o.levels;

  // Pixel-density histogram over L depth levels (fig. 4-19).
  m.histogram.assign(levels, 0);
  for (std::uint16_t q : m.depth) {
    if (q == kEmptyDepth) continue;
    const std::uint64_t level = std::min<std::uint64_t>(levels - 1, std::uint64_t{q} * levels / kDepthQuantum);
    ++m.histogram[level];
  }
  // Runs of adjacent valid levels.
  m.sub_boxes.clear();
  for (std::uint32_t l = 0; l < levels; ++l) {
    if (m.histogram[l] == 0) continue;
    if (!m.sub_boxes.empty() && m.sub_boxes.back().last_level + 1 == l) {
      m.sub_boxes.back().last_level = l;
    } else {
      m.sub_boxes.push_back(SubBox{l, l});
    }
  }

  // Uniform slicing, eq. 4-6..4-9 (and eq. 4-15 for the acceptance).
  const std::uint32_t n = o.planes;
  const double s = h / n;
  m.uniform_planes.clear();
  for (std::uint32_t i = 1; i <= n + 1; ++i) {
    m.uniform_planes.push_back(ReferencePlane{static_cast<float>(h / 2 - s * (i - 1)), static_cast<float>(s / 2)});
  }
  m.planes_requested = n;

  // Smart slicing, eq. 4-21 and 4-22.
  double eps = o.epsilon.value_or(h / (2.0 * n));
  std::uint64_t total = 0;
  for (const SubBox& b : m.sub_boxes) total += planes_for(h * (b.last_level - b.first_level + 1) / levels, eps);
  if (total > kMaxPlanes) {
    // Raise eps until the planes fit (halving steps keep this exact enough).
    double lo = eps, hi = h;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      std::uint64_t t = 0;
      for (const SubBox& b : m.sub_boxes) t += planes_for(h * (b.last_level - b.first_level + 1) / levels, mid);
      (t > kMaxPlanes ? lo : hi) = mid;
    }
    if (warning) {
      *warning = "epsilon " + std::to_string(eps) + " m would need " + std::to_string(total) +
                 " planes; capped at " + std::to_string(kMaxPlanes) + " (epsilon raised to " + std::to_string(hi) + " m)";
    }
    eps = hi;
  }
  m.epsilon = static_cast<float>(eps);
  m.smart_planes.clear();
  for (const SubBox& b : m.sub_boxes) {
    const double h_i = h * (b.last_level - b.first_level + 1) / levels;  // eq. 4-21
    const std::uint64_t n_i = planes_for(h_i, eps);                        // eq. 4-22
    const double top = h / 2 - h * b.first_level / levels;
    const double slab = h_i / static_cast<double>(n_i);
    for (std::uint64_t k = 0; k < n_i; ++k) {
      m.smart_planes.push_back(
          ReferencePlane{static_cast<float>(top - slab * (static_cast<double>(k) + 0.5)), static_cast<float>(slab / 2)});
    }
  }
  m.slicing = o.slicing;
}

}  // namespace caustix::bake
