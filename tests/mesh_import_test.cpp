// Mesh import: every supported format, polygons, and clear errors. The
// corpus of real-world-shaped files is mesh_corpus_test.cpp.

#include <gtest/gtest.h>

#include <filesystem>
#include <cstring>
#include <fstream>

#include "caustix/bake/mesh_import.h"
#include "caustix/common/mesh_topology.h"
#include "hostile_meshes.h"

namespace caustix::bake {
namespace {

class MeshImport : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("caustix_mesh_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const auto p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  std::filesystem::path dir_;
};

const char* kQuadObj = "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 4 3 2\n";

TEST_F(MeshImport, ObjQuadIsTriangulatedWithComputedNormals) {
  auto m = import_mesh(write("quad.obj", kQuadObj));
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->mesh.positions.size(), 4u);
  EXPECT_EQ(m->mesh.triangles.size(), 2u);
  EXPECT_FALSE(m->normals_from_file);
  for (const auto& n : m->mesh.normals) EXPECT_NEAR(n[1], 1.0f, 1e-6f);  // 1 4 3 2 winds CCW seen from +y
}

TEST_F(MeshImport, AllFormats) {
  const std::string off = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 0 1\n0 0 1\n3 0 3 2\n3 0 2 1\n";
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n1 0 1\n0 0 1\n3 0 3 2\n3 0 2 1\n";
  const std::string stl =
      "solid t\nfacet normal 0 1 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 1 0 1\nendloop\nendfacet\n"
      "facet normal 0 1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 1\nvertex 1 0 0\nendloop\nendfacet\nendsolid t\n";
  for (const auto& [name, text] : {std::pair{"q.off", off}, std::pair{"q.ply", ply}, std::pair{"q.stl", stl}}) {
    auto m = import_mesh(write(name, text));
    ASSERT_TRUE(m.ok()) << name << ": " << m.error().message;
    EXPECT_EQ(m->mesh.triangles.size(), 2u) << name;
    EXPECT_EQ(m->mesh.positions.size(), 4u) << name;
  }
}

TEST_F(MeshImport, FileNormalsAreKept) {
  auto m = import_mesh(write("n.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nvn 0 1 0\nvn 0 1 0\nvn 0.6 0.8 0\nf 1//1 3//2 2//3\n"));
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_TRUE(m->normals_from_file);
}

TEST_F(MeshImport, MissingAndUnsupported) {
  auto m = import_mesh((dir_ / "nope.obj").string());
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error().code, ErrorCode::kInput);
  EXPECT_NE(m.error().message.find("nope.obj: mesh file not found"), std::string::npos) << m.error().message;
  m = import_mesh(write("x.fbx", "whatever"));
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("unsupported mesh format"), std::string::npos);
}

TEST_F(MeshImport, OutOfRangeIndexIsRefused) {
  auto m = import_mesh(write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n"));
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("bad.obj: line 5: corner 3 '9' refers to vertex 9; the file has 3 vertices"),
            std::string::npos)
      << m.error().message;
  m = import_mesh(write("rel.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n"));  // -3 before the first vertex
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("line 3: corner 3 '-3' refers to vertex 0"), std::string::npos) << m.error().message;
  m = import_mesh(write("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"));
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("bad.off: face 0: corner 2 is missing or not a vertex index below 3 (line 6)"), std::string::npos)
      << m.error().message;
}

TEST_F(MeshImport, NonFiniteCoordinatesAreRefused) {
  auto m = import_mesh(write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"));
  ASSERT_FALSE(m.ok());
  m = import_mesh(write("inf.off", "OFF\n3 1 0\n0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n"));
  ASSERT_FALSE(m.ok()) << "1e39 overflows float";
}

TEST_F(MeshImport, EmptyAndAllDegenerate) {
  auto m = import_mesh(write("empty.obj", "# nothing\n"));
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("no faces"), std::string::npos);
  m = import_mesh(write("line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"));
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("degenerate"), std::string::npos) << m.error().message;
}

TEST_F(MeshImport, DegenerateFacesAreDroppedWithAWarning) {
  auto m = import_mesh(write("d.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 2 0 0\nf 1 3 2\nf 1 2 4\n"));
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->mesh.triangles.size(), 1u);
  EXPECT_EQ(m->mesh.positions.size(), 3u);  // the unused vertex is compacted away
  ASSERT_EQ(m->warnings.size(), 1u);
  EXPECT_NE(m->warnings[0].find("degenerate"), std::string::npos);
}

