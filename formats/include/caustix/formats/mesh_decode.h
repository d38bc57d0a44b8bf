#pragma once
// Draco decoding of a MESH chunk (encoder: bake/mesh_compress.h). The result
// is checked against the chunk's MeshInfo: vertex and triangle counts,
// in-range indices, finite positions within the recorded bounds (widened
// by the quantisation bound), unit normals. Errors name the mesh.

#include <array>
#include <cstdint>
#include <span>

#include "caustix/common/mesh.h"
#include "caustix/common/status.h"
#include "caustix/formats/scene.h"

namespace caustix {

// Largest per-coordinate error of positions quantised to `bits` bits by
// Draco, in object-space metres: half a step delta = range / (2^bits - 1),
// range being the largest side of the bounding box, plus float rounding.
double position_error_bound(const std::array<float, 3>& bounds_min, const std::array<float, 3>& bounds_max, int bits);

Result<TriangleMesh> decode_draco(std::span<const std::uint8_t> stream, const MeshInfo& info);

}  // namespace caustix
