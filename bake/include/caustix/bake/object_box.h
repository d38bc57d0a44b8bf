#pragma once
// Tight oriented bounding box of a point set, from CGAL's
// oriented_bounding_box (one translation unit, behind this interface), with
// a fixed random seed so the result is reproducible. Falls back to the
// axis-aligned box for fewer than four points.

#include <vector>

#include "caustix/formats/frame.h"
#include "caustix/formats/level_map.h"

namespace caustix::bake {

ObjectBox oriented_box(const std::vector<Vec3d>& world_points);

}  // namespace caustix::bake
