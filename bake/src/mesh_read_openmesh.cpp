// OBJ through OpenMesh's reader (mesh_soup.h says why), into a polygon soup:
// OpenMesh's readers talk to an importer interface, and this one records
// what the file says instead of building a halfedge mesh (which rejects
// faces with repeated corners and splits non-manifold vertices).
//
// OpenMesh 9's OBJ reader trusts the file's face lines: a corner without a
// vertex index ("f /1") stops the process on an assertion (Debian builds it
// with assertions on; found by fuzz_mesh_import), an unreadable index is
// used uninitialised, a relative index is added in int without a bound, and
// a "v" line it cannot read is skipped while the relative indices still
// count it; and it does not join a line ending in a backslash with the
// next (OBJ's line continuation). So check_obj() reads the lines the way
// OpenMesh splits them and refuses, naming the line, what it would misread;
// a valid file passes untouched and OpenMesh reads it (its continued lines
// joined first).

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <mutex>
#include <new>
#include <optional>
#include <sstream>
#include <string_view>

#include "mesh_soup.h"

namespace caustix::bake {
namespace {

using namespace OpenMesh;

class SoupImporter final : public IO::BaseImporter {
 public:
  explicit SoupImporter(PolygonSoup& soup) : soup_(soup) {}

  VertexHandle add_vertex(const Vec3f& p) override { return add_vertex(Vec3d(p)); }
  VertexHandle add_vertex(const Vec3d& p) override {
    soup_.points.push_back({p[0], p[1], p[2]});
    return VertexHandle(static_cast<int>(soup_.points.size() - 1));
  }
  VertexHandle add_vertex() override { return add_vertex(Vec3d(0, 0, 0)); }
  FaceHandle add_face(const VHandles& corners) override {
    // Handles as the file gave them; out-of-range ones (negative too) are
    // range-checked by the importer, which names the face.
    for (const VertexHandle& v : corners) soup_.corners.push_back(static_cast<std::uint32_t>(v.idx()));
    soup_.add_polygon_end();
    return FaceHandle(static_cast<int>(soup_.polygon_count() - 1));
  }
  void set_normal(VertexHandle v, const Vec3f& n) override { set_normal(v, Vec3d(n)); }
  void set_normal(VertexHandle v, const Vec3d& n) override {
    if (v.idx() < 0 || static_cast<std::size_t>(v.idx()) >= soup_.points.size()) return;
    if (normals_.size() < soup_.points.size()) normals_.resize(soup_.points.size(), {0, 0, 0});
    normals_[static_cast<std::size_t>(v.idx())] = {n[0], n[1], n[2]};
  }
  void set_point(VertexHandle v, const Vec3f& p) override {
    if (v.idx() >= 0 && static_cast<std::size_t>(v.idx()) < soup_.points.size()) {
      soup_.points[static_cast<std::size_t>(v.idx())] = {p[0], p[1], p[2]};
    }
  }
  std::size_t n_vertices() const override { return soup_.points.size(); }
  std::size_t n_faces() const override { return soup_.polygon_count(); }
  std::size_t n_edges() const override { return 0; }

  // Normals, once the file has given every point one (a corner's "vn"
  // reference sets its vertex's normal, as OpenMesh's own mesh does).
  void finish_normals() {
    if (!normals_.empty()) {
      normals_.resize(soup_.points.size(), {0, 0, 0});
      soup_.normals = std::move(normals_);
    }
  }

