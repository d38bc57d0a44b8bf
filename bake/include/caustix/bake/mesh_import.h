#pragma once
// Mesh import: OBJ, OFF, PLY and STL (the format follows the file
// extension, in any case), as the files users bring from other tools write
// them: OFF with comments and COFF/NOFF/4OFF headers, PLY in any element
// order with extra properties, ASCII and binary STL, OBJ with groups and
// negative indices, polygons of any size. Which library reads which format
// is in bake/src/mesh_soup.h.
//
// Contract: never crashes, hangs or exhausts memory on a malformed file.
// Refuses (kInput, the message starting with the path and naming the line,
// byte, element, vertex or face) a file that cannot be read, whose header
// declares element counts its data does not hold, that has no faces (a
// point cloud), a non-finite coordinate or one beyond the float range, or a
// face referring to a vertex that does not exist (never silently dropped).
// Polygons are triangulated inside their outline (non-convex ones too, on
// exact predicates); a polygon whose outline crosses itself becomes a fan,
// with a warning. Faces with fewer than three distinct corners or zero area
// are dropped with a warning naming the first ones; non-manifold and
// inconsistently wound edges import with a warning (a transparent object
// with them is refused by the baker). Unused vertices are dropped. Normals
// come from the file when every used vertex has a valid one, otherwise they
// are the normalised sum of the unit normals of each vertex's triangles.

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
