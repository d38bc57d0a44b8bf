#pragma once
// Draco decoding of a MESH chunk (encoder: bake/mesh_compress.h). The result
// is checked against the chunk's MeshInfo: vertex and triangle counts,
// in-range indices, finite positions within the recorded bounds, unit
// normals. Errors name the mesh.

#include <cstdint>
#include <span>

#include "caustix/common/mesh.h"
#include "caustix/common/status.h"
#include "caustix/formats/scene.h"

namespace caustix {

Result<TriangleMesh> decode_draco(std::span<const std::uint8_t> stream, const MeshInfo& info);

}  // namespace caustix
