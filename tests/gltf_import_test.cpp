// glTF 2.0 input (docs/scene-format.md "glTF scenes"): files the
// test writes as an exporter would (tests/gltf_fixture.h) -- embedded
// buffers, .glb, external buffers, node hierarchies, every material and
// light extension caustix reads, Draco and quantised attributes -- and the
// malformed ones, refused with the JSON pointer of the problem.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "caustix/bake/bake.h"
#include "caustix/bake/gltf_import.h"
#include "caustix/bake/mesh_compress.h"
#include "caustix/bake/scene_json.h"
#include "caustix/formats/container.h"
#include "caustix/formats/mesh_decode.h"
#include "caustix/formats/scene.h"
#include "gltf_fixture.h"

namespace caustix {
namespace {

namespace fs = std::filesystem;
using test::GltfBuilder;
using test::SplitCube;
using nlohmann::json;

class Gltf : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("caustix_gltf_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;

  // A floor quad, a glass cube above it, a sun and a camera: the parts of a
  // caustics scene, each through its glTF extension.
  static GltfBuilder pool_scene() {
    GltfBuilder g;
    g.use_extension("KHR_materials_transmission");
    g.use_extension("KHR_materials_ior");
    g.use_extension("KHR_materials_volume");
    g.use_extension("KHR_lights_punctual");
    const int floor_mat = g.material({{"name", "tiles"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.6, 0.7, 1.0}}, {"metallicFactor", 0.0}}}});
    const int glass_mat = g.material(
        {{"name", "glass"},
         {"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
         {"extensions",
          {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
           {"KHR_materials_ior", {{"ior", 1.45}}},
           {"KHR_materials_volume", {{"thicknessFactor", 1.0}, {"attenuationDistance", 2.0}, {"attenuationColor", {0.5, 0.25, 1.0}}}}}}});
    const int quad_pos = g.positions({{-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}});
    const int quad_idx = g.indices({0, 2, 1, 0, 3, 2});  // up-facing
    const int floor_mesh = g.mesh(json::array({{{"attributes", {{"POSITION", quad_pos}}}, {"indices", quad_idx}, {"material", floor_mat}}}), "floor");
    const SplitCube cube;
    const int cp = g.positions(cube.positions), cn = g.normals(cube.normals), ci = g.indices(cube.indices);
    const int cube_mesh = g.mesh(json::array({{{"attributes", {{"POSITION", cp}, {"NORMAL", cn}}}, {"indices", ci}, {"material", glass_mat}}}), "cube");
    g.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "directional"}, {"name", "sun"}, {"intensity", 683.0}, {"color", {1.0, 0.9, 0.8}}}});
    g.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}, {"zfar", 50.0}}}}});
    const int n_floor = g.node({{"name", "Floor"}, {"mesh", floor_mesh}});
    const int n_cube = g.node({{"name", "Glass"}, {"mesh", cube_mesh}, {"translation", {0.0, 1.0, 0.0}}});
    // The sun points down: a -90 degree turn about x takes -z to -y.
    const double s = std::sqrt(0.5);
    const int n_sun = g.node({{"name", "SunNode"}, {"rotation", {-s, 0.0, 0.0, s}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    const int n_cam = g.node({{"name", "Cam"}, {"camera", 0}, {"translation", {0.0, 2.0, 6.0}}});
    g.scene({n_floor, n_cube, n_sun, n_cam});
    return g;
  }

  std::string error_of(const GltfBuilder& g, const std::string& name = "bad.glb") {
    const fs::path p = dir_ / name;
    if (name.ends_with(".glb")) g.write_glb(p);
    else GltfBuilder(g).write_embedded(p);
    auto doc = bake::load_scene(p.string());
    EXPECT_FALSE(doc.ok());
    if (doc.ok()) return "";
    EXPECT_EQ(doc.error().code, ErrorCode::kInput);
    EXPECT_NE(doc.error().message.find(p.string()), std::string::npos) << doc.error().message;
    return doc.error().message;
  }
};

const Object* find(const SceneDesc& s, const std::string& name) {
  for (const Object& o : s.objects) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

std::array<double, 3> apply(const Mat4f& m, const std::array<double, 3>& p) {
  std::array<double, 3> r{};
  for (std::size_t k = 0; k < 3; ++k) r[k] = m[k] * p[0] + m[4 + k] * p[1] + m[8 + k] * p[2] + m[12 + k];
  return r;
}

TEST_F(Gltf, EmbeddedSceneMapsMaterialsLightsAndCamera) {
  const fs::path path = dir_ / "pool.gltf";
  pool_scene().write_embedded(path);
  auto doc = bake::load_scene(path.string());
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  const SceneDesc& s = doc->scene;
  ASSERT_EQ(s.objects.size(), 2u);
  const Object* floor = find(s, "Floor");
  const Object* glass = find(s, "Glass");
  ASSERT_TRUE(floor && glass);
  EXPECT_EQ(floor->role, Role::kReceiver);
  EXPECT_FLOAT_EQ(floor->material.albedo[1], 0.6f);
  EXPECT_EQ(glass->role, Role::kTransparent);
  EXPECT_FLOAT_EQ(glass->material.ior, 1.45f);
  // KHR_materials_volume: sigma = -ln(attenuationColor) / attenuationDistance.
  EXPECT_NEAR(glass->material.absorption[0], std::log(2.0) / 2, 1e-6);
  EXPECT_NEAR(glass->material.absorption[1], std::log(4.0) / 2, 1e-6);
  EXPECT_NEAR(glass->material.absorption[2], 0.0, 1e-9);
  EXPECT_FLOAT_EQ(glass->transform[13], 1.0f);
  // The glass cube's 24 split corners weld into a closed solid of 8.
  ASSERT_TRUE(doc->imported[glass->mesh_index]);
  EXPECT_EQ(doc->imported[glass->mesh_index]->mesh.positions.size(), 8u);
  EXPECT_EQ(doc->imported[glass->mesh_index]->mesh.triangles.size(), 12u);

  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, LightType::kDirectional);
  EXPECT_EQ(s.lights[0].name, "sun");
  EXPECT_NEAR(s.lights[0].irradiance, 1.0, 1e-6);  // 683 lux at 683 lm/W
  EXPECT_NEAR(s.lights[0].direction[1], -1.0, 1e-6);
  EXPECT_FLOAT_EQ(s.lights[0].color[2], 0.8f);
  ASSERT_TRUE(s.camera);
  EXPECT_FLOAT_EQ(s.camera->position[2], 6.0f);
  EXPECT_NEAR(s.camera->target[2], 5.0, 1e-6);  // one metre along -z
  EXPECT_NEAR(s.camera->fov_y_deg, 0.8 * 180 / 3.14159265358979, 1e-4);
  EXPECT_FLOAT_EQ(s.camera->far_plane, 50.0f);

  // The whole bake: the glass gets its transport table, the file names
  // the glTF as its only input (the buffer is embedded).
  bake::BakeOptions opt;
  opt.transport.resolution = 6;  // the table's accuracy is glass_test's
  auto baked = bake::bake_scene(path.string(), opt);
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  EXPECT_EQ(baked->transport.size(), 1u);
  EXPECT_EQ(baked->inputs, std::vector<std::string>{path.string()});
  auto again = bake::bake_scene(path.string(), opt);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(baked->cxb, again->cxb);  // deterministic
}

TEST_F(Gltf, GlbWithExternalBufferAndHierarchy) {
  GltfBuilder g;
  const SplitCube cube;
  const int cp = g.positions(cube.positions), ci = g.indices(cube.indices);
  const int mesh = g.mesh(json::array({{{"attributes", {{"POSITION", cp}}}, {"indices", ci}}}));
  // Parent: T(1, 0, 0) R(90 deg about y) S(2); child: T(0, 0, 1) with the
  // mesh; a third node by matrix (column-major): a translation by (0, 3, 0).
  const double s = std::sqrt(0.5);
  const int child = g.node({{"name", "Child"}, {"mesh", mesh}, {"translation", {0.0, 0.0, 1.0}}});
  const int parent = g.node({{"name", "Parent"}, {"translation", {1.0, 0.0, 0.0}}, {"rotation", {0.0, s, 0.0, s}}, {"scale", {2.0, 2.0, 2.0}}, {"children", {child}}});
  const int by_matrix = g.node({{"name", "Matrix"}, {"mesh", mesh}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 3, 0, 1}}});
  g.scene({parent, by_matrix});
  const fs::path glb = dir_ / "tree.glb";
  g.write_glb(glb);
  auto doc = bake::load_scene(glb.string());
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  ASSERT_EQ(doc->scene.objects.size(), 2u);
  const Object* c = find(doc->scene, "Child");
  ASSERT_TRUE(c);
  // Child's local (0, 0, 0) -> (0, 0, 1) -> scaled (0, 0, 2) -> turned about
  // y by 90 degrees: (2, 0, 0) -> moved: (3, 0, 0).
  const auto o = apply(c->transform, {0, 0, 0});
  EXPECT_NEAR(o[0], 3.0, 1e-6);
  EXPECT_NEAR(o[2], 0.0, 1e-6);
  const auto x = apply(c->transform, {0.5, 0, 0});  // local +x turns to -z, doubled
  EXPECT_NEAR(x[2], -1.0, 1e-6);
  const Object* m = find(doc->scene, "Matrix");
  ASSERT_TRUE(m);
  EXPECT_NEAR(apply(m->transform, {0, 0, 0})[1], 3.0, 1e-6);
  // Both nodes share one mesh. Without normals in the file, corners merge
  // by position (8 vertices) and normals are computed.
  EXPECT_EQ(c->mesh_index, m->mesh_index);
  EXPECT_EQ(doc->scene.meshes.size(), 1u);
  EXPECT_EQ(doc->imported[0]->mesh.positions.size(), 8u);
  EXPECT_FALSE(doc->imported[0]->normals_from_file);

  // The same scene with the buffer in a .bin beside the .gltf: the bake's
  // inputs (the depfile) name both.
  const fs::path gltf = dir_ / "tree.gltf";
  g.write_external(gltf, "tree.bin");
  auto baked = bake::bake_scene(gltf.string(), {});
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  EXPECT_EQ(baked->inputs, (std::vector<std::string>{gltf.string(), (dir_ / "tree.bin").string()}));
  auto said = [](const bake::BakeResult& r, const std::string& start) {
    return std::any_of(r.warnings.begin(), r.warnings.end(), [&](const std::string& w) { return w.rfind(start, 0) == 0; });
  };
  // The file has no lights: the default rig's sun, from over the automatic
  // camera's right shoulder (the camera looks along -(0.6, 0.7, 1)), said.
  EXPECT_TRUE(said(*baked, gltf.string() + ": the file has no lights; lit by the default rig"));
  const SceneDesc& lit = baked->scene;
  ASSERT_EQ(lit.lights.size(), 1u);
  EXPECT_EQ(lit.lights[0].type, LightType::kDirectional);
  EXPECT_FLOAT_EQ(lit.lights[0].irradiance, 1.0f);
  const Vec3f d = lit.lights[0].direction;
  EXPECT_NEAR(std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), 1.0, 1e-6);
  EXPECT_NEAR(std::asin(-d[1]) * 180.0 / 3.14159265358979, 55.0, 1e-4);  // its elevation
  // Light travels away from the camera's side (-z) and to its left (-x of
  // a camera at +x +z: the sun is on the right shoulder).
  EXPECT_LT(d[2], 0.0f);
  const double right_x = 1.0 / std::sqrt(1.36), right_z = -0.6 / std::sqrt(1.36);  // cross(up, back) normalised
  EXPECT_LT(d[0] * right_x + d[2] * right_z, -0.1);
  bake::BakeOptions dark;
  dark.default_light = false;
  auto unlit = bake::bake_scene(gltf.string(), dark);
  ASSERT_TRUE(unlit.ok()) << unlit.error().message;
  EXPECT_TRUE(unlit->scene.lights.empty());
  EXPECT_TRUE(said(*unlit, gltf.string() + ": the scene has no lights; everything will be dark. Export its lights as KHR_lights_punctual"));
}