  // What OBJ files also carry and caustix does not use: accepted, dropped.
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_status(VertexHandle, const Attributes::StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const Attributes::StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const Attributes::StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  PolygonSoup& soup_;
  std::vector<std::array<double, 3>> normals_;
};

// The next white-space separated token (as a stream's >> reads it).
std::string_view next_token(std::string_view& s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  std::size_t end = 0;
  while (end < s.size() && !std::isspace(static_cast<unsigned char>(s[end]))) ++end;
  const std::string_view token = s.substr(0, end);
  s.remove_prefix(end);
  return token;
}

// An OBJ index: [+-]digits, at most 9 of them (so OpenMesh's int arithmetic
// on it cannot overflow).
std::optional<long> obj_index(std::string_view s) {
  std::string_view digits = s;
  if (!digits.empty() && (digits[0] == '+' || digits[0] == '-')) digits.remove_prefix(1);
  if (digits.empty() || digits.size() > 9) return std::nullopt;
  long value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  return s[0] == '-' ? -value : value;
}

// Calls line(text, number) for each logical line of an OBJ file: a line
// that ends in a backslash goes on in the next (the format's continuation,
// which OpenMesh does not know: it dropped the corners after one). Returns
// whether any line was continued; `in` is read to its end.
template <typename Line>
bool for_each_line(std::istream& in, Line&& line) {
  bool continued = false;
  std::string text;
  std::size_t number = 0, first = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++number;
    if (text.empty()) first = number;
    const std::size_t last = raw.find_last_not_of(" \t\r");
    const bool comment = text.empty() && raw.find_first_not_of(" \t") < raw.size() &&
                         raw[raw.find_first_not_of(" \t")] == '#';
    if (last != std::string::npos && raw[last] == '\\' && !comment) {
      text.append(raw, 0, last).push_back(' ');
      continued = true;
      continue;
    }
    text += raw;
    line(std::string_view(text), first);
    text.clear();
  }
  if (!text.empty()) line(std::string_view(text), first);
  return continued;
}

// What OpenMesh would misread (see the top of this file), as "line L: ...";
// otherwise the number of face lines that give fewer than three distinct
// vertices, which OpenMesh skips (the caller warns), and whether lines are
// continued (then OpenMesh reads the joined lines).
struct ObjCheck {
  std::optional<std::string> error;
  std::size_t short_faces = 0;
  std::size_t first_short_line = 0;
  bool continued = false;
};

// One corner of a face line: v, v/vt, v//vn or v/vt/vn, with `before`
// vertices read so far (a relative index counts back from there; an
// absolute one may refer forward, so the caller checks it at the end).
// Texture and normal indices need only be readable: OpenMesh range-checks
// those itself, and a vertex left without a normal gets a computed one.
std::optional<std::string> check_corner(std::string_view token, long& vertex, long before) {
  std::array<std::string_view, 3> part{};
  for (std::size_t n = 0;; ++n) {
    if (n == 3) return std::string("has more than v/vt/vn");
    const std::size_t slash = token.find('/');
    part[n] = token.substr(0, slash);
    if (slash == std::string_view::npos) break;
    token.remove_prefix(slash + 1);
  }
  const auto v = obj_index(part[0]);
  if (!v) return std::string("has no vertex index (OBJ corners are v, v/vt, v//vn or v/vt/vn; indices count from 1)");
  vertex = *v > 0 ? *v : before + *v + 1;
  if (vertex < 1) {
    return "refers to vertex " + std::to_string(vertex) + "; " + std::to_string(before) +
           " vertices precede it (counted from 1)";
  }
  if (!part[1].empty() && !obj_index(part[1])) return std::string("has an unreadable texture index");
  if (!part[2].empty() && !obj_index(part[2])) return std::string("has an unreadable normal index");
  return std::nullopt;
}

// One pass over the file; the corner with the largest absolute vertex
// index is checked against the vertex count at the end.
ObjCheck check_obj(const std::string& path) {
  ObjCheck out;
  std::ifstream in(path, std::ios::binary);
  long positions = 0;
  long largest = 0;
  std::string largest_at;  // "line L: corner C 'token'"
  const auto fail = [&](std::size_t line_no, const std::string& what) {
    if (!out.error) out.error = "line " + std::to_string(line_no) + ": " + what;
  };
  out.continued = for_each_line(in, [&](std::string_view line, std::size_t line_no) {
    // OpenMesh trims " \t\r\n" and skips comments and lines that still
    // start with white space.
    line.remove_prefix(std::min(line.size(), line.find_first_not_of(" \t\r\n")));
    line = line.substr(0, line.find_last_not_of(" \t\r\n") + 1);
    if (out.error || line.empty() || line[0] == '#' || std::isspace(static_cast<unsigned char>(line[0]))) return;
    const std::string_view key = next_token(line);
    if (key == "v") {
      for (int axis = 0; axis < 3; ++axis) {
        // As OpenMesh's stream extraction reads a float: an optional sign,
        // no hex; a magnitude above FLT_MAX fails it, an underflow does
        // not (from_chars on a double to tell the two apart).
        const std::string_view t = next_token(line);
        if (t.empty()) return fail(line_no, "vertex " + std::to_string(positions + 1) + " has fewer than 3 coordinates");
        const std::string_view number = t.substr(t[0] == '+' ? 1 : 0);
        double value = 0;
        const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), value);
        if (ec != std::errc() || end != number.data() + number.size() || !std::isfinite(value) ||
            std::fabs(value) > std::numeric_limits<float>::max()) {
          return fail(line_no, "vertex " + std::to_string(positions + 1) + ": '" + std::string(t) +
                                   "' is not a coordinate (a vertex is 'v x y z', finite single-precision numbers)");
        }
      }
      ++positions;
    } else if (key == "f") {
      std::vector<long> vertices;
      for (std::string_view token = next_token(line); !token.empty(); token = next_token(line)) {
        const auto at = [&] { return "corner " + std::to_string(vertices.size() + 1) + " '" + std::string(token) + "'"; };
        long vertex = 0;
        if (auto bad = check_corner(token, vertex, positions)) return fail(line_no, at() + " " + *bad);
        if (vertex > largest) {
          largest = vertex;
          if (largest > positions) largest_at = "line " + std::to_string(line_no) + ": " + at();
        }
        vertices.push_back(vertex);
      }
      std::sort(vertices.begin(), vertices.end());
      const auto distinct = std::unique(vertices.begin(), vertices.end()) - vertices.begin();
      if (distinct < 3 && out.short_faces++ == 0) out.first_short_line = line_no;
    }
  });
  if (in.bad()) out.error = "cannot read the file";
  if (!out.error && largest > positions) {
    out.error = largest_at + " refers to vertex " + std::to_string(largest) + "; the file has " +
                std::to_string(positions) + " vertices (counted from 1)";
  }
  return out;
}

