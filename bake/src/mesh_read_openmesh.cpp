// OBJ through OpenMesh's reader (mesh_soup.h says why), into a polygon soup:
// OpenMesh's readers talk to an importer interface, and this one records
// what the file says instead of building a halfedge mesh (which rejects
// faces with repeated corners and splits non-manifold vertices).

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include <mutex>
#include <new>
#include <sstream>

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

// OpenMesh reports what it could not read only on its omerr stream (and
// chatter such as a missing material file on omlog): process-wide streams,
// hence the lock. For one read both write straight into a string: their
// stream buffers are swapped, not their targets -- OpenMesh 9's
// mostream::disconnect() forgets a target without deleting it (a leak per
// read that LeakSanitizer reports).
std::mutex g_omerr_mutex;

}  // namespace

Result<PolygonSoup> read_obj(const std::string& path) {
  PolygonSoup soup;
  SoupImporter importer(soup);
  std::lock_guard<std::mutex> lock(g_omerr_mutex);
  std::ostringstream captured, chatter;
  std::streambuf* const err = omerr().rdbuf(captured.rdbuf());
  std::streambuf* const log = omlog().rdbuf(chatter.rdbuf());
  IO::Options options = IO::Options::VertexNormal;
  bool ok = false;
  try {
    ok = IO::IOManager().read(path, importer, options);
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
  return soup;
}

}  // namespace caustix::bake
