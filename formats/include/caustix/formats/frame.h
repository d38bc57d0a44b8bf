#pragma once
// Bounding frames for level maps (Tipprasert 2006 §4.2.1): the light direction
// refracted by the flat water surface (eq. 2-8), and the frame aligned to it
// (eq. 4-1) with tight extents. Shared by the baker and by the runtime,
// which re-derives frames when a light or an object moves.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "caustix/formats/level_map.h"
#include "caustix/formats/scene.h"

namespace caustix {

using Vec3d = std::array<double, 3>;

// Object-space points through an object -> world matrix, in double
// precision (objects far from the origin keep their detail).
std::vector<Vec3d> world_points(const Mat4f& transform, const std::vector<Vec3f>& points);
// Object-space normals through the same matrix (its cofactor matrix, sign
// kept for mirroring transforms: normals stay normal and outward under any
// invertible affine transform), normalised.
std::vector<Vec3d> world_normals(const Mat4f& transform, const std::vector<Vec3f>& normals);

// Per object: for a transparent object whose world box holds a receiver's
// (an insect in amber), the first such receiver. The light-
// transport tables' rays start where light leaves the glass and never
// reach inside, so the runtime lights such glass by caustic maps; the
// baker says so. A world box is the box of the object's mesh bounds
// (MeshInfo) with its 8 corners through its transform.
std::vector<std::optional<std::uint32_t>> receiver_inside_glass(const SceneDesc& scene);

// Tipprasert 2006 eq. 2-8: T = (eta cos(theta_i) - cos(theta_r)) N + eta I, with I
// the unit incident direction, N the unit normal on the incident side
// (I . N <= 0) and eta = n1 / n2. Returns nothing on total internal reflection.
std::optional<Vec3d> refract(const Vec3d& incident, const Vec3d& normal, double eta);

// Unpolarised Fresnel transmittance 1 - (R_s + R_p) / 2 at an interface
// with eta = n1 / n2 (light going from n1 into n2), cos_i the cosine of
// the angle of incidence; 0 beyond the critical angle.
double fresnel_transmittance(double cos_i, double eta);

struct LightDirection {
  Vec3d travel{};          // unit direction of travel T at the object
  bool refracted = false;  // whether it crossed the water surface
};

// Direction of travel of `light` at an object whose world origin is
// `object_origin` and whose world y range is [min_y, max_y]: refracted by the
// flat water (y = level) when the light comes from above the water and the
// object is not entirely above it; for a point light, along the ray from the
// light to the object's origin, refracted where it crosses the water
// (fig. 4-7). Returns nothing, with the reason, when the light cannot reach
// the object through the water surface.
std::optional<LightDirection> light_direction(const Light& light, const std::optional<Water>& water,
                                              const Vec3d& object_origin, double min_y, double max_y,
                                              std::string* why_not);

// The frame with V = -T: U and W from eq. 4-1 with N the world axis least
// aligned with V (first of x, y, z on ties), so the choice is reproducible;
// origin at the centre of the tight box of `world_points` along U, V, W, and
// the thesis's symmetric size 2 max |coordinate| about `object_origin`
// (eq. 4-3) for comparison. Extents thinner than 1e-6 of the largest are
// widened to that, so a flat object still has a usable depth range.
BoundingFrame make_frame(const Vec3d& travel, const std::vector<Vec3d>& world_points, const Vec3d& object_origin);

// The unit normal of the plane holding every point, if they lie in one
// (within 1e-6 of their extent): a floor, a wall, a table top. Three points
// far apart span it: the first, the farthest from it, the farthest from the
// line through both. O(points).
std::optional<Vec3d> plane_normal(const std::vector<Vec3d>& points);

}  // namespace caustix
