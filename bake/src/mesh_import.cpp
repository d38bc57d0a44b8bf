#include "caustix/bake/mesh_import.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
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
  out.ok = OpenMesh::IO::read_mesh(m, path, opt);
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
