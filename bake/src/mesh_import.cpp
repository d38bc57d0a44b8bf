#include "caustix/bake/mesh_import.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <new>
#include <optional>
#include <sstream>

namespace caustix::bake {
namespace {

using OmMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

Error input_error(const std::string& path, const std::string& msg) {
  return make_error(ErrorCode::kInput, path + ": " + msg);
}

// OpenMesh reports dropped data only on its omerr stream; capture it for the
// duration of one read. omerr is process-global, hence the lock.
std::mutex g_omerr_mutex;

struct ReadOutcome {
  bool ok = false;
  bool had_normals = false;
  std::string report;
};

ReadOutcome read_with_report(OmMesh& m, const std::string& path) {
  std::lock_guard<std::mutex> lock(g_omerr_mutex);
  std::ostringstream captured;
  omerr().disconnect(std::cerr);
  omerr().connect(captured);
  omlog().disconnect(std::clog);
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexNormal;
  m.request_vertex_normals();
  ReadOutcome out;
  try {
    out.ok = OpenMesh::IO::read_mesh(m, path, opt);
  } catch (const std::bad_alloc&) {  // counts the header check cannot bound (OBJ)
    out.ok = false;
    captured << "out of memory";
  }
  out.had_normals = opt.vertex_has_normal();
  omerr().flush();
  omerr().disconnect(captured);
  omerr().connect(std::cerr);
  out.report = captured.str();
  return out;
}

std::size_t count_occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1)) ++n;
  return n;
}

