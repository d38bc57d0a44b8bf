#pragma once
// Draco compression of baked meshes (edgebreaker connectivity, quantised
// attributes). The runtime decodes with formats/mesh_decode.h.
//
// Error bound: Draco quantises each position coordinate to
// round((x - min) / delta) with delta = range / (2^bits - 1), range being the
// largest side of the mesh's bounding box. The decoded coordinate is within
// delta / 2 of the source (plus float rounding): position_error_bound().

#include <array>
#include <cstdint>
#include <vector>

#include "caustix/common/mesh.h"
#include "caustix/common/status.h"
#include "caustix/formats/mesh_decode.h"
#include "caustix/formats/scene.h"

namespace caustix::bake {

struct DracoOptions {
  int position_bits = 14;  // 8..30; 14 => 0.03 mm on a 1 m object
  int normal_bits = 14;    // 6..30 (octahedral); 10 => under 0.2 deg, each bit halves it.
                           // 14: the normals steer refraction through glass, and
                           // coarser ones make light-transport tables larger and
                           // less accurate (docs/glass-tables.md)
  int speed = 3;           // Draco encoder speed 0 (smallest) .. 10 (fastest)
};

// Largest per-coordinate error of decoded positions (formats/mesh_decode.h).
using caustix::position_error_bound;

// The MESH chunk's description of `mesh` compressed with `options`
// (counts, quantisation bits, bounds; `source` left empty).
MeshInfo describe_mesh(const TriangleMesh& mesh, const DracoOptions& options);

// Encodes a valid mesh (see mesh_import.h). Deterministic.
Result<std::vector<std::uint8_t>> encode_draco(const TriangleMesh& mesh, const DracoOptions& options);

}  // namespace caustix::bake
