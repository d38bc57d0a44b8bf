#pragma once
// Embree 3 first-hit queries (single precision, robust mode), only for
// caustix-bench raycast: the measured alternative to the CGAL AABB tree the
// baker and caustix-reference use (docs/reference.md says why CGAL stays).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "caustix/formats/frame.h"

namespace caustix::bench {

class EmbreeCaster {
 public:
  EmbreeCaster(const std::vector<Vec3d>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles);
  ~EmbreeCaster();
  EmbreeCaster(const EmbreeCaster&) = delete;
  EmbreeCaster& operator=(const EmbreeCaster&) = delete;
  // Distance along the unit direction to the first triangle hit.
  std::optional<double> first_hit(const Vec3d& origin, const Vec3d& direction) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::bench