bool finite3(const OmMesh::Point& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// Element counts declared in a file's header (OFF, PLY, binary STL), checked
// against the data that follows before OpenMesh reads it: OpenMesh reserves
// memory for the declared counts (10^9 vertices: std::bad_alloc), invents
// faces from stale values when an ASCII OFF ends early, and silently reads
// fewer faces than a PLY header declares. A header that lies in either
// direction is refused with both counts.
struct Declared {
  std::uint64_t vertices = 0, faces = 0;
};

std::string trim_comment(std::string line) {
  if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
  const auto b = line.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  return line.substr(b, line.find_last_not_of(" \t\r") + 1 - b);
}

// Non-blank, non-comment lines left in `in` (ASCII data of OFF and PLY: one
// vertex or one face per line).
std::uint64_t count_data_lines(std::istream& in) {
  std::uint64_t n = 0;
  for (std::string line; std::getline(in, line);) n += !trim_comment(line).empty();
  return n;
}

std::optional<std::string> check_declared_counts(const std::string& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  if (!in || ec) return std::string("cannot open the file");
  const auto lie = [](const std::string& declared, const std::string& found) {
    return "the header declares " + declared + " but the file holds " + found +
           "; refusing a file whose header does not match its data";
  };
  const auto declared = [](const Declared& d, const char* unit) {
    return std::to_string(d.vertices) + " vertices and " + std::to_string(d.faces) + " faces" + unit;
  };
  std::string lower = ext;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == ".off") {
    std::string line, first;
    while (first.empty() && std::getline(in, line)) first = trim_comment(line);
    if (first.size() < 3 || first.compare(first.size() - 3, 3, "OFF") != 0) return std::nullopt;  // OpenMesh decides
    if (first.find(' ') != std::string::npos) return std::nullopt;  // "OFF BINARY": left to OpenMesh
    std::string counts;
    while (counts.empty() && std::getline(in, line)) counts = trim_comment(line);
    std::istringstream cs(counts);
    Declared d;
    if (!(cs >> d.vertices >> d.faces)) return std::string("the OFF header has no vertex and face counts");
    const std::uint64_t lines = count_data_lines(in);
    if (lines != d.vertices + d.faces) {
      return lie(declared(d, " (one line each)"), std::to_string(lines) + " data lines");
    }
    return std::nullopt;
  }
  if (lower == ".ply") {
    std::string line, format;
    Declared d;
    std::uint64_t vertex_bytes = 0;  // binary: bytes per vertex record
    std::uint64_t all_elements = 0;  // ASCII: one line each, whatever the element
    bool in_vertex = false, ended = false;
    while (std::getline(in, line)) {
      std::istringstream ls(line);
      std::string word;
      ls >> word;
      if (word == "format") ls >> format;
      else if (word == "element") {
        std::string name;
        std::uint64_t n = 0;
        ls >> name >> n;
        all_elements += n;
        in_vertex = name == "vertex";
        if (name == "vertex") d.vertices = n;
        if (name == "face") d.faces = n;
      } else if (word == "property" && in_vertex) {
        std::string type;
        ls >> type;
        for (const auto& [t, bytes] : {std::pair{"char", 1}, {"uchar", 1}, {"int8", 1}, {"uint8", 1}, {"short", 2},
                                       {"ushort", 2}, {"int16", 2}, {"uint16", 2}, {"int", 4}, {"uint", 4}, {"int32", 4},
                                       {"uint32", 4}, {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}}) {
          if (type == t) vertex_bytes += static_cast<std::uint64_t>(bytes);
        }
      } else if (word == "end_header") {
        ended = true;
        break;
      }
    }
    if (!ended) return std::string("the PLY header has no end_header line");
    if (format == "ascii") {
      const std::uint64_t lines = count_data_lines(in);
      if (lines != all_elements) {
        return lie(declared(d, "") + " (" + std::to_string(all_elements) + " elements in all, one line each)",
                   std::to_string(lines) + " data lines");
      }
      return std::nullopt;
    }
    // Binary: each face needs at least its count byte and three indices.
    const auto pos = in.tellg();
    const std::uint64_t data = pos < 0 ? 0 : file_size - static_cast<std::uint64_t>(pos);
    const long double need = static_cast<long double>(d.vertices) * static_cast<long double>(vertex_bytes) +
                             static_cast<long double>(d.faces) * 4.0L;
    if (need > static_cast<long double>(data)) {
      return lie(declared(d, ""), std::to_string(data) + " bytes of data, fewer than they take");
    }
    return std::nullopt;
  }
  if (lower == ".stl") {
    char head[84] = {};
    in.read(head, sizeof head);
    if (in.gcount() < 84) return std::nullopt;
    std::string start(head, 5);
    for (char& c : start) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::uint32_t n = 0;
    std::memcpy(&n, head + 80, 4);
    const std::uint64_t binary_size = 84 + 50 * std::uint64_t{n};
    // ASCII STL starts with "solid" (so may a binary one's free-form header:
    // then the size decides, as OpenMesh's reader does).
    if (start == "solid" && binary_size != file_size) return std::nullopt;
    if (binary_size != file_size) {
      return lie(std::to_string(n) + " triangles", std::to_string(file_size) + " bytes (a binary STL of that many takes " +
                                     std::to_string(binary_size) + ")");
    }
  }
  return std::nullopt;
}

}  // namespace