// A header that lies about its counts, in either direction, is refused
// before a library reads the file: the readers size containers from the
// declared counts (10^9: std::bad_alloc, a crash), and would read stale
// values as faces where data is missing or silently skip what follows.
TEST_F(MeshImport, HeadersThatLieAboutTheirCountsAreRefused) {
  const std::string ply_head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  std::string stl(84, '\0');
  const std::uint32_t claimed = 1000000000;  // 10^9 triangles, one present
  std::memcpy(stl.data() + 80, &claimed, 4);
  stl += std::string(50, '\0');
  std::string binary_ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  binary_ply += std::string(3 * 12 + 13, '\0');
  const std::vector<std::pair<std::string, std::string>> files{
      {"more_vertices.off", "OFF\n10 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"more_faces.off", "OFF\n3 5 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"fewer_faces.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n"},
      {"a_billion.off", "OFF\n1000000000 1000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"more_faces.ply", ply_head + "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"binary.ply", binary_ply},
      {"binary.stl", stl}};
  for (const auto& [name, text] : files) {
    auto m = import_mesh(write(name, text));
    ASSERT_FALSE(m.ok()) << name;
    EXPECT_EQ(m.error().code, ErrorCode::kInput) << name;
    EXPECT_NE(m.error().message.find(name + ": the header declares"), std::string::npos) << m.error().message;
  }
  // Honest headers still read, blank lines included.
  auto m = import_mesh(write("honest.off", "OFF\n3 1 0\n\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  ASSERT_TRUE(m.ok()) << m.error().message;
}

// Non-manifold edges, duplicate faces and inconsistent winding are legal in
// a receiver (it is drawn two-sided unless closed): imported with a
// warning, nothing dropped.
TEST_F(MeshImport, NonManifoldDuplicateAndMiswoundFacesImportWithWarnings) {
  for (auto flaw : {test::CubeFlaw::kFin, test::CubeFlaw::kDuplicateFace, test::CubeFlaw::kFlippedFace}) {
    const TriangleMesh cube = test::unit_cube(flaw);
    auto m = import_mesh(write("flawed.obj", test::to_obj(cube)));
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->mesh.triangles.size(), cube.triangles.size());
    ASSERT_FALSE(m->warnings.empty());
    EXPECT_NE(m->warnings[0].find("non-manifold"), std::string::npos) << m->warnings[0];
  }
}

TEST(EdgeCensus, ClassifiesEveryFlaw) {
  using test::CubeFlaw;
  const EdgeCensus ok = census_edges(test::unit_cube());
  EXPECT_TRUE(ok.closed());
  EXPECT_NEAR(ok.signed_volume, 1.0, 1e-12);
  const EdgeCensus inside_out = census_edges(test::unit_cube(CubeFlaw::kInsideOut));
  EXPECT_TRUE(inside_out.closed());  // closed, but wound inward: the volume says so
  EXPECT_NEAR(inside_out.signed_volume, -1.0, 1e-12);
  const EdgeCensus flipped = census_edges(test::unit_cube(CubeFlaw::kFlippedFace));
  EXPECT_EQ(flipped.inconsistent.size(), 3u);
  EXPECT_TRUE(flipped.open.empty() && flipped.non_manifold.empty());
  const EdgeCensus hole = census_edges(test::unit_cube(CubeFlaw::kHole));
  EXPECT_EQ(hole.open.size(), 3u);
  const EdgeCensus fin = census_edges(test::unit_cube(CubeFlaw::kFin));
  EXPECT_EQ(fin.open.size(), 2u);
  EXPECT_EQ(fin.non_manifold.size(), 1u);
  EXPECT_EQ(census_edges(test::unit_cube(CubeFlaw::kDuplicateFace)).non_manifold.size(), 3u);
  // Split seams (a vertex per face corner, as box.obj has) weld by position.
  TriangleMesh split = test::unit_cube();
  TriangleMesh seams;
  for (const auto& t : split.triangles) {
    std::array<std::uint32_t, 3> u{};
    for (std::size_t k = 0; k < 3; ++k) {
      u[k] = static_cast<std::uint32_t>(seams.positions.size());
      seams.positions.push_back(split.positions[t[k]]);
    }
    seams.triangles.push_back(u);
  }
  EXPECT_TRUE(census_edges(seams).closed());
  // Two cubes sharing an edge bound a solid: each directed edge has an opposite.
  TriangleMesh two = test::unit_cube();
  for (const auto& p : test::unit_cube().positions) two.positions.push_back({p[0] + 1, p[1] + 1, p[2]});
  for (const auto& t : test::unit_cube().triangles) two.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  const EdgeCensus pair = census_edges(two);
  EXPECT_TRUE(pair.closed());
  EXPECT_NEAR(pair.signed_volume, 2.0, 1e-12);
}

}  // namespace
}  // namespace caustix::bake

