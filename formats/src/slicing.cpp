#include "caustix/formats/slicing.h"

#include <algorithm>
#include <cmath>

namespace caustix {
namespace {

// Eq. 4-22, rounded up, at least one.
std::uint64_t planes_for(double h_i, double eps) {
  const double n = std::ceil(h_i / (2.0 * eps) - 1e-9);
  if (!(n < 1e12)) return std::uint64_t{1} << 40;  // absurdly small eps: the caller caps
  return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(n));
}

std::uint64_t total_planes(double h, std::uint32_t levels, const std::vector<SubBox>& boxes, double eps) {
  std::uint64_t t = 0;
  for (const SubBox& b : boxes) t += planes_for(h * (b.last_level - b.first_level + 1) / levels, eps);
  return t;
}

}  // namespace

std::vector<SubBox> find_sub_boxes(const std::vector<std::uint32_t>& histogram) {
  std::vector<SubBox> boxes;
  for (std::uint32_t l = 0; l < histogram.size(); ++l) {
    if (histogram[l] == 0) continue;
    if (!boxes.empty() && boxes.back().last_level + 1 == l) {
      boxes.back().last_level = l;
    } else {
      boxes.push_back(SubBox{l, l});
    }
  }
  return boxes;
}

std::vector<ReferencePlane> uniform_planes(double h, std::uint32_t n) {
  std::vector<ReferencePlane> planes;
  const double s = h / n;  // eq. 4-8
  for (std::uint32_t i = 1; i <= n + 1; ++i) {
    planes.push_back(ReferencePlane{static_cast<float>(h / 2 - s * (i - 1)), static_cast<float>(s / 2)});  // eq. 4-7, 4-9, 4-15
  }
  return planes;
}

std::vector<ReferencePlane> smart_planes(double h, std::uint32_t levels, const std::vector<SubBox>& boxes, double eps,
                                         double* used_epsilon) {
  if (total_planes(h, levels, boxes, eps) > kMaxPlanes) {
    double lo = eps, hi = std::max(h, eps);
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (total_planes(h, levels, boxes, mid) > kMaxPlanes ? lo : hi) = mid;
    }
    eps = hi;
  }
  if (used_epsilon) *used_epsilon = eps;
  std::vector<ReferencePlane> planes;
  for (const SubBox& b : boxes) {
    const double h_i = h * (b.last_level - b.first_level + 1) / levels;  // eq. 4-21
    const std::uint64_t n_i = planes_for(h_i, eps);                        // eq. 4-22
    const double top = h / 2 - h * b.first_level / levels;
    const double slab = h_i / static_cast<double>(n_i);
    for (std::uint64_t k = 0; k < n_i; ++k) {
      planes.push_back(ReferencePlane{static_cast<float>(top - slab * (static_cast<double>(k) + 0.5)), static_cast<float>(slab / 2)});
    }
  }
  return planes;
}

}  // namespace caustix