Result<ImportedMesh> import_mesh(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return input_error(path, std::filesystem::exists(path, ec) ? "not a regular file" : "mesh file not found");
  }
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl" && ext != ".OBJ" &&
      ext != ".OFF" && ext != ".PLY" && ext != ".STL") {
    return input_error(path, "unsupported mesh format '" + ext + "' (expected .obj, .off, .ply or .stl)");
  }

  if (auto lie = check_declared_counts(path, ext)) return input_error(path, *lie);
  OmMesh m;
  const ReadOutcome read = read_with_report(m, path);
  if (!read.ok) {
    return input_error(path, "OpenMesh could not read the file" +
                                 (read.report.empty() ? std::string() : ": " + read.report));
  }
  ImportedMesh out;
  const std::size_t bad_index = count_occurrences(read.report, "invalid vertex index");
  if (bad_index > 0) {
    return input_error(path, std::to_string(bad_index) +
                                 " face(s) refer to a vertex that does not exist (index out of range, "
                                 "or a vertex whose coordinates could not be parsed, such as nan/inf); "
                                 "OpenMesh dropped them, so the mesh is refused");
  }
  const std::size_t complex = count_occurrences(read.report, "complex");
  if (complex > 0) {
    out.warnings.push_back(std::to_string(complex) +
                           " non-manifold vertex/edge case(s): OpenMesh duplicated vertices to import them");
  }
  if (m.n_faces() == 0) return input_error(path, "the mesh has no faces");

  for (auto v : m.vertices()) {
    if (!finite3(m.point(v))) {
      return input_error(path, "vertex " + std::to_string(v.idx()) + " has a non-finite coordinate");
    }
  }

  m.triangulate();
  // Normals: keep the file's when every one is finite and non-zero.
  bool file_normals = read.had_normals;
  if (file_normals) {
    for (auto v : m.vertices()) {
      const auto n = m.normal(v);
      if (!finite3(n) || n.norm() < 1e-12f) {
        file_normals = false;
        out.warnings.push_back("vertex " + std::to_string(v.idx()) +
                               " has an invalid normal; all normals recomputed");
        break;
      }
    }
  }

  // Collect triangles, dropping degenerate ones (zero area, in double).
  TriangleMesh& tm = out.mesh;
  std::vector<std::uint32_t> remap(m.n_vertices(), UINT32_MAX);
  std::size_t degenerate = 0;
  std::string first_degenerate;
  for (auto f : m.faces()) {
    std::array<std::uint32_t, 3> tri{};
    std::array<OpenMesh::Vec3d, 3> p;
    int k = 0;
    for (auto v : m.fv_range(f)) {
      if (k < 3) {
        tri[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(v.idx());
        const auto q = m.point(v);
        p[static_cast<std::size_t>(k)] = OpenMesh::Vec3d(q[0], q[1], q[2]);
      }
      ++k;
    }
    if (k != 3) return make_error(ErrorCode::kInternal, path + ": triangulation left a face with " + std::to_string(k) + " vertices");
    const double area2 = ((p[1] - p[0]) % (p[2] - p[0])).norm();
    const double scale = std::max({(p[1] - p[0]).sqrnorm(), (p[2] - p[0]).sqrnorm(), (p[2] - p[1]).sqrnorm()});
    if (!(area2 > 1e-12 * scale)) {
      if (degenerate++ < 5) {
        first_degenerate += (first_degenerate.empty() ? "" : ", ") + std::to_string(f.idx());
      }
      continue;
    }
    for (auto& idx : tri) {
      if (remap[idx] == UINT32_MAX) {
        remap[idx] = static_cast<std::uint32_t>(tm.positions.size());
        const auto q = m.point(OmMesh::VertexHandle(static_cast<int>(idx)));
        tm.positions.push_back({q[0], q[1], q[2]});
      }
      idx = remap[idx];
    }
    tm.triangles.push_back(tri);
  }
  if (degenerate > 0) {
    out.warnings.push_back("dropped " + std::to_string(degenerate) +
                           " degenerate (zero-area) triangle(s), first at triangulated face " +
                           first_degenerate);
  }
  if (tm.triangles.empty()) return input_error(path, "every face is degenerate (zero area)");

  if (!file_normals) {
    m.request_face_normals();
    m.update_face_normals();
    m.update_vertex_normals();
  }
  tm.normals.resize(tm.positions.size());
  for (std::size_t old = 0; old < remap.size(); ++old) {
    if (remap[old] == UINT32_MAX) continue;
    auto n = m.normal(OmMesh::VertexHandle(static_cast<int>(old)));
    const float len = n.norm();
    if (std::isfinite(len) && len > 0) n /= len; else n = OmMesh::Normal(0, 1, 0);
    tm.normals[remap[old]] = {n[0], n[1], n[2]};
  }
  out.normals_from_file = file_normals;
  return out;
}

}  // namespace caustix::bake