namespace caustix::bake {
namespace {

double area_of(const TriangleMesh& m) {
  double a = 0;
  for (const auto& t : m.triangles) {
    const auto& p = m.positions[t[0]];
    const auto& q = m.positions[t[1]];
    const auto& r = m.positions[t[2]];
    const double u[3] = {double{q[0]} - p[0], double{q[1]} - p[1], double{q[2]} - p[2]};
    const double v[3] = {double{r[0]} - p[0], double{r[1]} - p[1], double{r[2]} - p[2]};
    // +y component of u x v: the polygons below lie in y = 0, facing +y
    a += 0.5 * (u[2] * v[0] - u[0] * v[2]);
  }
  return a;
}

// A comb (an outline with deep notches) as one OBJ face, and a pentagon
// with a corner in the middle of an edge (a T-junction): triangulated
// inside the outline, every triangle facing like the polygon, covering its
// area exactly. OpenMesh's fan covered the comb's notches too (area 13.5
// instead of 9) and folded triangles back.
TEST_F(MeshImport, NonConvexPolygonsAreTriangulatedInsideTheirOutline) {
  // Comb: base [0,9] x [0,1] with teeth [2k, 2k+1] x [1,3], k = 0..4 (area 9 + 10 = ... )
  std::string obj;
  std::vector<std::pair<int, int>> outline{{0, 0}, {9, 0}};
  for (int k = 4; k >= 0; --k) {
    outline.push_back({2 * k + 1, 1});
    outline.push_back({2 * k + 1, 3});
    outline.push_back({2 * k, 3});
    if (k > 0) outline.push_back({2 * k, 1});
  }
  // Counter-clockwise in (x, z) faces -y; reverse to face +y.
  for (auto it = outline.rbegin(); it != outline.rend(); ++it) {
    obj += "v " + std::to_string(it->first) + " 0 " + std::to_string(it->second) + "\n";
  }
  obj += "f";
  for (std::size_t i = 1; i <= outline.size(); ++i) obj += " " + std::to_string(i);
  obj += "\n";
  auto m = import_mesh(write("comb.obj", obj));
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->mesh.triangles.size(), outline.size() - 2);
  EXPECT_NEAR(area_of(m->mesh), 9.0 + 5 * 2.0, 1e-5);  // base 9 x 1, five teeth 1 x 2
  EXPECT_TRUE(m->warnings.empty());
  for (const auto& n : m->mesh.normals) EXPECT_NEAR(n[1], 1.0f, 1e-6f);

  m = import_mesh(write("t_junction.off", "OFF\n5 1 0\n0 0 0\n0 0 1\n1 0 1\n1 0 0\n0.5 0 0\n5 0 1 2 3 4\n"));
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->mesh.triangles.size(), 3u);
  EXPECT_NEAR(area_of(m->mesh), 1.0, 1e-6);
  EXPECT_TRUE(m->warnings.empty()) << m->warnings.front();  // no zero-area triangle from the collinear corner
}

// A quad whose outline crosses itself (a bow tie, as scans produce) has no
// inside to triangulate: it becomes a fan, and the import says so.
TEST_F(MeshImport, SelfCrossingPolygonIsAFanWithAWarning) {
  auto m = import_mesh(write("bowtie.obj", "v 0 0 0\nv 1 0 1\nv 1 0 0\nv 0 0 1\nf 1 2 3 4\n"));
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->mesh.triangles.size(), 2u);
  ASSERT_FALSE(m->warnings.empty());
  EXPECT_NE(m->warnings[0].find("crosses or touches itself, triangulated as a fan from the first corner, first at face 0"),
            std::string::npos)
      << m->warnings[0];
}

// An ASCII PLY is walked value by value before CGAL reads it: a value
// that is not a number, a list longer than the data, and data beyond the
// declared elements are refused with the element, its index and the line.
TEST_F(MeshImport, PlyDataThatDoesNotMatchItsHeaderIsRefusedWithThePlace) {
  const std::string head =
      "ply\nformat ascii 1.0\ncomment x\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {head + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "'vertex' 1 (line 12): 'zero' is not a number"},
      {head + "0 0 0\n1 0 0\n0 1 0\n4000000 0 1 2\n", "the data ends inside list 'vertex_indices' of 'face' 0 (line 14)"},
      {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n", "more values follow their data (line 15)"},
      {head + "0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", "'face' 0 (line 14): list 'vertex_indices' has length -3"}};
  for (const auto& [text, message] : cases) {
    auto m = import_mesh(write("bad.ply", text));
    ASSERT_FALSE(m.ok()) << message;
    EXPECT_NE(m.error().message.find(message), std::string::npos) << m.error().message;
  }
}

}  // namespace
}  // namespace caustix::bake
