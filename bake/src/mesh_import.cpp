#include "caustix/bake/mesh_import.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <filesystem>
#include <unordered_map>

#include "caustix/common/mesh_topology.h"
#include "mesh_soup.h"

namespace caustix::bake {
namespace {

using P3 = std::array<double, 3>;

Error input_error(const std::string& path, const std::string& msg) {
  return make_error(ErrorCode::kInput, path + ": " + msg);
}

P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
P3 cross(const P3& a, const P3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
bool finite3(const P3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

std::optional<MeshFormat> format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return MeshFormat::kObj;
  if (ext == ".off") return MeshFormat::kOff;
  if (ext == ".ply") return MeshFormat::kPly;
  if (ext == ".stl") return MeshFormat::kStl;
  return std::nullopt;
}

// "first at face 3, 17, 40" for the first few of a list of face indices.
struct FaceTally {
  std::size_t count = 0;
  std::string first;
  void add(std::size_t face) {
    if (count++ < 5) first += (first.empty() ? "" : ", ") + std::to_string(face);
  }
  std::string where() const { return "first at face " + first + (count > 5 ? ", ..." : ""); }
};

}  // namespace

std::size_t snap_close_points(std::vector<P3>& points) {
  if (points.empty()) return 0;
  P3 lo = points.front(), hi = lo;
  for (const P3& p : points) {
    for (std::size_t k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  const double tol = kSnapTolerance * std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (!(tol > 0) || !std::isfinite(tol)) return 0;
  // Cells of side tol: a point's neighbours within tol lie in the 27 cells
  // around its own. Only points that stayed put are candidates, so moves
  // never chain.
  using Cell = std::array<std::int64_t, 3>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const {
      return std::hash<std::int64_t>()(c[0] * 73856093 ^ c[1] * 19349663 ^ c[2] * 83492791);
    }
  };
  std::unordered_map<Cell, std::vector<std::uint32_t>, CellHash> grid;
  grid.reserve(points.size());
  std::size_t moved = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    P3& p = points[i];
    Cell c{};
    for (std::size_t k = 0; k < 3; ++k) c[k] = static_cast<std::int64_t>(std::floor((p[k] - lo[k]) / tol));
    std::uint32_t best = UINT32_MAX;
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (std::uint32_t j : it->second) {
            const P3 d = sub(points[j], p);
            if (j < best && dot(d, d) <= tol * tol) best = j;
          }
        }
      }
    }
    if (best == UINT32_MAX) {
      grid[c].push_back(static_cast<std::uint32_t>(i));
    } else if (points[best] != p) {
      p = points[best];
      ++moved;
    }
  }
  return moved;
}

Result<ImportedMesh> import_mesh(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return input_error(path, std::filesystem::exists(path, ec) ? "not a regular file" : "mesh file not found");
  }
  const auto format = format_of(path);
  if (!format) {
    return input_error(path, "unsupported mesh format '" + std::filesystem::path(path).extension().string() +
                                 "' (expected .obj, .off, .ply or .stl)");
  }
  auto read = *format == MeshFormat::kObj   ? read_obj(path)
              : *format == MeshFormat::kOff ? read_off(path)
              : *format == MeshFormat::kPly ? read_ply(path)
                                            : read_stl(path);
  if (!read) return input_error(path, read.error().message);
  auto out = mesh_from_soup(std::move(*read));
  if (!out) return input_error(path, out.error().message);
  return out;
}

