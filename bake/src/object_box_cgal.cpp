// CGAL's optimal bounding box lives only in this translation unit (about
// 20 s and 1.4 GB to compile).
//
// Kernel: Exact_predicates_inexact_constructions_kernel. The box is
// optimised over the points' 3-D convex hull, a combinatorial structure
// built from orientation tests; with Simple_cartesian<double> those tests
// contradict each other on ordinary meshes (points on a cylinder's rulings,
// a scan's nearly coplanar patches), the hull's data structure is corrupted
// and the process aborts in free() (a turbine-blade scan and a
// cylinder). Exact predicates make the hull correct on any input; the
// optimiser's own arithmetic (rotations, extents) stays in doubles.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/optimal_bounding_box.h>

#include <algorithm>
#include <cmath>

#include "caustix/bake/object_box.h"

namespace caustix::bake {

ObjectBox oriented_box(const std::vector<Vec3d>& pts) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  ObjectBox box;
  std::array<Vec3d, 8> corners{};
  if (pts.size() >= 4) {
    std::vector<K::Point_3> points;
    points.reserve(pts.size());
    for (const auto& p : pts) points.emplace_back(p[0], p[1], p[2]);
    std::array<K::Point_3, 8> obb;
    CGAL::oriented_bounding_box(points, obb, CGAL::parameters::random_seed(20061).use_convex_hull(true));
    for (std::size_t i = 0; i < 8; ++i) corners[i] = {obb[i].x(), obb[i].y(), obb[i].z()};
  } else {
    Vec3d lo = pts.at(0), hi = pts.at(0);
    for (const auto& p : pts) {
      for (std::size_t k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    }
    // CGAL's corner order (make_hexahedron): 0 (x-,y-,z-), 1 x+, 3 y+, 5 z+.
    corners[0] = lo;
    corners[1] = {hi[0], lo[1], lo[2]};
    corners[3] = {lo[0], hi[1], lo[2]};
    corners[5] = {lo[0], lo[1], hi[2]};
  }
  // Edges from corner 0 along the box's three axes: 0->1, 0->3, 0->5. A
  // planar point set gives one edge of (nearly) zero length whose direction
  // is noise, so the axes come from the two longest edges by Gram-Schmidt
  // and the third is their cross product: orthonormal whatever the input.
  const std::size_t ends[3] = {1, 3, 5};
  std::array<Vec3d, 3> e{};
  std::array<double, 3> len{};
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t k = 0; k < 3; ++k) e[a][k] = corners[ends[a]][k] - corners[0][k];
    len[a] = std::sqrt(e[a][0] * e[a][0] + e[a][1] * e[a][1] + e[a][2] * e[a][2]);
  }
  std::array<std::size_t, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return len[x] > len[y]; });
  auto dot = [](const Vec3d& x, const Vec3d& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
  auto unit = [&](Vec3d v) {
    const double n = std::sqrt(dot(v, v));
    for (double& c : v) c /= n;
    return v;
  };
  std::array<Vec3d, 3> axis{};
  axis[order[0]] = unit(e[order[0]]);
  Vec3d second = e[order[1]];
  const double along = dot(second, axis[order[0]]);
  for (std::size_t k = 0; k < 3; ++k) second[k] -= along * axis[order[0]][k];
  if (dot(second, second) < 1e-24 * len[order[0]] * len[order[0]]) {
    // Collinear corners (cannot come from a valid mesh): any perpendicular.
    const Vec3d& a = axis[order[0]];
    second = std::fabs(a[0]) < 0.9 ? Vec3d{0, -a[2], a[1]} : Vec3d{-a[2], 0, a[0]};
  }
  axis[order[1]] = unit(second);
  const Vec3d& a = axis[order[0]];
  const Vec3d& b = axis[order[1]];
  axis[order[2]] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  for (std::size_t i = 0; i < 3; ++i) {
    box.half[i] = static_cast<float>(std::fabs(dot(e[i], axis[i])) / 2);
    for (std::size_t k = 0; k < 3; ++k) {
      box.axes[i][k] = static_cast<float>(axis[i][k]);
      box.center[k] += 0.5 * e[i][k] + (i == 0 ? corners[0][k] : 0.0);
    }
  }
  return box;
}

}  // namespace caustix::bake
