// OFF, PLY and STL through CGAL's readers (mesh_soup.h says why these and
// not OpenMesh's). CGAL's IO headers stay in this translation unit.
//
// Sanitizers: CGAL's OFF scanner converts each number it reads as a face
// size or vertex index from double to size_t; for a value out of range
// (-1, 1e30) that conversion is undefined, and UBSan's float-cast-overflow
// stops there (fuzz_mesh_import). What the conversion gives on x86-64 is
// a huge count or index, which the scanner and read_off refuse at the next
// value (no allocation is sized from it). Its header code also doubles the
// declared edge count in an int (File_header_OFF_impl.h), which overflows
// for a count above 2^30; this file is built with -fwrapv, so that wraps
// and CGAL replaces the implausible count (the edges are never used). Those
// two checks are off for this file (bake/CMakeLists.txt); everything else
// stays checked.
//
// Kernel: Simple_cartesian<double>, used only as a point type to read into.
// Reading decides nothing geometric (the STL reader merges points that
// compare equal coordinate by coordinate, which is exact on doubles), so no
// exact predicates are needed here; the triangulation that follows uses
// them (mesh_triangulate_cgal.cpp).

#include <CGAL/IO/OFF/File_scanner_OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>
#include <CGAL/IO/read_ply_points.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <new>
#include <optional>
#include <sstream>

#include "mesh_soup.h"

namespace caustix::bake {
namespace {

using K = CGAL::Simple_cartesian<double>;

Error input(const std::string& msg) { return make_error(ErrorCode::kInput, msg); }

// 1-based line of byte offset `pos` (error messages of the text formats).
std::size_t line_at(const std::string& path, std::streamoff pos) {
  std::ifstream in(path, std::ios::binary);
  std::size_t line = 1;
  char c = 0;
  for (std::streamoff i = 0; i < pos && in.get(c); ++i) line += c == '\n';
  return line;
}

std::streamoff position(std::istream& in) {
  in.clear();
  const auto p = in.tellg();
  return p < 0 ? 0 : static_cast<std::streamoff>(p);
}

std::uint64_t file_size(const std::string& path) {
  std::error_code ec;
  const auto n = std::filesystem::file_size(path, ec);
  return ec ? 0 : static_cast<std::uint64_t>(n);
}

// Offset of the first byte after `from` that is neither white space nor
// inside a '#' comment (ASCII OFF), or -1 at the end of the file.
std::streamoff first_data_after(std::istream& in, std::streamoff from) {
  in.clear();
  in.seekg(from);
  for (char c = 0; in.get(c);) {
    if (c == '#') {
      while (in.get(c) && c != '\n') {}
      continue;
    }
    if (!std::isspace(static_cast<unsigned char>(c))) return position(in) - 1;
  }
  return -1;
}

// Where an ASCII STL stops following its grammar (CGAL's reader says only
// that it failed): solid NAME, then per triangle facet normal X Y Z / outer
// loop / three vertex X Y Z / endloop / endfacet, then endsolid.
std::string ascii_stl_error(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::size_t line_no = 0;
  int vertices = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word)) continue;
    for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const auto three_numbers = [&](const char* what) -> std::optional<std::string> {
      double x = 0, y = 0, z = 0;
      if (ls >> x >> y >> z) return std::nullopt;
      return "line " + std::to_string(line_no) + ": '" + line.substr(line.find_first_not_of(" \t")) + "' is not '" +
             what + " X Y Z' with three numbers";
    };
    if (word == "vertex") {
      if (auto bad = three_numbers("vertex")) return *bad;
      ++vertices;
    } else if (word == "facet") {
      std::string normal;
      ls >> normal;
      if (auto bad = three_numbers("facet normal")) return *bad;
      vertices = 0;
    } else if (word == "endloop") {
      if (vertices != 3) {
        return "line " + std::to_string(line_no) + ": a facet's loop has " + std::to_string(vertices) + " vertices, not 3";
      }
    } else if (word != "solid" && word != "outer" && word != "endfacet" && word != "endsolid") {
      return "line " + std::to_string(line_no) + ": unexpected '" + word + "'";
    }
  }
  return "the file ends inside a solid (line " + std::to_string(line_no) + ")";
}

}  // namespace

