#pragma once
// Exact ray casting against triangle meshes through CGAL's AABB tree (one
// translation unit, behind this plain interface). Used as the independent
// check of the position-map rasteriser, for its measurement, and for the
// "fully shadowed" test of the level-map stage. Thread-safe queries.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "caustix/formats/frame.h"

namespace caustix::bake {

class RayCaster {
 public:
  // Triangles of several objects; owner[i] names triangle i's object.
  RayCaster(const std::vector<Vec3d>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
            const std::vector<std::uint32_t>& owner);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // Distance along the unit direction to the first triangle hit, ignoring
  // triangles owned by `skip_owner` (pass UINT32_MAX to skip none).
  std::optional<double> first_hit(const Vec3d& origin, const Vec3d& direction,
                                  std::uint32_t skip_owner = UINT32_MAX) const;

  struct Hit {
    double distance;
    std::uint32_t triangle;  // index into the constructor's triangles
  };
  // As first_hit(), also naming the triangle hit.
  std::optional<Hit> first_hit_triangle(const Vec3d& origin, const Vec3d& direction,
                                        std::uint32_t skip_owner = UINT32_MAX) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The same first-hit queries through Embree 3, several times the CGAL
// tree's rays per second (docs/reference.md), for the light-transport
// tables and the reference tracer's rays that start off every mesh.
// Robust mode (watertight: rays through shared edges and vertices
// hit, GeometryKernel.EmbreeRaysThroughSharedEdgesAndVerticesHit); single
// precision, with the mesh moved to its box's centre so that float
// coordinates keep 2^-24 of its size; the BVH built on one thread, so that
// it, and every answer, does not depend on the thread count. Thread-safe
// queries. One object, no owners.
class EmbreeCaster {
 public:
  EmbreeCaster(const std::vector<Vec3d>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles);
  ~EmbreeCaster();
  EmbreeCaster(const EmbreeCaster&) = delete;
  EmbreeCaster& operator=(const EmbreeCaster&) = delete;
  // False when Embree could not be started (the caller falls back to CGAL).
  bool ok() const;
  std::optional<RayCaster::Hit> first_hit_triangle(const Vec3d& origin, const Vec3d& direction) const;
  bool occluded(const Vec3d& origin, const Vec3d& direction) const;
  // The threads that built the BVH: 1, so that it, and which of two equally
  // near triangles answers, does not depend on the thread count.
  std::size_t build_threads() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::bake
