// CGAL's AABB tree lives only in this translation unit (compile cost).

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>

#include "caustix/bake/ray_cast.h"

namespace caustix::bake {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

}  // namespace

struct RayCaster::Impl {
  std::vector<Triangle> triangles;
  std::vector<std::uint32_t> owner;
  Tree tree;
};

RayCaster::RayCaster(const std::vector<Vec3d>& p, const std::vector<std::array<std::uint32_t, 3>>& tris,
                     const std::vector<std::uint32_t>& owner)
    : impl_(std::make_unique<Impl>()) {
  impl_->triangles.reserve(tris.size());
  for (const auto& t : tris) {
    impl_->triangles.emplace_back(K::Point_3(p[t[0]][0], p[t[0]][1], p[t[0]][2]),
                                  K::Point_3(p[t[1]][0], p[t[1]][1], p[t[1]][2]),
                                  K::Point_3(p[t[2]][0], p[t[2]][1], p[t[2]][2]));
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

std::optional<RayCaster::Hit> RayCaster::first_hit_triangle(const Vec3d& o, const Vec3d& d, std::uint32_t skip_owner) const {
  if (impl_->triangles.empty()) return std::nullopt;
  const K::Ray_3 ray(K::Point_3(o[0], o[1], o[2]), K::Vector_3(d[0], d[1], d[2]));
  const auto begin = impl_->triangles.begin();
  const auto& owner = impl_->owner;
  auto skip = [&](const Iterator& it) { return owner[static_cast<std::size_t>(it - begin)] == skip_owner; };
  const auto hit = impl_->tree.first_intersection(ray, skip);
  if (!hit) return std::nullopt;
  const auto tri = static_cast<std::uint32_t>(hit->second - begin);
  if (const K::Point_3* pt = boost::get<K::Point_3>(&hit->first)) {
    return Hit{std::sqrt(CGAL::squared_distance(ray.source(), *pt)), tri};
  }
  if (const K::Segment_3* seg = boost::get<K::Segment_3>(&hit->first)) {  // ray in the triangle's plane
    return Hit{std::sqrt(std::min(CGAL::squared_distance(ray.source(), seg->source()),
                                  CGAL::squared_distance(ray.source(), seg->target()))),
               tri};
  }
  return std::nullopt;
}

}  // namespace caustix::bake
