#pragma once
// Voxelisation of a transparent object's refractive index and the octree of
// near-constant index (Pfeuti, "Voxelization", "Octree Construction";
// formats/index_grid.h describes the result). Deterministic whatever the
// thread count.

#include <cstdint>
#include <functional>

#include "caustix/common/mesh.h"
#include "caustix/formats/index_grid.h"
#include "caustix/formats/scene.h"

namespace caustix::bake {

struct IndexGridOptions {
  std::uint32_t resolution = 64;  // voxels along the mesh's longest side (caustix-bake --volume-res)
  float blur = 1.0f;              // Gaussian sigma in voxels, 0..8 (--volume-blur)
  float epsilon = 0.01f;          // octree threshold on n (--octree-eps)
  std::uint32_t supersample = 4;  // coverage rows per voxel axis (y and z; x is exact)
};

// Voxels the grid of `mesh` would have: the mesh's bounds at the option's
// resolution, padded by the Gaussian's support (checked against
// kMaxIndexGridVoxels before any memory is taken).
std::uint64_t index_grid_voxels(const TriangleMesh& mesh, const IndexGridOptions& options);

// The mesh (object space, closed) voxelised: the exact inside fraction of
// each voxel along x over supersample^2 rows in y and z (parity of the
// crossings of each row), Gaussian-filtered, then the octree levels.
// ior_outside is the index around the object. `progress`, when given, is
// called with the fraction done (from any thread, about every 1 % of the
// voxel rows, then after each later step); once it returns false the grid
// stops where it is and what is returned is incomplete (the baker's
// budgets).
IndexGrid voxelize_index(std::uint32_t object, const TriangleMesh& mesh, float ior_inside, float ior_outside,
                         const IndexGridOptions& options, const std::function<bool(double)>& progress = {});

}  // namespace caustix::bake
