// Mesh import through OpenMesh: every supported format, and clear errors.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "caustix/bake/mesh_import.h"

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
  EXPECT_NE(m.error().message.find("1 face(s) refer to a vertex that does not exist"), std::string::npos)
      << m.error().message;
  m = import_mesh(write("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"));
  ASSERT_FALSE(m.ok());
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

}  // namespace
}  // namespace caustix::bake