Result<ImportedMesh> mesh_from_soup(PolygonSoup&& soup) {
  const auto refuse = [](const std::string& msg) { return make_error(ErrorCode::kInput, msg); };
  ImportedMesh out;
  out.warnings = std::move(soup.warnings);

  if (soup.polygon_count() == 0) {
    return refuse("the mesh has no faces" +
                                 (soup.points.empty() ? std::string()
                                                      : " (" + std::to_string(soup.points.size()) +
                                                            " points: a point cloud is not a surface)"));
  }
  for (std::size_t i = 0; i < soup.points.size(); ++i) {
    const P3& p = soup.points[i];
    if (!finite3(p)) return refuse("vertex " + std::to_string(i) + " has a non-finite coordinate");
    if (std::max({std::fabs(p[0]), std::fabs(p[1]), std::fabs(p[2])}) > FLT_MAX) {
      return refuse("vertex " + std::to_string(i) + " has a coordinate beyond the float range");
    }
  }
  snap_close_points(soup.points);
  const auto n_points = static_cast<std::uint64_t>(soup.points.size());
  for (std::size_t f = 0; f < soup.polygon_count(); ++f) {
    for (std::uint32_t k = soup.offsets[f]; k < soup.offsets[f + 1]; ++k) {
      if (soup.corners[k] >= n_points) {
        return refuse("face " + std::to_string(f) + " refers to vertex " + std::to_string(soup.corners[k]) +
                                     ", a vertex that does not exist (the file has " + std::to_string(n_points) +
                                     " vertices); refusing the mesh rather than dropping the face");
      }
    }
  }

  // Triangles of every polygon, in the file's order. Repeated corners in a
  // row (a quad with a collapsed edge) are one corner; what is left with
  // fewer than three corners or no area is dropped and reported.
  TriangleMesh& tm = out.mesh;
  std::vector<std::uint32_t> remap(soup.points.size(), UINT32_MAX);
  std::vector<std::array<std::uint32_t, 3>> tris;  // point indices
  FaceTally degenerate, crossing;
  std::vector<std::uint32_t> poly;
  std::vector<P3> corners;
  for (std::size_t f = 0; f < soup.polygon_count(); ++f) {
    poly.clear();
    for (std::uint32_t k = soup.offsets[f]; k < soup.offsets[f + 1]; ++k) {
      if (poly.empty() || poly.back() != soup.corners[k]) poly.push_back(soup.corners[k]);
    }
    while (poly.size() > 1 && poly.back() == poly.front()) poly.pop_back();
    const std::size_t before = tris.size();
    if (poly.size() == 3) {
      tris.push_back({poly[0], poly[1], poly[2]});
    } else if (poly.size() > 3) {
      corners.clear();
      for (std::uint32_t i : poly) corners.push_back(soup.points[i]);
      const PolygonTriangles pt = triangulate_polygon(corners);
      if (!pt.simple) crossing.add(f);
      for (const auto& t : pt.triangles) tris.push_back({poly[t[0]], poly[t[1]], poly[t[2]]});
    }
    // Zero area, in double: collinear corners, or a triangle of a fan.
    std::size_t kept = before;
    for (std::size_t t = before; t < tris.size(); ++t) {
      const P3& a = soup.points[tris[t][0]];
      const P3 e1 = sub(soup.points[tris[t][1]], a), e2 = sub(soup.points[tris[t][2]], a);
      const P3 e3 = sub(soup.points[tris[t][2]], soup.points[tris[t][1]]);
      const P3 n = cross(e1, e2);
      const double scale = std::max({dot(e1, e1), dot(e2, e2), dot(e3, e3)});
      if (std::sqrt(dot(n, n)) > 1e-12 * scale) tris[kept++] = tris[t];
    }
    if (kept == before) degenerate.add(f);
    tris.resize(kept);
  }
  if (tris.empty()) return refuse("every face is degenerate (fewer than three corners, or zero area)");
  if (degenerate.count > 0) {
    out.warnings.push_back("dropped " + std::to_string(degenerate.count) +
                           " degenerate face(s) (fewer than three distinct corners, or zero area), " + degenerate.where());
  }
  if (crossing.count > 0) {
    out.warnings.push_back(std::to_string(crossing.count) +
                           " polygon(s) whose outline crosses or touches itself, triangulated as a fan from the "
                           "first corner, " + crossing.where());
  }

  // Vertices in order of first use (unused ones dropped), as floats.
  for (auto& t : tris) {
    for (std::uint32_t& i : t) {
      if (remap[i] == UINT32_MAX) {
        remap[i] = static_cast<std::uint32_t>(tm.positions.size());
        const P3& p = soup.points[i];
        tm.positions.push_back({static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
        if (soup.uvs.size() == soup.points.size()) tm.uvs.push_back(soup.uvs[i]);
        if (soup.colors.size() == soup.points.size()) tm.colors.push_back(soup.colors[i]);
      }
    }
    tm.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
  }

  // Normals: the file's when every used vertex has a finite, non-zero one;
  // otherwise the normalised sum of the unit normals of its triangles.
  std::vector<P3> normals(tm.positions.size(), P3{0, 0, 0});
  bool from_file = soup.normals.size() == soup.points.size();
  for (std::size_t old = 0; from_file && old < remap.size(); ++old) {
    if (remap[old] == UINT32_MAX) continue;
    const P3& n = soup.normals[old];
    if (!finite3(n) || dot(n, n) < 1e-24) {
      out.warnings.push_back("vertex " + std::to_string(old) + " has an invalid normal; all normals recomputed");
      from_file = false;
    } else {
      normals[remap[old]] = n;
    }
  }
  if (!from_file) {
    std::fill(normals.begin(), normals.end(), P3{0, 0, 0});
    for (const auto& t : tris) {
      P3 n = cross(sub(soup.points[t[1]], soup.points[t[0]]), sub(soup.points[t[2]], soup.points[t[0]]));
      const double len = std::sqrt(dot(n, n));
      for (double& c : n) c /= len;
      for (std::uint32_t i : t) {
        for (std::size_t k = 0; k < 3; ++k) normals[remap[i]][k] += n[k];
      }
    }
  }
  tm.normals.reserve(normals.size());
  for (const P3& n : normals) {
    const double len = std::sqrt(dot(n, n));
    if (std::isfinite(len) && len > 0) {
      tm.normals.push_back({static_cast<float>(n[0] / len), static_cast<float>(n[1] / len), static_cast<float>(n[2] / len)});
    } else {
      tm.normals.push_back({0, 1, 0});  // opposite triangles cancelled out
    }
  }
  out.normals_from_file = from_file;

  // Legal in a receiver (drawn two-sided), refused in a transparent object
  // (bake.cpp); said here so that neither comes as a surprise.
  const EdgeCensus census = census_edges(tm);
  if (!census.non_manifold.empty() || !census.inconsistent.empty()) {
    out.warnings.push_back("not a manifold, consistently wound surface: " + std::to_string(census.non_manifold.size()) +
                           " non-manifold edge(s) (more than two triangles), " +
                           std::to_string(census.inconsistent.size()) +
                           " inconsistently wound edge(s); fine for a receiver, refused for a transparent object");
  }
  return out;
}

}  // namespace caustix::bake
