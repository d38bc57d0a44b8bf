// CGAL's optimal bounding box lives only in this translation unit (about
// 20 s and 1.4 GB to compile).

#include <CGAL/Simple_cartesian.h>
#include <CGAL/optimal_bounding_box.h>

#include <algorithm>
#include <cmath>

#include "caustix/bake/object_box.h"

namespace caustix::bake {

ObjectBox oriented_box(const std::vector<Vec3d>& pts) {
  using K = CGAL::Simple_cartesian<double>;
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
  // Edges from corner 0 along the box's three axes: 0->1, 0->3, 0->5.
  const std::size_t ends[3] = {1, 3, 5};
  std::array<Vec3d, 3> axis{};
  int flat = -1;
  for (std::size_t a = 0; a < 3; ++a) {
    Vec3d e{};
    for (std::size_t k = 0; k < 3; ++k) e[k] = corners[ends[a]][k] - corners[0][k];
    const double len = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    box.half[a] = static_cast<float>(len / 2);
    if (len > 0) {
      for (std::size_t k = 0; k < 3; ++k) axis[a][k] = e[k] / len;
    } else {
      flat = static_cast<int>(a);
    }
    for (std::size_t k = 0; k < 3; ++k) box.center[k] += 0.5 * e[k] + (a == 0 ? corners[0][k] : 0.0);
  }
  if (flat >= 0) {
    // A planar point set gives a zero edge: complete the frame by a cross
    // product of the other two axes. (Import guarantees non-collinear points.)
    const Vec3d& a = axis[(static_cast<std::size_t>(flat) + 1) % 3];
    const Vec3d& b = axis[(static_cast<std::size_t>(flat) + 2) % 3];
    axis[static_cast<std::size_t>(flat)] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  }
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t k = 0; k < 3; ++k) box.axes[a][k] = static_cast<float>(axis[a][k]);
  }
  return box;
}

}  // namespace caustix::bake