// Duplicated objects as exporters write them: each copy of the
// glass cube its own glTF mesh with its own copy of the data, one turned
// and scaled, one in a glass that differs only in colour (a tint, drawn at
// run time), one of another index. The bake stores the mesh once and
// traces two tables: the cube's, which the turned and the coloured copies
// use (LTTR), and the other index's. With share off, four of each.
TEST_F(Gltf, DuplicatedMeshesAndTablesAreStoredOnce) {
  GltfBuilder g = pool_scene();
  const SplitCube cube;
  auto glass = [&](double ior, std::vector<double> colour) {
    return g.material({{"pbrMetallicRoughness", {{"baseColorFactor", colour}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
                       {"extensions",
                        {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                         {"KHR_materials_ior", {{"ior", ior}}},
                         {"KHR_materials_volume", {{"thicknessFactor", 1.0}, {"attenuationDistance", 2.0}, {"attenuationColor", {0.5, 0.25, 1.0}}}}}}});
  };
  const int same = glass(1.45, {1, 1, 1, 1}), amber = glass(1.45, {1.0, 0.7, 0.4, 1}), denser = glass(1.7, {1, 1, 1, 1});
  const double s = std::sqrt(0.5);
  struct Copy {
    const char* name;
    int material;
    json place;
  };
  const Copy copies[] = {{"Turned", same, {{"translation", {1.0, 0.5, 0.0}}, {"rotation", {0.0, s, 0.0, s}}, {"scale", {0.5, 0.5, 0.5}}}},
                         {"Amber", amber, {{"translation", {-1.0, 0.5, 0.0}}}},
                         {"Denser", denser, {{"translation", {0.0, 0.5, 1.0}}}}};
  std::vector<int> roots = g.doc["scenes"][0]["nodes"].get<std::vector<int>>();
  for (const Copy& c : copies) {
    const int cp = g.positions(cube.positions), cn = g.normals(cube.normals), ci = g.indices(cube.indices);
    const int m = g.mesh(json::array({{{"attributes", {{"POSITION", cp}, {"NORMAL", cn}}}, {"indices", ci}, {"material", c.material}}}), c.name);
    json node = c.place;
    node["name"] = c.name;
    node["mesh"] = m;
    roots.push_back(g.node(node));
  }
  g.scene(roots);
  const fs::path p = dir_ / "copies.glb";
  g.write_glb(p);
  bake::BakeOptions opt;
  opt.transport.resolution = 6;  // the tables' accuracy is glass_test's
  auto shared = bake::bake_scene(p.string(), opt);
  ASSERT_TRUE(shared.ok()) << shared.error().message;
  opt.share = false;
  auto separate = bake::bake_scene(p.string(), opt);
  ASSERT_TRUE(separate.ok()) << separate.error().message;
  EXPECT_EQ(shared->scene.meshes.size(), 2u) << "the floor's and the cube's";
  EXPECT_EQ(separate->scene.meshes.size(), 5u);
  EXPECT_EQ(shared->transport.size(), 2u);
  EXPECT_EQ(separate->transport.size(), 4u);
  const SceneDesc& sc = shared->scene;
  const Object *cube0 = find(sc, "Glass"), *turned = find(sc, "Turned"), *amber_cube = find(sc, "Amber"), *denser_cube = find(sc, "Denser");
  ASSERT_TRUE(cube0 && turned && amber_cube && denser_cube);
  const auto index = [&](const Object* o) { return static_cast<std::uint32_t>(o - sc.objects.data()); };
  EXPECT_EQ(turned->tables_from, std::optional<std::uint32_t>{index(cube0)});
  EXPECT_EQ(amber_cube->tables_from, std::optional<std::uint32_t>{index(cube0)});
  EXPECT_FALSE(denser_cube->tables_from.has_value()) << "another index needs its own table";
  EXPECT_EQ(denser_cube->mesh_index, cube0->mesh_index) << "but not its own mesh";
  const std::size_t notes = std::count_if(shared->notes.begin(), shared->notes.end(), [](const std::string& n) { return n.find("stored once") != std::string::npos; });
  EXPECT_EQ(notes, 3u);
  std::printf("[copies] %zu bytes shared, %zu without\n", shared->cxb.size(), separate->cxb.size());
  EXPECT_LT(shared->cxb.size(), separate->cxb.size());
  for (const auto* r : {&*shared, &*separate}) {
    auto c = cxb::read_container(r->cxb.data(), r->cxb.size());
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->find(cxb::kTagTransportShared).size(), r == &*shared ? 1u : 0u);
    EXPECT_TRUE(decode_scene(*c).ok());
  }
}

TEST_F(Gltf, ReceiverKeepsHardEdgesGlassIsWelded) {
  GltfBuilder g = pool_scene();
  const fs::path p = dir_ / "pool.glb";
  g.write_glb(p);
  auto file = bake::GltfFile::load(p.string());
  ASSERT_TRUE(file.ok()) << file.error().message;
  auto hard = file->node_mesh("Glass", /*weld=*/false);
  auto welded = file->node_mesh("Glass", /*weld=*/true);
  ASSERT_TRUE(hard.ok() && welded.ok());
  EXPECT_EQ(hard->mesh.positions.size(), 24u);
  EXPECT_TRUE(hard->normals_from_file);
  for (const auto& n : hard->mesh.normals) EXPECT_NEAR(std::fabs(n[0]) + std::fabs(n[1]) + std::fabs(n[2]), 1.0, 1e-6);
  EXPECT_EQ(welded->mesh.positions.size(), 8u);
  for (const auto& n : welded->mesh.normals) EXPECT_NEAR(std::fabs(n[0]), 1 / std::sqrt(3.0), 1e-6);  // averaged at corners
  auto missing = file->node_mesh("Nope", false);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("no node named 'Nope' (nodes: Floor, Glass, SunNode, Cam)"), std::string::npos);
}

