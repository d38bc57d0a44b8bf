// CGAL's AABB tree lives only in this translation unit (compile cost).
//
// Kernel: Exact_predicates_inexact_constructions_kernel. Whether a ray hits
// a triangle is decided by orientation tests; in Simple_cartesian<double>
// a ray through a shared edge or vertex can be judged to miss every
// triangle around it, and light leaks out of a closed surface: from points
// inside a 48 x 24 UV sphere, 3208 of 154 600 rays aimed at its vertices
// and edge midpoints hit nothing (the sphere test in
// geometry_kernel_test.cpp; with exact predicates, none after the fallback
// in first_hit_triangle). The light-transport tracer starts its rays at
// vertices and the baker's rays run along grid lines, so such rays are not
// rare. The hit point itself is constructed in doubles. Cost: caustix-bench
// raycast runs at 0.70-0.74x the rays per second of Simple_cartesian
// (exact predicates 0.90-0.93x, the fallback the rest; docs/robustness.md).

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>

#include "caustix/bake/ray_cast.h"

namespace caustix::bake {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = K::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

}  // namespace

struct RayCaster::Impl {
  std::vector<Triangle> triangles;  // the non-degenerate input triangles
  std::vector<std::uint32_t> index;  // their indices in the input
  std::vector<std::uint32_t> owner;  // per input triangle
  Tree tree;
};

RayCaster::RayCaster(const std::vector<Vec3d>& p, const std::vector<std::array<std::uint32_t, 3>>& tris,
                     const std::vector<std::uint32_t>& owner)
    : impl_(std::make_unique<Impl>()) {
  impl_->triangles.reserve(tris.size());
  impl_->index.reserve(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const auto& t = tris[i];
    const Triangle tri(K::Point_3(p[t[0]][0], p[t[0]][1], p[t[0]][2]), K::Point_3(p[t[1]][0], p[t[1]][1], p[t[1]][2]),
                       K::Point_3(p[t[2]][0], p[t[2]][1], p[t[2]][2]));
    // A triangle whose corners are exactly collinear (the importer drops
    // them, but quantising a mesh can make one: a glass mesh's Draco-decoded
    // sliver) covers no area, and CGAL's exact ray-triangle code stops with
    // an error on it for a ray in its line ("the triangle is assumed to be
    // non flat"). Its neighbours cover the surface.
    if (tri.is_degenerate()) continue;
    impl_->triangles.push_back(tri);
    impl_->index.push_back(static_cast<std::uint32_t>(i));
  }
  impl_->owner = owner;
  impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

RayCaster::~RayCaster() = default;

std::optional<double> RayCaster::first_hit(const Vec3d& o, const Vec3d& d, std::uint32_t skip_owner) const {
  const auto hit = first_hit_triangle(o, d, skip_owner);
  if (!hit) return std::nullopt;
  return hit->distance;
}

namespace {

// Distance from the ray's source to an intersection (a point, or a segment
// where the ray runs in the triangle's plane); nothing for other results.
template <typename Intersection>
std::optional<double> distance_to(const K::Ray_3& ray, const Intersection& x) {
  if (const K::Point_3* pt = boost::get<K::Point_3>(&x)) return std::sqrt(CGAL::squared_distance(ray.source(), *pt));
  if (const K::Segment_3* seg = boost::get<K::Segment_3>(&x)) {
    return std::sqrt(std::min(CGAL::squared_distance(ray.source(), seg->source()),
                              CGAL::squared_distance(ray.source(), seg->target())));
  }
  return std::nullopt;
}

}  // namespace

std::optional<RayCaster::Hit> RayCaster::first_hit_triangle(const Vec3d& o, const Vec3d& d, std::uint32_t skip_owner) const {
  if (impl_->triangles.empty()) return std::nullopt;
  const K::Ray_3 ray(K::Point_3(o[0], o[1], o[2]), K::Vector_3(d[0], d[1], d[2]));
  const auto begin = impl_->triangles.begin();
  const auto& owner = impl_->owner;
  const auto input = [&](const Iterator& it) { return impl_->index[static_cast<std::size_t>(it - begin)]; };
  auto skip = [&](const Iterator& it) { return owner[input(it)] == skip_owner; };
  if (const auto hit = impl_->tree.first_intersection(ray, skip)) {
    if (const auto dist = distance_to(ray, hit->first)) return Hit{*dist, input(hit->second)};
  }
  // CGAL 5.5's first_intersection orders and prunes boxes by a ray-box
  // distance computed in doubles, which drops boxes the ray only touches:
  // at a mesh vertex, a corner of its triangles' boxes. Even on exact
  // predicates 611 of the 154 600 vertex and edge rays of the sphere test
  // found nothing that way. The exact traversal decides instead (cheap
  // where the ray misses everything), and the nearest of its hits wins.
  if (!impl_->tree.do_intersect(ray)) return std::nullopt;
  std::vector<Tree::Intersection_and_primitive_id<K::Ray_3>::Type> all;
  impl_->tree.all_intersections(ray, std::back_inserter(all));
  std::optional<Hit> best;
  for (const auto& x : all) {
    if (skip(x.second)) continue;
    const auto dist = distance_to(ray, x.first);
    if (dist && (!best || *dist < best->distance)) best = Hit{*dist, input(x.second)};
  }
  return best;
}

}  // namespace caustix::bake