Result<PolygonSoup> read_off(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return input("cannot open the file");
  const std::uint64_t size = file_size(path);
  // The header: comment lines, [ST][C][N][4][n]OFF [BINARY], the counts
  // (on the keyword's line or the next one, comments between).
  CGAL::File_scanner_OFF scanner(in, false);
  if (!in || scanner.skel()) {
    std::ifstream again(path, std::ios::binary);
    std::string first;
    while (std::getline(again, first) && (first.find_first_not_of(" \t\r") == std::string::npos ||
                                          first[first.find_first_not_of(" \t\r")] == '#')) {}
    if (const auto b = first.find_first_not_of(" \t\r"); b != std::string::npos) first = first.substr(b, 40);
    return input("cannot read the OFF header: expected the keyword OFF, COFF, NOFF, CNOFF, 4OFF or STOFF (after "
                 "any '#' comment lines), then the vertex, face and edge counts (each below 2^31); the file starts '" +
                 first + "'");
  }
  if (scanner.n_dimensional() && scanner.dimension() != 3) {
    return input("an nOFF file of dimension " + std::to_string(scanner.dimension()) + "; only 3-D points are meshes");
  }
  const std::uint64_t nv = scanner.size_of_vertices(), nf = scanner.size_of_facets();
  // Bound the counts by the data before anything is sized from them: an
  // ASCII vertex takes at least "0 0 0\n" and a face "3 0 0 0\n"; a binary
  // vertex 12 bytes, a binary face 20 (size, three indices, colour count).
  const std::uint64_t data = size - std::min<std::uint64_t>(size, static_cast<std::uint64_t>(position(in)));
  const long double need = scanner.binary() ? 12.0L * nv + 20.0L * nf : 6.0L * nv + 8.0L * nf - 1.0L;
  if (need > static_cast<long double>(data)) {
    return input("the header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                 " faces, but only " + std::to_string(data) + " bytes follow it");
  }
  // The scanner reads a vertex or face as one line, newline included: the
  // record just read ends at the byte before the stream's position.
  const auto where = [&](const std::string& what) {
    const std::streamoff at = position(in);
    return scanner.binary() ? what + " (byte " + std::to_string(at) + ")"
                            : what + " (line " + std::to_string(line_at(path, std::max<std::streamoff>(0, at - 1))) + ")";
  };

  PolygonSoup soup;
  soup.points.reserve(nv);
  if (scanner.has_normals()) soup.normals.reserve(nv);
  for (std::uint64_t i = 0; i < nv; ++i) {
    double x = 0, y = 0, z = 0, w = 1;
    scanner.scan_vertex(x, y, z, w);
    if (scanner.has_normals()) {
      double nx = 0, ny = 0, nz = 0;
      scanner.scan_normal(nx, ny, nz);
      soup.normals.push_back({nx, ny, nz});
    }
    // Colours and texture coordinates are not used. In ASCII the scanner
    // has read the whole line already, so they are not interpreted either:
    // its colour conversion casts any number to unsigned char (undefined
    // for 9e8, found by fuzz_mesh_import) and its texture look-up indexes
    // the line's values with an uninitialised offset when the header has
    // ST without C. A binary file's texture coordinates must be read past.
    if (scanner.binary() && scanner.has_textures()) {
      double u = 0, v = 0;
      scanner.scan_texture(u, v);
    }
    if (in.fail()) {
      return input(where("vertex " + std::to_string(i) + ": cannot read its coordinates" +
                         (scanner.has_normals() ? " and normal" : "") + "; the header declares " +
                         std::to_string(nv) + " vertices"));
    }
    soup.points.push_back({x / w, y / w, z / w});  // 4OFF: homogeneous
  }
  soup.offsets.reserve(nf + 1);
  for (std::uint64_t f = 0; f < nf; ++f) {
    std::size_t n = 0;
    scanner.scan_facet(n, f);
    if (in.fail()) {
      return input(where("face " + std::to_string(f) + ": cannot read it; the header declares " +
                         std::to_string(nf) + " faces"));
    }
    for (std::size_t j = 0; j < n; ++j) {
      std::size_t id = 0;
      scanner.scan_facet_vertex_index(id, j + 1, f);
      if (in.fail()) {
        return input(where("face " + std::to_string(f) + ": corner " + std::to_string(j) +
                           " is missing or not a vertex index below " + std::to_string(nv)));
      }
      soup.corners.push_back(static_cast<std::uint32_t>(id));
    }
    scanner.skip_to_next_facet(f);  // binary: the colour count and values (ASCII: on the line already read)
    if (in.fail()) return input(where("face " + std::to_string(f) + ": cannot read its colour"));
    soup.add_polygon_end();
  }
  // Data after the declared faces: the counts do not describe the file.
  const std::streamoff end = position(in);
  const std::streamoff extra = scanner.binary() ? (static_cast<std::uint64_t>(end) < size ? end : -1)
                                                : first_data_after(in, end);
  if (extra >= 0) {
    return input("the header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                 " faces, but more data follows them (" +
                 (scanner.binary() ? "byte " + std::to_string(extra) : "line " + std::to_string(line_at(path, extra))) +
                 ")");
  }
  return soup;
}

Result<PolygonSoup> read_ply(const std::string& path) {
  PlyNormals normals;
  if (auto bad = check_declared_counts(path, MeshFormat::kPly, &normals)) return input(*bad);
  std::ifstream in(path, std::ios::binary);
  if (!in) return input("cannot open the file");
  std::vector<K::Point_3> points;
  std::vector<std::vector<std::size_t>> polygons;
  try {
    if (!CGAL::IO::read_PLY(in, points, polygons, CGAL::parameters::verbose(false))) {
      return input("CGAL's PLY reader could not read the data (a value that is not a number, or a face "
                   "element without a vertex_indices or vertex_index list of int or uint)");
    }
  } catch (const std::bad_alloc&) {
    return input("out of memory while reading");
  }
  PolygonSoup soup;
  soup.points.reserve(points.size());
  for (const auto& p : points) soup.points.push_back({p.x(), p.y(), p.z()});
  soup.offsets.reserve(polygons.size() + 1);
  for (const auto& poly : polygons) {
    for (std::size_t i : poly) soup.corners.push_back(i > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(i));
    soup.add_polygon_end();
  }
  // Per-vertex normals, where the vertex element has nx, ny, nz: a second
  // pass through CGAL's point reader (its polygon-soup reader drops them),
  // which reads them as float or double only (any other type it
  // dereferences as a null pointer, as for coordinates).
  if (normals.present && !normals.unreadable_type.empty()) {
    soup.warnings.push_back("the vertex normals (nx, ny, nz) include a " + normals.unreadable_type +
                            ", not float or double; normals are computed");
  } else if (normals.present) {
    std::ifstream again(path, std::ios::binary);
    using PointNormal = std::pair<K::Point_3, K::Vector_3>;
    std::vector<PointNormal> pn;
    if (CGAL::IO::read_PLY_with_properties(again, std::back_inserter(pn),
                                           CGAL::make_ply_point_reader(CGAL::First_of_pair_property_map<PointNormal>()),
                                           CGAL::make_ply_normal_reader(CGAL::Second_of_pair_property_map<PointNormal>())) &&
        pn.size() == soup.points.size()) {
      for (const auto& [p, n] : pn) soup.normals.push_back({n.x(), n.y(), n.z()});
    } else {
      soup.warnings.push_back("the vertex normals (nx, ny, nz) could not be read; normals are computed");
    }
  }
  return soup;
}

Result<PolygonSoup> read_stl(const std::string& path) {
  if (auto bad = check_declared_counts(path, MeshFormat::kStl)) return input(*bad);
  std::vector<K::Point_3> points;
  std::vector<std::array<std::size_t, 3>> triangles;
  try {
    // Binary unless it starts with "solid" and parses as ASCII (binary
    // files whose free-form header starts with "solid" fall back to binary).
    std::ifstream in(path, std::ios::binary);
    if (!in) return input("cannot open the file");
    if (!CGAL::IO::read_STL(in, points, triangles, CGAL::parameters::verbose(false))) {
      // Binary sizes were checked before, so the file was read as ASCII.
      return input("not a valid ASCII STL: " + ascii_stl_error(path));
    }
  } catch (const std::bad_alloc&) {
    return input("out of memory while reading");
  }
  PolygonSoup soup;
  soup.points.reserve(points.size());
  for (const auto& p : points) soup.points.push_back({p.x(), p.y(), p.z()});
  soup.corners.reserve(3 * triangles.size());
  soup.offsets.reserve(triangles.size() + 1);
  for (const auto& t : triangles) {
    for (std::size_t i : t) soup.corners.push_back(static_cast<std::uint32_t>(i));
    soup.add_polygon_end();
  }
  return soup;
}

}  // namespace caustix::bake