TEST_F(Gltf, DracoCompressedPrimitive) {
  const SplitCube cube(0.25f);
  bake::DracoOptions opt;
  opt.position_bits = 14;
  auto stream = bake::encode_draco(cube.triangle_mesh(), opt);
  ASSERT_TRUE(stream.ok()) << stream.error().message;
  GltfBuilder g;
  g.use_extension("KHR_draco_mesh_compression", true);
  const int mesh = g.mesh(json::array({g.draco_primitive(*stream, 24, 12, 0.25f)}));
  const int view = g.doc["meshes"][mesh]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"].get<int>();
  g.scene({g.node({{"name", "D"}, {"mesh", mesh}})});
  const fs::path p = dir_ / "draco.glb";
  g.write_glb(p);
  auto file = bake::GltfFile::load(p.string());
  ASSERT_TRUE(file.ok()) << file.error().message;
  auto m = file->node_mesh("D", false);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->mesh.triangles.size(), 12u);
  // Every corner within Draco's quantisation step of the cube's.
  const double step = 0.5 / ((1 << 14) - 1);
  for (const auto& q : m->mesh.positions) {
    for (float c : q) EXPECT_NEAR(std::fabs(c), 0.25, step);
  }
  // A corrupt stream is refused at the extension's pointer.
  g.bin[static_cast<std::size_t>(g.doc["bufferViews"][view]["byteOffset"].get<int>()) + 3] ^= 0xFF;
  g.bin[static_cast<std::size_t>(g.doc["bufferViews"][view]["byteOffset"].get<int>()) + 4] ^= 0xFF;
  const std::string e = error_of(g);
  EXPECT_NE(e.find("/meshes/0/primitives/0/extensions/KHR_draco_mesh_compression"), std::string::npos) << e;
}

