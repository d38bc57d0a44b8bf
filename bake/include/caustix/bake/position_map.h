#pragma once
// Position map and diffuse map (Tipprasert 2006 §4.2.2): an orthographic view along
// -V over the frame (eq. 4-10..4-13), computed on the CPU by a scanline
// rasteriser (texel centres, edge functions in double precision). Per texel:
// the depth of the first surface the light meets (the largest V coordinate),
// stored as t = (half.v - v) / (2 half.v) in 16 bits, so the depth error is at
// most 2 half.v / 65534 / 2 = frame height / 131068; and the receiver's albedo.
// Rows are rasterised in parallel bands; the result does not depend on the
// thread count.

#include <array>
#include <cstdint>
#include <vector>

#include "caustix/formats/frame.h"
#include "caustix/formats/level_map.h"

namespace caustix::bake {

// Frame coordinates (u, v, w) of a world point, relative to the frame origin.
Vec3d to_frame(const BoundingFrame& frame, const Vec3d& world);
// World point at frame coordinates (u, v, w).
Vec3d from_frame(const BoundingFrame& frame, const Vec3d& uvw);
// Centre of texel (row, col) in frame (u, w) coordinates.
std::array<double, 2> texel_center(const BoundingFrame& frame, std::uint32_t size, std::uint32_t row, std::uint32_t col);
// Frame V coordinate of a stored depth.
double depth_to_v(const BoundingFrame& frame, std::uint16_t q);
// Largest error of a stored depth, in metres.
double depth_precision(const BoundingFrame& frame);

// Fills map.depth and map.diffuse (map.frame and map.map_size must be set).
void rasterize_position_map(const std::vector<Vec3d>& world_positions,
                            const std::vector<std::array<std::uint32_t, 3>>& triangles, const Vec3f& albedo,
                            LevelMap& map);

}  // namespace caustix::bake
