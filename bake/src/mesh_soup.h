#pragma once
// The mesh importer's middle: every reader turns a file into a polygon soup
// (points, polygons as index lists, optional per-point normals) exactly as
// the file states it -- no welding, no halfedge structure that could reject
// or split faces -- and mesh_import.cpp validates, triangulates and compacts
// it. Which library reads which format, and why (measured on the
// corpus in tests/data/meshes):
//
//   OFF  CGAL's File_scanner_OFF (mesh_read_cgal.cpp): comments anywhere,
//        COFF/NOFF/CNOFF/4OFF/STOFF headers, counts on the header line,
//        polygons with trailing face colours, Geomview's binary OFF.
//        OpenMesh 9 reads none of comments, 4OFF or face colours.
//   PLY  CGAL's PLY reader (mesh_read_cgal.cpp): elements in any order (faces
//        before vertices), extra elements and properties, vertex_indices or
//        vertex_index lists of int or uint (any count type), ASCII and both
//        binary byte orders. OpenMesh 9 reads no face element declared
//        before the vertices and stops at a face's second list property.
//        CGAL reads coordinates and normals only as float or double and
//        corners only as int or uint: other valid types are refused by name
//        (normals: skipped with a warning) before it runs, because it
//        dereferences a null pointer on them (mesh_header_check.cpp).
//   STL  CGAL's STL reader (mesh_read_cgal.cpp): ASCII, binary, binary files
//        whose header starts with "solid", several solids in one file.
//        OpenMesh 9 accepts an ASCII STL with an unparsable number.
//   OBJ  OpenMesh's OBJ reader (mesh_read_openmesh.cpp) through an importer
//        that records the soup: groups, materials, negative (relative)
//        indices, v/vt/vn corners, polygons, tabs and CRLF, l and p lines.
//        CGAL 5.5's OBJ reader fails on tabs and on l lines. OpenMesh's
//        reader trusts its face lines (it stops on an assertion at "f /1"),
//        so they are checked first and refused by line where it would
//        misread them (mesh_read_openmesh.cpp).
//
// Library readers size containers from the counts a file declares, so
// check_declared_counts() (mesh_header_check.cpp) first bounds every count
// by the bytes that follow, without refusing any valid file whose types
// the reader can take.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "caustix/bake/mesh_import.h"
#include "caustix/common/status.h"

namespace caustix::bake {

enum class MeshFormat { kObj, kOff, kPly, kStl };

struct PolygonSoup {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<double, 3>> normals;  // empty, or one per point as the file gave them
  std::vector<std::array<float, 2>> uvs;       // empty, or one per point (glTF TEXCOORD_n)
  std::vector<std::array<float, 4>> colors;    // empty, or one per point (glTF COLOR_0, linear RGBA)
  // Polygon i is corners[offsets[i] .. offsets[i + 1]) (point indices, not
  // yet range-checked); offsets.size() == polygons + 1.
  std::vector<std::uint32_t> corners;
  std::vector<std::uint32_t> offsets{0};
  std::vector<std::string> warnings;  // what the reader skipped (named, not silent)

  std::size_t polygon_count() const { return offsets.size() - 1; }
  void add_polygon_end() { offsets.push_back(static_cast<std::uint32_t>(corners.size())); }
};

// Exporters split vertices along UV seams and hard edges, and write the
// copies from separate computations (sin 2pi is not sin 0), so a closed
// surface's seam can hold positions a few ulps apart. Points within
// kSnapTolerance of the points' bounding box's longest side of an earlier
// point are moved onto it (the first such point in index order, so the
// result does not depend on anything but the order of the file); their
// other attributes are kept. Topology (census_edges) is then decided on
// exactly equal positions. 2^-20 of the extent is 1 um on a 1 m object,
// far below any feature a mesh for caustics draws and above float
// rounding (2^-24). Returns how many points moved.
inline constexpr double kSnapTolerance = 0x1p-20;
std::size_t snap_close_points(std::vector<std::array<double, 3>>& points);

// Validates, triangulates and compacts a soup as import_mesh() documents
// (bake/include/caustix/bake/mesh_import.h); errors name the vertex or face
// but not the file. The glTF importer builds its soups from accessors.
Result<ImportedMesh> mesh_from_soup(PolygonSoup&& soup);

// Each reader returns the soup or an error message (without the path: the
// importer prefixes it) naming the place: line, element, vertex or face.
Result<PolygonSoup> read_off(const std::string& path);
Result<PolygonSoup> read_ply(const std::string& path);
Result<PolygonSoup> read_stl(const std::string& path);
Result<PolygonSoup> read_obj(const std::string& path);

// What a PLY header says of per-vertex normals: whether the vertex element
// has nx, ny or nz, and the first of their types CGAL cannot read (empty
// when it can read them all: float or double).
struct PlyNormals {
  bool present = false;
  std::string unreadable_type;
};

// Refuses a header whose element counts the data that follows cannot hold
// (OFF, PLY, binary STL), before any library allocates for them: every
// count is bounded by the bytes each element needs at the least, and a
// binary PLY's elements (list lengths included) are walked to the end of
// the file. Never refuses a file whose data matches its header, unless (a
// PLY) its coordinates or corners are of a type CGAL's reader cannot take.
// For a PLY, `normals` (when given) gets what the header says of normals.
std::optional<std::string> check_declared_counts(const std::string& path, MeshFormat format,
                                                 PlyNormals* normals = nullptr);

// Triangles of one polygon (corner positions in order, >= 4 of them), as
// indices into `corners`, wound like the polygon (mesh_triangulate_cgal.cpp).
// Non-convex polygons are triangulated inside their outline (a constrained
// Delaunay triangulation on exact predicates, in the plane of the polygon's
// Newell normal). A polygon whose projected outline crosses or touches
// itself, or has no area, cannot be triangulated that way: `simple` is then
// false and the result is a fan from corner 0.
struct PolygonTriangles {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  bool simple = true;
};
PolygonTriangles triangulate_polygon(const std::vector<std::array<double, 3>>& corners);

}  // namespace caustix::bake