TEST_F(Gltf, QuantisedPositionsAndNormals) {
  // KHR_mesh_quantization: positions as normalised shorts scaled by the
  // node, normals as normalised bytes.
  GltfBuilder g;
  g.use_extension("KHR_mesh_quantization", true);
  const SplitCube cube;
  std::vector<std::int16_t> pos;
  std::vector<std::int8_t> nrm;
  for (std::size_t i = 0; i < cube.positions.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      pos.push_back(static_cast<std::int16_t>(cube.positions[i][k] * 2 * 32767));
      nrm.push_back(static_cast<std::int8_t>(cube.normals[i][k] * 127));
    }
    pos.push_back(0);  // vec3 of shorts padded to 4-byte elements (§3.6.2.4) by a stride
    nrm.push_back(0);
  }
  const int pv = g.view(pos.data(), pos.size() * 2), nv = g.view(nrm.data(), nrm.size());
  g.doc["bufferViews"][pv]["byteStride"] = 8;
  g.doc["bufferViews"][nv]["byteStride"] = 4;
  g.doc["accessors"].push_back({{"bufferView", pv}, {"componentType", 5122}, {"normalized", true}, {"count", 24}, {"type", "VEC3"}, {"min", {-1, -1, -1}}, {"max", {1, 1, 1}}});
  g.doc["accessors"].push_back({{"bufferView", nv}, {"componentType", 5120}, {"normalized", true}, {"count", 24}, {"type", "VEC3"}});
  const int ci = g.indices(cube.indices);
  const int mesh = g.mesh(json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", ci}}}));
  g.scene({g.node({{"name", "Q"}, {"mesh", mesh}, {"scale", {0.5, 0.5, 0.5}}})});
  const fs::path p = dir_ / "q.gltf";
  g.write_embedded(p);
  auto doc = bake::load_scene(p.string());
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  const auto& m = doc->imported[0]->mesh;
  for (const auto& q : m.positions) {
    for (float c : q) EXPECT_NEAR(std::fabs(c), 1.0, 1.0 / 32767);
  }
  EXPECT_TRUE(doc->imported[0]->normals_from_file);
  EXPECT_NEAR(apply(doc->scene.objects[0].transform, {1, 1, 1})[0], 0.5, 1e-6);
}

