// The mesh-import corpus: tests/data/meshes holds files shaped
// like the ones users bring from other tools, and broken ones, with
// expectations.json saying what must happen to each (generate.py writes
// both). Every file is imported, then baked as a receiver in a small pool
// and, where it bounds a solid, as a transparent object: the valid ones
// must bake (and load back through the runtime's loader), the broken ones
// must be refused with a message naming the file and the place. Nothing may
// crash, hang or leak: CI runs this suite under AddressSanitizer too.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "caustix/bake/bake.h"
#include "caustix/bake/mesh_import.h"
#include "caustix/common/mesh_topology.h"
#include "caustix/runtime/scene_loader.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

const std::string kCorpus = std::string(CAUSTIX_SOURCE_DIR) + "/tests/data/meshes/";

struct Entry {
  nlohmann::json j;
  std::string file() const { return j.at("file").get<std::string>(); }
  std::string path() const { return kCorpus + file(); }
  bool bakes() const { return j.at("expect") == "bakes"; }
};

std::vector<Entry> corpus() {
  std::ifstream f(kCorpus + "expectations.json");
  std::vector<Entry> out;
  for (const auto& e : nlohmann::json::parse(f)) out.push_back({e});
  return out;
}

double mesh_area(const TriangleMesh& m) {
  double a = 0;
  for (const auto& t : m.triangles) {
    const auto& p = m.positions[t[0]];
    const auto& q = m.positions[t[1]];
    const auto& r = m.positions[t[2]];
    const double u[3] = {double{q[0]} - p[0], double{q[1]} - p[1], double{q[2]} - p[2]};
    const double v[3] = {double{r[0]} - p[0], double{r[1]} - p[1], double{r[2]} - p[2]};
    const double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    a += 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  }
  return a;
}

// A small pool with the file as a receiver on the floor, or the file as a
// glass object over a floor in the sun: small maps and tables, so that the
// whole corpus bakes in seconds (and under ASan in a minute or two).
std::string scene_with(const std::string& mesh, bool transparent) {
  nlohmann::json part = {{"name", "part"}, {"mesh", mesh}, {"transform", {{"translate", {0, 0.6, 0}}, {"scale", 0.5}}}};
  if (transparent) {
    part["role"] = "transparent";
    part["material"] = {{"transparent", true}, {"ior", 1.5}};
  } else {
    part["role"] = "receiver";
    part["material"] = {{"albedo", 0.8}};
  }
  nlohmann::json j = {
      {"objects", {{{"name", "floor"}, {"mesh", std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/plane.obj"},
                    {"role", "receiver"}, {"material", {{"albedo", 1.0}}}, {"transform", {{"scale", {4, 1, 4}}}}},
                   part}},
      {"lights", {{{"type", "directional"}, {"name", "sun"}, {"direction", {0.25, -1.0, 0.15}}, {"irradiance", 1.0}}}}};
  if (!transparent) {
    j["water"] = {{"level", 2.0}, {"ior", 1.33}, {"grid", {{"cells", {16, 16}}, {"extent", {-2, -2, 2, 2}}}},
                  {"waves", {{{"amplitude", 0.02}, {"wavelength", 1.0}, {"direction", {1, 0}}, {"speed", 0.5}}}}};
  }
  return test::write_scene(j, std::string(transparent ? "glass_" : "pool_") + std::filesystem::path(mesh).stem().string());
}

bake::BakeOptions small_bake() {
  bake::BakeOptions o;
  o.level_maps.map_size = 64;
  o.transport.resolution = 6;
  // Creases are still split; splitting flat faces (tested in glass_test)
  // would turn each corpus cube into thousands of vertices to trace.
  o.glass_refine.max_edge = 0;
  return o;
}

TEST(MeshCorpus, HasFortyFilesOrMore) {
  const auto all = corpus();
  EXPECT_GE(all.size(), 40u);
  for (const Entry& e : all) EXPECT_TRUE(std::filesystem::is_regular_file(e.path())) << e.file();
}

// What the importer makes of each file: the triangles, the area they cover
// (a non-convex polygon triangulated as a fan covers more), the volume of
// closed ones, normals and warnings; or a refusal naming file and place.
TEST(MeshCorpus, ImportsAsExpected) {
  for (const Entry& e : corpus()) {
    SCOPED_TRACE(e.file());
    auto m = bake::import_mesh(e.path());
    if (!e.bakes()) {
      ASSERT_FALSE(m.ok());
      EXPECT_EQ(m.error().code, ErrorCode::kInput);
      EXPECT_EQ(m.error().message.rfind(e.path() + ": ", 0), 0u) << m.error().message;
      EXPECT_NE(m.error().message.find(e.j.at("message").get<std::string>()), std::string::npos) << m.error().message;
      continue;
    }
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->mesh.triangles.size(), e.j.at("triangles").get<std::size_t>());
    const double area = e.j.at("area");
    // Float positions: relative 1e-6 (the huge-coordinate file: its 2 m
    // cube sits 1000 km out, where floats are 6 cm apart).
    EXPECT_NEAR(mesh_area(m->mesh), area, area * (e.file() == "off_huge_coordinates.off" ? 0.1 : 1e-5));
    const EdgeCensus census = census_edges(m->mesh);
    EXPECT_EQ(census.closed(), e.j.at("closed").get<bool>());
    if (e.j.contains("volume")) EXPECT_NEAR(census.signed_volume, e.j.at("volume").get<double>(), 1e-5);
    EXPECT_EQ(m->normals_from_file, e.j.value("normals_from_file", m->normals_from_file));
    for (const auto& n : m->mesh.normals) EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0f, 1e-5f);
    if (e.j.contains("warning")) {
      bool found = false;
      for (const auto& w : m->warnings) found = found || w.find(e.j.at("warning").get<std::string>()) != std::string::npos;
      EXPECT_TRUE(found) << "no warning about " << e.j.at("warning");
    }
  }
}

