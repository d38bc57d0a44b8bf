#pragma once
// Voxelised refractive index of a transparent object, for photon marching
// in media (Pfeuti, "Voxelization" and "Octree Construction"; Sun et al.
// 2008). Baked by bake/index_grid.h only for scenes where something
// scatters; stored as one "IGRD" chunk per transparent object
// (formats/SPEC.md). The grid lies in object space, so it follows the
// object's rigid motion at run time.
//
// coverage: the fraction of each voxel inside the mesh, Gaussian-filtered
// (Pfeuti's "grey voxels"), quantised to q / 65535. The index is
//   n = ior_outside + (ior_inside - ior_outside) * coverage.
// level: the octree of regions of near-constant index, stored per voxel as
// the level k of the largest aligned cube of 2^k voxels around it whose
// index varies by at most epsilon (cells outside the grid count as
// outside the object): a photon there can take one step across that cube.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/types.h"

namespace caustix {

struct SceneDesc;

// Refused beyond this (3 bytes a voxel raw: 384 MiB).
inline constexpr std::uint64_t kMaxIndexGridVoxels = std::uint64_t{1} << 27;
inline constexpr std::uint8_t kMaxOctreeLevel = 15;

struct IndexGrid {
  std::uint32_t object = 0;
  std::array<std::uint32_t, 3> size{0, 0, 0};  // voxels along object x, y, z
  Vec3f origin{0, 0, 0};                      // object-space corner of voxel (0, 0, 0)
  float voxel = 0;                            // edge length, object-space metres
  float ior_inside = 1.5f;                    // the material's
  float ior_outside = 1.0f;
  float blur = 1.0f;                          // Gaussian sigma, voxels (0: none)
  float epsilon = 0.01f;                      // octree threshold on n
  std::vector<std::uint16_t> coverage;        // x fastest, then y, then z
  std::vector<std::uint8_t> level;

  std::size_t voxels() const { return std::size_t{size[0]} * size[1] * size[2]; }
  std::size_t index(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
    return (std::size_t{k} * size[1] + j) * size[0] + i;
  }
  float ior_at(std::size_t v) const {
    return ior_outside + (ior_inside - ior_outside) * (static_cast<float>(coverage[v]) / 65535.0f);
  }
};

std::vector<std::uint8_t> encode_index_grid(const IndexGrid& grid);
// Checks everything against the scene (object transparent, its IOR, sizes
// against the voxel limit and the payload, levels in range).
Result<IndexGrid> decode_index_grid(std::span<const std::uint8_t> payload, const SceneDesc& scene);

}  // namespace caustix