TEST_F(Gltf, MirrorsPointAndSpotLightsAndNamedWarnings) {
  GltfBuilder g = pool_scene();
  // The floor turns into a mirror (metallic, smooth), with a texture and
  // an unsupported material extension; the glass has dispersion (imported
  // as caustix's own: 20 / Abbe number) and the floor's out-of-range one
  // would be refused, but a mirror's material takes no dispersion.
  g.doc["materials"][0]["pbrMetallicRoughness"] = {{"baseColorFactor", {0.9, 0.8, 0.7, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.05}, {"baseColorTexture", {{"index", 0}}}};
  g.doc["materials"][0]["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 1.0}};
  g.doc["materials"][1]["extensions"]["KHR_materials_dispersion"] = {{"dispersion", 0.4}};
  g.use_extension("KHR_materials_clearcoat");
  g.use_extension("KHR_materials_dispersion");
  g.doc["extensions"]["KHR_lights_punctual"]["lights"].push_back({{"type", "point"}, {"intensity", 68.3}});
  g.doc["extensions"]["KHR_lights_punctual"]["lights"].push_back({{"type", "spot"}, {"intensity", 6.83}, {"spot", {{"outerConeAngle", 0.5}}}});
  g.doc["animations"] = json::array({{{"channels", json::array()}, {"samplers", json::array()}}});
  const int lamp = g.node({{"name", "Lamp"}, {"translation", {1.0, 2.0, 3.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  const int spot = g.node({{"name", "Spot"}, {"translation", {0.0, 4.0, 0.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  g.doc["scenes"][0]["nodes"].push_back(lamp);
  g.doc["scenes"][0]["nodes"].push_back(spot);
  const fs::path p = dir_ / "m.gltf";
  g.write_embedded(p);
  auto doc = bake::load_scene(p.string());
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  const Object* floor = find(doc->scene, "Floor");
  ASSERT_TRUE(floor);
  EXPECT_EQ(floor->role, Role::kMirror);
  EXPECT_FLOAT_EQ(floor->material.reflectance[0], 0.9f);
  const Object* glass = find(doc->scene, "Glass");
  ASSERT_TRUE(glass);
  EXPECT_FLOAT_EQ(glass->material.dispersion, 0.4f);
  ASSERT_EQ(doc->scene.lights.size(), 3u);
  EXPECT_EQ(doc->scene.lights[1].type, LightType::kPoint);
  EXPECT_EQ(doc->scene.lights[1].name, "Lamp");
  EXPECT_NEAR(doc->scene.lights[1].intensity, 0.1, 1e-6);  // 68.3 cd
  EXPECT_FLOAT_EQ(doc->scene.lights[1].position[2], 3.0f);
  EXPECT_EQ(doc->scene.lights[2].type, LightType::kPoint);
  // KHR_lights_punctual's spot: its cone about the node's -z (no rotation: -z).
  EXPECT_TRUE(doc->scene.lights[2].spot);
  EXPECT_FALSE(doc->scene.lights[1].spot);
  EXPECT_FLOAT_EQ(doc->scene.lights[2].inner_cone, 0.0f);
  EXPECT_FLOAT_EQ(doc->scene.lights[2].outer_cone, 0.5f);
  EXPECT_FLOAT_EQ(doc->scene.lights[2].direction[2], -1.0f);
  std::string all;
  for (const auto& w : doc->warnings) all += w + "\n";
  for (const char* named : {"baseColorTexture", "KHR_materials_clearcoat",
                            "1 animation(s) ignored"}) {
    EXPECT_NE(all.find(named), std::string::npos) << named << " not in:\n" << all;
  }
  EXPECT_EQ(all.find("KHR_materials_dispersion"), std::string::npos) << all;
}

TEST_F(Gltf, SceneJsonImportsAFileAndNamesNodes) {
  pool_scene().write_glb(dir_ / "assets.glb");
  // All of assets.glb after scene.json's own object, with scene.json's
  // water and light (the file's sun is not taken), plus one node's mesh
  // placed and dressed by scene.json.
  std::ofstream(dir_ / "scene.json") << R"({
    "objects": [{"name": "Lens", "mesh": "assets.glb#Glass", "role": "transparent",
                 "material": {"transparent": true, "ior": 1.6}, "transform": {"translate": [1, 0.5, 0]}}],
    "gltf": "assets.glb",
    "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": 2}],
    "water": {"level": 0.8, "grid": {"extent": [-2, -2, 2, 2], "cells": [32, 32]}}
  })";
  auto doc = bake::load_scene((dir_ / "scene.json").string());
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  ASSERT_EQ(doc->scene.objects.size(), 3u);
  EXPECT_EQ(doc->scene.objects[0].name, "Lens");
  EXPECT_FLOAT_EQ(doc->scene.objects[0].material.ior, 1.6f);
  EXPECT_EQ(doc->imported[0]->mesh.positions.size(), 8u);  // welded: transparent
  EXPECT_EQ(doc->scene.objects[1].name, "Floor");
  EXPECT_EQ(doc->scene.lights.size(), 1u);
  EXPECT_FLOAT_EQ(doc->scene.lights[0].irradiance, 2.0f);
  ASSERT_TRUE(doc->scene.camera);  // scene.json has none: the file's
  EXPECT_EQ(doc->inputs, (std::vector<std::string>{(dir_ / "scene.json").string(), (dir_ / "assets.glb").string()}));
  bake::BakeOptions opt;
  opt.transport.resolution = 6;
  auto baked = bake::bake_scene((dir_ / "scene.json").string(), opt);
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  EXPECT_EQ(baked->transport.size(), 2u);

  // A node that does not exist: the scene's place, then the file's message.
  std::ofstream(dir_ / "bad.json") << R"({"objects": [{"name": "X", "mesh": "assets.glb#Missing"}]})";
  auto bad = bake::load_scene((dir_ / "bad.json").string());
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("bad.json:1:"), std::string::npos) << bad.error().message;
  EXPECT_NE(bad.error().message.find("/objects/0/mesh: " + (dir_ / "assets.glb").string() + ": no node named 'Missing'"), std::string::npos)
      << bad.error().message;
}

// assets/gltf/glass_ball.gltf is assets/scenes/glass_ball.json as an
// exporter writes it (assets/gltf/generate.py): both routes must bake the
// same scene -- the same meshes, transforms, materials, light, camera and
// light-transport table.
TEST(GltfScene, GlassBallBakesAsTheSceneJsonDoes) {
  const std::string assets = std::string(CAUSTIX_SOURCE_DIR) + "/assets/";
  bake::BakeOptions opt;
  opt.transport.resolution = 6;
  auto from_json = bake::bake_scene(assets + "scenes/glass_ball.json", opt);
  auto from_gltf = bake::bake_scene(assets + "gltf/glass_ball.gltf", opt);
  ASSERT_TRUE(from_json.ok()) << from_json.error().message;
  ASSERT_TRUE(from_gltf.ok()) << from_gltf.error().message;
  const SceneDesc& a = from_json->scene;
  const SceneDesc& b = from_gltf->scene;
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].name, b.objects[i].name);
    EXPECT_EQ(a.objects[i].role, b.objects[i].role);
    EXPECT_EQ(a.objects[i].material.ior, b.objects[i].material.ior);
    for (std::size_t k = 0; k < 16; ++k) EXPECT_NEAR(a.objects[i].transform[k], b.objects[i].transform[k], 1e-7) << i << " " << k;
  }
  ASSERT_EQ(b.lights.size(), 1u);
  EXPECT_NEAR(b.lights[0].irradiance, a.lights[0].irradiance, 1e-6);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(b.lights[0].direction[k], a.lights[0].direction[k], 1e-6);
  ASSERT_TRUE(a.camera && b.camera);
  // Same eye and viewing direction (the glTF camera's target is 1 m out).
  std::array<double, 3> da{}, db{};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(a.camera->position[k], b.camera->position[k], 1e-6);
    da[k] = a.camera->target[k] - a.camera->position[k];
    db[k] = b.camera->target[k] - b.camera->position[k];
  }
  const double la = std::sqrt(da[0] * da[0] + da[1] * da[1] + da[2] * da[2]);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(da[k] / la, db[k], 1e-6);
  EXPECT_NEAR(a.camera->fov_y_deg, b.camera->fov_y_deg, 1e-4);
  // The stored meshes and the transport table, byte for byte.
  auto ca = cxb::read_container(from_json->cxb.data(), from_json->cxb.size());
  auto cb = cxb::read_container(from_gltf->cxb.data(), from_gltf->cxb.size());
  ASSERT_TRUE(ca.ok() && cb.ok());
  for (const cxb::Tag tag : {cxb::kTagMesh, cxb::kTagTransport}) {
    const auto ia = ca->find(tag), ib = cb->find(tag);
    ASSERT_EQ(ia.size(), ib.size());
    ASSERT_FALSE(ia.empty());
    for (std::size_t k = 0; k < ia.size(); ++k) {
      const auto pa = ca->payload(ia[k]), pb = cb->payload(ib[k]);
      EXPECT_TRUE(std::equal(pa.begin(), pa.end(), pb.begin(), pb.end())) << "chunk " << k;
    }
  }
}

// assets/gltf/materials.gltf (a material sheet as exporters write it):
// every receiver keeps its metallic-roughness factors as a surface, the
// panel its emission times KHR_materials_emissive_strength, the amber ball
// its Beer-Lambert coefficient -ln(c) / d, and the file, without lights,
// gets the default sun.
TEST(GltfScene, AMaterialSheetKeepsSurfacesEmissionAndVolume) {
  auto doc = bake::load_scene(std::string(CAUSTIX_SOURCE_DIR) + "/assets/gltf/materials.gltf");
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  const auto surface = [&](const char* name) {
    const Object* o = find(doc->scene, name);
    EXPECT_TRUE(o && o->role == Role::kReceiver && o->material.surface) << name;
    return o && o->material.surface ? *o->material.surface : Surface{};
  };
  EXPECT_EQ(surface("gold"), (Surface{1.0f, 0.25f, {0, 0, 0}}));
  EXPECT_EQ(surface("iron"), (Surface{1.0f, 1.0f, {0, 0, 0}}));
  EXPECT_EQ(surface("red"), (Surface{0.0f, 0.0f, {0, 0, 0}}));
  EXPECT_EQ(surface("panel").emissive, (Vec3f{2.0f, 1.2f, 0.6f}));
  const Object* amber = find(doc->scene, "amber");
  ASSERT_TRUE(amber);
  EXPECT_EQ(amber->role, Role::kTransparent);
  EXPECT_FALSE(amber->material.surface);
  EXPECT_NEAR(amber->material.absorption[0], 0.0, 1e-6);
  EXPECT_NEAR(amber->material.absorption[1], -std::log(0.55) / 0.3, 1e-4);
  EXPECT_NEAR(amber->material.absorption[2], -std::log(0.15) / 0.3, 1e-4);
  ASSERT_EQ(doc->scene.lights.size(), 1u);
  EXPECT_EQ(doc->scene.lights[0].name, "default sun");
}

// textured.gltf's materials as an exporter writes them (assets/gltf/
// generate.py): every texture slot reaches the .cxb, an ORM image used as
// metallic-roughness and occlusion is stored once, a masking base colour
// keeps its alpha, and nothing is said to be ignored.
TEST(GltfScene, TexturedMaterialsKeepTheirMapsAndAlpha) {
  const std::string path = std::string(CAUSTIX_SOURCE_DIR) + "/assets/gltf/textured.gltf";
  auto baked = bake::bake_scene(path, {});
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  for (const auto& w : baked->warnings) EXPECT_EQ(w.find("ignored"), std::string::npos) << w;
  auto c = cxb::read_container(baked->cxb.data(), baked->cxb.size());
  ASSERT_TRUE(c.ok());
  auto d = decode_scene(*c);
  ASSERT_TRUE(d.ok()) << d.error().message;
  const SceneDesc& s = d->scene;
  const auto maps = [&](const char* name) -> const Material& {
    const Object* o = find(s, name);
    EXPECT_TRUE(o && o->role == Role::kReceiver) << name;
    static const Material none;
    return o ? o->material : none;
  };
  const Material& floor = maps("floor");
  ASSERT_TRUE(floor.albedo_texture && floor.maps);
  ASSERT_TRUE(floor.maps->metallic_roughness && floor.maps->normal && floor.maps->occlusion);
  EXPECT_FALSE(floor.maps->emissive);
  EXPECT_EQ(floor.maps->metallic_roughness->image, floor.maps->occlusion->image);  // the ORM image, once
  EXPECT_NE(floor.albedo_texture->image, floor.maps->normal->image);
  EXPECT_EQ(floor.maps->normal->transform, texture_transform({0, 0}, 0, {2, 2}));
  EXPECT_EQ(floor.maps->alpha_mode, AlphaMode::kOpaque);
  const Object* floor_object = find(s, "floor");
  ASSERT_TRUE(floor_object);
  auto mesh = decode_draco(d->draco_meshes[floor_object->mesh_index], s.meshes[floor_object->mesh_index]);
  ASSERT_TRUE(mesh.ok());
  EXPECT_EQ(mesh->uvs.size(), mesh->positions.size());  // the maps' coordinates travel
  ASSERT_TRUE(maps("sign").maps && maps("sign").maps->emissive);
  const Material& fence = maps("fence");
  ASSERT_TRUE(fence.maps && fence.albedo_texture);
  EXPECT_EQ(fence.maps->alpha_mode, AlphaMode::kMask);
  EXPECT_EQ(fence.maps->alpha_cutoff, 0.5f);
  EXPECT_EQ(s.images[fence.albedo_texture->image].alpha.size(), std::size_t{64} * 64);
  EXPECT_TRUE(s.images[floor.albedo_texture->image].alpha.empty());  // an opaque base colour keeps none
  ASSERT_TRUE(maps("plate").maps && maps("plate").maps->metallic_roughness);
  const Material& pane = maps("pane");
  ASSERT_TRUE(pane.maps);
  EXPECT_EQ(pane.maps->alpha_mode, AlphaMode::kBlend);
  EXPECT_NEAR(pane.maps->alpha, 0.35f, 1e-6);
  const Object* ball = find(s, "ball");
  ASSERT_TRUE(ball);
  EXPECT_EQ(ball->role, Role::kTransparent);
  EXPECT_FALSE(ball->material.maps);
}

TEST_F(Gltf, MalformedFilesAreRefusedWithThePointer) {
  {  // POSITION names an accessor that does not exist.
    GltfBuilder g = pool_scene();
    g.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99;
    EXPECT_NE(error_of(g).find("/meshes/0/primitives/0/attributes/POSITION: accessor 99 does not exist"), std::string::npos);
  }
  {  // A buffer view that runs past its buffer.
    GltfBuilder g = pool_scene();
    g.doc["bufferViews"][0]["byteLength"] = 1 << 20;
    EXPECT_NE(error_of(g, "bad.gltf").find("/bufferViews/0: bytes 0 + 1048576 run past"), std::string::npos);
  }
  {  // An accessor longer than its view.
    GltfBuilder g = pool_scene();
    g.doc["accessors"][0]["count"] = 5;
    EXPECT_NE(error_of(g).find("/accessors/0: bytes 0 + 60 run past the 48 bytes of buffer view 0"), std::string::npos);
  }
  {  // An index beyond the vertices.
    GltfBuilder g = pool_scene();
    const int bad = g.indices({0, 1, 7});
    g.doc["meshes"][0]["primitives"][0]["indices"] = bad;
    EXPECT_NE(error_of(g).find("/accessors/" + std::to_string(bad) + ": index 7 at element 2 is beyond the 4 vertices of POSITION"), std::string::npos);
  }
  {  // A cycle in the node hierarchy.
    GltfBuilder g = pool_scene();
    g.doc["nodes"][1]["children"] = {0};
    g.doc["nodes"][0]["children"] = {1};
    EXPECT_NE(error_of(g).find("is reached twice"), std::string::npos);
  }
  {  // A required extension caustix does not know.
    GltfBuilder g = pool_scene();
    g.use_extension("EXT_meshopt_compression", true);
    EXPECT_NE(error_of(g).find("/extensionsRequired/0: the file requires extension EXT_meshopt_compression"), std::string::npos);
  }
  {  // Values out of range.
    GltfBuilder g = pool_scene();
    g.doc["materials"][1]["extensions"]["KHR_materials_ior"]["ior"] = 0.5;
    EXPECT_NE(error_of(g).find("/materials/1/extensions/KHR_materials_ior/ior: must be a number in [1,"), std::string::npos);
    g = pool_scene();
    g.doc["materials"][1]["extensions"]["KHR_materials_dispersion"]["dispersion"] = -1.0;
    EXPECT_NE(error_of(g).find("/materials/1/extensions/KHR_materials_dispersion/dispersion: must be a number in [0,"), std::string::npos);
    g = pool_scene();
    g.doc["nodes"][0]["scale"] = {0.0, 1.0, 1.0};
    EXPECT_NE(error_of(g).find("/nodes/0 ('Floor')/transform: is degenerate"), std::string::npos) << error_of(g);
    g = pool_scene();
    g.doc["nodes"][2]["extensions"]["KHR_lights_punctual"]["light"] = 4;
    EXPECT_NE(error_of(g).find("/nodes/2/extensions/KHR_lights_punctual/light: light 4 does not exist"), std::string::npos);
  }
  {  // An image's buffer view that runs past its buffer (exporters' files
     // edited by hand; tinygltf hands such a view over unchecked).
    std::ifstream in(std::string(CAUSTIX_SOURCE_DIR) + "/assets/gltf/textured.gltf");
    json doc = json::parse(in);
    const auto size = doc["buffers"][0]["byteLength"].get<std::int64_t>();
    doc["bufferViews"][0]["byteOffset"] = size - 100;
    doc["bufferViews"][0]["byteLength"] = 200;
    const fs::path p = dir_ / "image_view.gltf";
    std::ofstream(p) << doc.dump();
    auto r = bake::load_scene(p.string());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kInput);
    EXPECT_NE(r.error().message.find("/bufferViews/0: bytes " + std::to_string(size - 100) + " + 200 run past"), std::string::npos)
        << r.error().message;
  }
  // Not JSON, a truncated GLB, an empty file: tinygltf's reason.
  const fs::path junk = dir_ / "junk.gltf";
  std::ofstream(junk) << "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [";
  auto j = bake::load_scene(junk.string());
  ASSERT_FALSE(j.ok());
  EXPECT_NE(j.error().message.find(junk.string() + ": not a valid glTF 2.0 file"), std::string::npos) << j.error().message;
  auto bytes = pool_scene().glb();
  for (std::size_t cut : {std::size_t{0}, std::size_t{11}, std::size_t{30}, bytes.size() / 2, bytes.size() - 1}) {
    const fs::path t = dir_ / "cut.glb";
    std::ofstream(t, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(cut));
    auto r = bake::load_scene(t.string());
    EXPECT_FALSE(r.ok()) << "cut at " << cut;
    if (!r.ok()) EXPECT_EQ(r.error().code, ErrorCode::kInput);
  }
  auto none = bake::load_scene((dir_ / "absent.glb").string());
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("glTF file not found"), std::string::npos);
}

}  // namespace
}  // namespace caustix