// OpenMesh reports what it could not read only on its omerr stream (and
// chatter such as a missing material file on omlog): process-wide streams,
// hence the lock. For one read both write straight into a string: their
// stream buffers are swapped, not their targets -- OpenMesh 9's
// mostream::disconnect() forgets a target without deleting it (a leak per
// read that LeakSanitizer reports).
std::mutex g_omerr_mutex;

}  // namespace

Result<PolygonSoup> read_obj(const std::string& path) {
  const ObjCheck check = check_obj(path);
  if (check.error) return make_error(ErrorCode::kInput, *check.error);
  PolygonSoup soup;
  SoupImporter importer(soup);
  std::lock_guard<std::mutex> lock(g_omerr_mutex);
  std::ostringstream captured, chatter;
  std::streambuf* const err = omerr().rdbuf(captured.rdbuf());
  std::streambuf* const log = omlog().rdbuf(chatter.rdbuf());
  IO::Options options = IO::Options::VertexNormal;
  bool ok = false;
  try {
    if (check.continued) {
      std::ifstream in(path, std::ios::binary);
      std::string joined;
      for_each_line(in, [&](std::string_view line, std::size_t) { joined.append(line).push_back('\n'); });
      std::istringstream text(joined);
      ok = IO::IOManager().read(text, "obj", importer, options);
    } else {
      ok = IO::IOManager().read(path, importer, options);
    }
  } catch (const std::bad_alloc&) {
    captured << "out of memory";
  }
  omerr().rdbuf(err);
  omlog().rdbuf(log);
  if (!ok) {
    std::string report = captured.str();
    while (!report.empty() && std::isspace(static_cast<unsigned char>(report.back()))) report.pop_back();
    return make_error(ErrorCode::kInput,
                      "OpenMesh's OBJ reader could not read the file" + (report.empty() ? "" : ": " + report));
  }
  if (options.vertex_has_normal()) importer.finish_normals();
  if (check.short_faces > 0) {
    soup.warnings.push_back("skipped " + std::to_string(check.short_faces) +
                            " face(s) with fewer than 3 distinct vertices (first at line " +
                            std::to_string(check.first_short_line) + ")");
  }
  return soup;
}

}  // namespace caustix::bake
