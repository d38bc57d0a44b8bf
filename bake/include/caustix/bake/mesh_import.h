#pragma once
// Mesh import through OpenMesh (OBJ, OFF, PLY, STL; the format follows the
// file extension) and validation.
//
// Contract: never crashes on a malformed file. Refuses (kInput, naming the
// file and the vertex or face index) a file whose header's element counts
// do not match its data (OFF, PLY, binary STL; checked before OpenMesh
// reads it), that cannot be read, has no
// faces, has a non-finite coordinate or normal, or lost data on import
// (OpenMesh drops faces with out-of-range vertex indices and values it cannot
// parse; a mesh with missing faces is refused, not silently baked). Polygons
// are triangulated; degenerate (zero-area) triangles are dropped and reported
// as warnings, as are non-manifold vertices OpenMesh had to duplicate. Normals
// come from the file when it has valid ones, otherwise they are computed.

#include <string>
#include <vector>

#include "caustix/common/mesh.h"
#include "caustix/common/status.h"

namespace caustix::bake {

struct ImportedMesh {
  TriangleMesh mesh;
  bool normals_from_file = false;
  std::vector<std::string> warnings;
};

Result<ImportedMesh> import_mesh(const std::string& path);

}  // namespace caustix::bake