// Every file baked as a receiver under water: valid ones bake and load
// back through the runtime's loader (Draco decoding included), broken ones
// are refused by the bake with the importer's message.
TEST(MeshCorpus, BakesAsReceiverOrIsRefused) {
  for (const Entry& e : corpus()) {
    SCOPED_TRACE(e.file());
    auto baked = bake::bake_scene(scene_with(e.path(), false), small_bake());
    if (!e.bakes()) {
      ASSERT_FALSE(baked.ok());
      EXPECT_EQ(baked.error().code, ErrorCode::kInput);
      EXPECT_NE(baked.error().message.find(e.path()), std::string::npos) << baked.error().message;
      continue;
    }
    ASSERT_TRUE(baked.ok()) << baked.error().message;
    auto loaded = runtime::load_scene(baked->cxb.data(), baked->cxb.size());
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->meshes.back().triangles.size(), e.j.at("triangles").get<std::size_t>());
  }
}

// Transparent objects are stricter: closed, consistently wound meshes bake
// as solid glass (light-transport table and all); open ones bound no solid
// and bake thin-walled, with a warning giving the edge census
// (what is wrong, how many edges, the first ones); a closed one that is not
// a solid is refused with it.
TEST(MeshCorpus, ClosedOnesBakeAsGlassOthersThinWalled) {
  for (const Entry& e : corpus()) {
    if (!e.bakes()) continue;
    SCOPED_TRACE(e.file());
    auto baked = bake::bake_scene(scene_with(e.path(), true), small_bake());
    if (e.j.at("closed").get<bool>()) {
      ASSERT_TRUE(baked.ok()) << baked.error().message;
      ASSERT_EQ(baked->transport.size(), 1u);
      EXPECT_GT(baked->transport[0].leaving, 0u);
      continue;
    }
    if (e.j.value("as_glass", std::string("thin")) == "refused") {  // closed, not a solid: a solid was meant
      ASSERT_FALSE(baked.ok());
      EXPECT_EQ(baked.error().code, ErrorCode::kInput);
      EXPECT_NE(baked.error().message.find(e.path() + ": transparent object 'part' is not a closed, consistently wound mesh"),
                std::string::npos)
          << baked.error().message;
      EXPECT_NE(baked.error().message.find(e.j.at("transparent_message").get<std::string>()), std::string::npos) << baked.error().message;
      continue;
    }
    ASSERT_TRUE(baked.ok()) << baked.error().message;
    EXPECT_EQ(baked->scene.objects.back().role, Role::kThin);
    EXPECT_TRUE(baked->transport.empty());
    std::string msg;
    for (const auto& w : baked->warnings) msg += w + "\n";
    EXPECT_NE(msg.find(e.path() + ": transparent object 'part' is not a closed, consistently wound mesh"), std::string::npos)
        << msg;
    EXPECT_NE(msg.find(e.j.value("transparent_message", std::string("edge"))), std::string::npos) << msg;
    EXPECT_NE(msg.find("baked thin-walled"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace caustix
