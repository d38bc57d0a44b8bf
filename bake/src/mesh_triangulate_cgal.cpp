// Polygons into triangles (mesh_soup.h), CGAL's constrained Delaunay
// triangulation in its own translation unit.
//
// Kernel: Exact_predicates_inexact_constructions_kernel. A triangulation is
// a combinatorial structure built from orientation and in-circle tests; with
// inexact predicates (Simple_cartesian<double>) nearly collinear corners --
// T-junctions, scanned outlines -- get contradictory answers, and the
// structure is corrupted or the insertion does not terminate (how CGAL's
// convex hull failed on such meshes). Nothing here constructs new points.

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <deque>

#include "mesh_soup.h"

namespace caustix::bake {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, CGAL::Triangulation_face_base_with_info_2<int, K>>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Crossing outlines are not triangulated here (they would need new points):
// the tag makes CGAL throw instead.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_tag>;

PolygonTriangles fan(std::size_t n, bool simple) {
  PolygonTriangles out;
  out.simple = simple;
  for (std::uint32_t i = 1; i + 1 < n; ++i) out.triangles.push_back({0, i, i + 1});
  return out;
}

}  // namespace

PolygonTriangles triangulate_polygon(const std::vector<std::array<double, 3>>& c) {
  const std::size_t n = c.size();
  // Newell's normal: the polygon's area vector, robust for non-planar and
  // non-convex outlines. Project along its largest component, keeping the
  // polygon counter-clockwise in the projection (so triangles keep its
  // winding).
  std::array<double, 3> normal{0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = c[i];
    const auto& q = c[(i + 1) % n];
    normal[0] += (p[1] - q[1]) * (p[2] + q[2]);
    normal[1] += (p[2] - q[2]) * (p[0] + q[0]);
    normal[2] += (p[0] - q[0]) * (p[1] + q[1]);
  }
  std::size_t axis = 0;
  for (std::size_t k = 1; k < 3; ++k) {
    if (std::fabs(normal[k]) > std::fabs(normal[axis])) axis = k;
  }
  if (!(std::fabs(normal[axis]) > 0)) return fan(n, false);  // no area (or not finite)
  const std::size_t u = normal[axis] > 0 ? (axis + 1) % 3 : (axis + 2) % 3;
  const std::size_t v = normal[axis] > 0 ? (axis + 2) % 3 : (axis + 1) % 3;
  std::vector<K::Point_2> p;
  p.reserve(n);
  for (const auto& q : c) p.emplace_back(q[u], q[v]);

  // Strictly convex (every turn to the left, turning once around): a fan.
  bool convex = true;
  double turning = 0;
  for (std::size_t i = 0; i < n && convex; ++i) {
    const K::Point_2& a = p[i];
    const K::Point_2& b = p[(i + 1) % n];
    const K::Point_2& d = p[(i + 2) % n];
    convex = CGAL::orientation(a, b, d) == CGAL::LEFT_TURN;
    turning += std::atan2((b.x() - a.x()) * (d.y() - b.y()) - (b.y() - a.y()) * (d.x() - b.x()),
                          (b.x() - a.x()) * (d.x() - b.x()) + (b.y() - a.y()) * (d.y() - b.y()));
  }
  if (convex && turning < 3 * M_PI) return fan(n, true);  // exterior angles sum to 2 pi, not 4 pi or more

  // Otherwise: the outline as constraints; the faces inside it are those
  // reached from outside by crossing the outline an odd number of times.
  try {
    Cdt cdt;
    std::vector<Cdt::Vertex_handle> vh;
    vh.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      Cdt::Vertex_handle h = cdt.insert(p[i]);
      if (cdt.number_of_vertices() != i + 1) return fan(n, false);  // a corner repeats: the outline touches itself
      h->info() = i;
      vh.push_back(h);
    }
    for (std::size_t i = 0; i < n; ++i) cdt.insert_constraint(vh[i], vh[(i + 1) % n]);
    for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
    std::deque<std::pair<Cdt::Face_handle, int>> todo{{cdt.infinite_face(), 0}};
    while (!todo.empty()) {
      auto [f, level] = todo.front();
      todo.pop_front();
      if (f->info() != -1) continue;
      f->info() = level;
      for (int e = 0; e < 3; ++e) {
        Cdt::Face_handle g = f->neighbor(e);
        if (g->info() == -1) todo.emplace_back(g, cdt.is_constrained({f, e}) ? level + 1 : level);
      }
    }
    PolygonTriangles out;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      if (f->info() % 2 == 1) out.triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
    }
    // A simple polygon of n corners has exactly n - 2 triangles inside.
    if (out.triangles.size() != n - 2) return fan(n, false);
    return out;
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    return fan(n, false);  // the outline crosses itself
  }
}

}  // namespace caustix::bake
