// Level-map baking (Tipprasert 2006 §4.2, §4.7.2): frames, position maps, depth
// profiles, plane sets, what is skipped, extremes and determinism.

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>

#include "caustix/bake/bake.h"
#include "caustix/formats/frame.h"
#include "caustix/bake/mesh_import.h"
#include "caustix/bake/position_map.h"
#include "caustix/bake/ray_cast.h"

namespace caustix::bake {
namespace {

const std::string kMeshes = std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/";
constexpr double kPi = 3.14159265358979323846;

double dot(const Vec3f& a, const Vec3f& b) { return double{a[0]} * b[0] + double{a[1]} * b[1] + double{a[2]} * b[2]; }

// Writes a scene file into a fresh temporary directory and bakes it.
class LevelMapTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("caustix_lm_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string scene_file(const std::string& json) {
    const auto p = dir_ / "scene.json";
    std::ofstream(p) << json;
    return p.string();
  }
  Result<BakeResult> bake(const std::string& json, const BakeOptions& opt = {}) {
    return bake_scene(scene_file(json), opt);
  }
  std::filesystem::path dir_;
};

// One object over a pool with flat water at y = 2 and one light.
std::string pool_scene(const std::string& object, const std::string& light, const std::string& water_extra = "") {
  return R"({"objects": [)" + object + R"(], "lights": [)" + light +
         R"(], "water": {"level": 2, "ior": 1.33, "grid": {"cells": [8, 8], "extent": [-50, -50, 50, 50]})" +
         water_extra + "}}";
}
std::string sphere_at(const std::string& translate, double scale = 0.5) {
  return R"({"name": "ball", "mesh": ")" + kMeshes + R"(sphere.obj", "transform": {"translate": )" + translate +
         R"(, "scale": )" + std::to_string(scale) + "}}";
}
std::string sun(double dx, double dy, double dz) {
  return R"({"type": "directional", "direction": [)" + std::to_string(dx) + ", " + std::to_string(dy) + ", " +
         std::to_string(dz) + "]}";
}

void expect_orthonormal_right_handed(const BoundingFrame& f) {
  EXPECT_NEAR(dot(f.u, f.u), 1, 1e-6);
  EXPECT_NEAR(dot(f.v, f.v), 1, 1e-6);
  EXPECT_NEAR(dot(f.w, f.w), 1, 1e-6);
  EXPECT_NEAR(dot(f.u, f.v), 0, 1e-6);
  EXPECT_NEAR(dot(f.u, f.w), 0, 1e-6);
  EXPECT_NEAR(dot(f.v, f.w), 0, 1e-6);
  const Vec3f uxv{f.u[1] * f.v[2] - f.u[2] * f.v[1], f.u[2] * f.v[0] - f.u[0] * f.v[2], f.u[0] * f.v[1] - f.u[1] * f.v[0]};
  EXPECT_NEAR(dot(uxv, f.w), 1, 1e-6);  // W = U x V
}

void expect_all_finite(const LevelMap& m) {
  for (double o : m.frame.origin) ASSERT_TRUE(std::isfinite(o));
  for (const auto* v : {&m.frame.u, &m.frame.v, &m.frame.w, &m.frame.half, &m.frame.symmetric_size}) {
    for (float c : *v) ASSERT_TRUE(std::isfinite(c));
  }
  for (const auto& p : m.uniform_planes) ASSERT_TRUE(std::isfinite(p.offset) && std::isfinite(p.epsilon) && p.epsilon > 0);
  for (const auto& p : m.smart_planes) ASSERT_TRUE(std::isfinite(p.offset) && std::isfinite(p.epsilon) && p.epsilon > 0);
  ASSERT_TRUE(std::isfinite(m.epsilon));
}

TEST(Refraction, Eq2_8MatchesSnell) {
  for (double deg : {0.0, 10.0, 30.0, 60.0, 89.0}) {
    const double th = deg * kPi / 180;
    const Vec3d incident{std::sin(th), -std::cos(th), 0};
    const auto t = refract(incident, {0, 1, 0}, 1 / 1.33);
    ASSERT_TRUE(t.has_value());
    const double sin_t = std::sin(th) / 1.33;
    EXPECT_NEAR((*t)[0], sin_t, 1e-12) << deg;
    EXPECT_NEAR((*t)[1], -std::sqrt(1 - sin_t * sin_t), 1e-12) << deg;
  }
  // Water -> air beyond the critical angle: total internal reflection.
  EXPECT_FALSE(refract({std::sin(1.0), -std::cos(1.0), 0}, {0, 1, 0}, 1.33).has_value());
}

TEST_F(LevelMapTest, FramesFollowTheRefractedDirection) {
  for (double deg : {0.0, 15.0, 30.0, 45.0, 70.0, 85.0}) {
    const double th = deg * kPi / 180;
    // Azimuth 40 degrees so no axis is special.
    const double ax = std::cos(0.7), az = std::sin(0.7);
    auto r = bake(pool_scene(sphere_at("[0, 0.6, 0]"), sun(std::sin(th) * ax, -std::cos(th), std::sin(th) * az)));
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->level_maps.maps.size(), 1u) << deg;
    const BoundingFrame& f = r->level_maps.maps[0].frame;
    expect_orthonormal_right_handed(f);
    const double sin_t = std::sin(th) / 1.33, cos_t = std::sqrt(1 - sin_t * sin_t);
    // V = -T: back toward the light.
    EXPECT_NEAR(f.v[0], -sin_t * ax, 1e-6) << deg;
    EXPECT_NEAR(f.v[1], cos_t, 1e-6) << deg;
    EXPECT_NEAR(f.v[2], -sin_t * az, 1e-6) << deg;
    // The sphere's tight extents are its diameter along every axis.
    for (float hlf : f.half) EXPECT_NEAR(hlf, 0.5, 0.01) << deg;
  }
}

TEST_F(LevelMapTest, PointLightUsesTheRayToTheOrigin) {
  // Fig. 4-7: from the light at (3, 6, 1) to the object's origin (0, 0.6, 0).
  auto r = bake(pool_scene(sphere_at("[0, 0.6, 0]"), R"({"type": "point", "position": [3, 6, 1], "intensity": 10})"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->level_maps.maps.size(), 1u);
  const BoundingFrame& f = r->level_maps.maps[0].frame;
  expect_orthonormal_right_handed(f);
  Vec3d i{-3, -5.4, -1};
  const double n = std::sqrt(i[0] * i[0] + i[1] * i[1] + i[2] * i[2]);
  for (double& c : i) c /= n;
  const Vec3d t = *refract(i, {0, 1, 0}, 1 / 1.33);
  EXPECT_NEAR(f.v[0], -t[0], 1e-6);
  EXPECT_NEAR(f.v[1], -t[1], 1e-6);
  EXPECT_NEAR(f.v[2], -t[2], 1e-6);
  EXPECT_LT(t[0] / t[1], i[0] / i[1]) << "refraction bends the ray toward the vertical";
}

TEST_F(LevelMapTest, ObjectsAboveWaterAndScenesWithoutWaterAreSkipped) {
  auto r = bake(pool_scene(sphere_at("[0, 3, 0]"), sun(0.2, -1, 0)));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->level_maps.maps.empty());
  ASSERT_EQ(r->level_maps.pairs.size(), 1u);
  EXPECT_EQ(r->level_maps.pairs[0].reason, "entirely above the water");

  r = bake(R"({"objects": [)" + sphere_at("[0, 0.6, 0]") + R"(], "lights": [)" + sun(0, -1, 0) + "]}");
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->level_maps.maps.empty());
  EXPECT_NE(r->level_maps.pairs[0].reason.find("no water"), std::string::npos);

  // Light parallel to the water: documented result, no NaN.
  r = bake(pool_scene(sphere_at("[0, 0.6, 0]"), sun(1, 0, 0)));
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->level_maps.maps.empty());
  EXPECT_NE(r->level_maps.pairs[0].reason.find("parallel"), std::string::npos);
}

TEST_F(LevelMapTest, UnreachableAndShadowedReceiversAreSkipped) {
  // Far outside the water grid (extent is +-50 m).
  auto r = bake(pool_scene(sphere_at("[200, 0.6, 0]"), sun(0, -1, 0)));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->level_maps.pairs[0].reason, "no refracted ray from the water grid reaches it");
  // Under an opaque roof (a 6 x 6 m plane at y = 1.5), light straight down.
  const std::string roof = R"({"name": "roof", "mesh": ")" + kMeshes + R"(plane.obj", "transform": {"translate": [0, 1.5, 0], "scale": [6, 1, 6]}})";
  r = bake(pool_scene(sphere_at("[0, 0.6, 0]") + "," + roof, sun(0, -1, 0)));
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->level_maps.pairs.size(), 2u);
  EXPECT_EQ(r->level_maps.pairs[0].reason, "fully shadowed by other objects");
  EXPECT_TRUE(r->level_maps.pairs[1].baked) << r->level_maps.pairs[1].reason;
}

// The water grid's coverage (a floor as wide as the grid had a
// dark strip along its sunward edge, unsaid). A 12 m floor 2 m under water
// whose grid is exactly as wide, a sun 30 degrees from vertical travelling
// +x: the floor within 2 tan(asin(sin 30 / 1.33)) = 0.811 m of the grid's
// -x edge gets no light; the warning names the pair and asks for that much
// more grid on -x. A grid that overhangs by 1 m, or light straight down,
// gives none; so does a pool whose wall rises to the surface along that
// edge (the strip is in its shadow).
TEST_F(LevelMapTest, AWaterGridThatDoesNotOverhangTheLitFloorIsSaid) {
  const std::string floor = R"({"name": "floor", "mesh": ")" + kMeshes + R"(plane.obj", "transform": {"scale": [12, 1, 12]}})";
  const std::string slanted = sun(0.5, -std::sqrt(0.75), 0);
  const auto scene = [&](const std::string& objects, const std::string& light, double half) {
    const std::string h = std::to_string(half);
    return R"({"objects": [)" + objects + R"(], "lights": [)" + light + R"(], "water": {"level": 2, "ior": 1.33, "grid": {"cells": [8, 8], "extent": [-)" +
           h + ", -" + h + ", " + h + ", " + h + "]}}}";
  };
  const double need = 2 * std::tan(std::asin(0.5 / 1.33));
  char want[64];
  std::snprintf(want, sizeof want, "extend the water's extent by %.3g m on -x", need);
  auto r = bake(scene(floor, slanted, 6));
  ASSERT_TRUE(r.ok()) << r.error().message;
  std::string said;
  for (const auto& w : r->warnings) said += w + "\n";
  EXPECT_NE(said.find("object 'floor', light 0: the water grid does not reach far enough"), std::string::npos) << said;
  EXPECT_NE(said.find(want), std::string::npos) << said;
  EXPECT_EQ(said.find("on +x"), std::string::npos) << said;
  for (const auto& [objects, light, half] : {std::tuple{floor, slanted, 7.0}, std::tuple{floor, sun(0, -1, 0), 6.0}}) {
    r = bake(scene(objects, light, half));
    ASSERT_TRUE(r.ok()) << r.error().message;
    for (const auto& w : r->warnings) EXPECT_EQ(w.find("does not reach far enough"), std::string::npos) << w;
  }
  // A wall from the floor to the surface along x = -6 (a box 0.2 m thick outside the grid).
  const std::string wall = R"({"name": "wall", "mesh": ")" + kMeshes + R"(box.obj", "transform": {"translate": [-6.1, 1, 0], "scale": [0.2, 2, 12]}})";
  r = bake(scene(floor + "," + wall, slanted, 6));
  ASSERT_TRUE(r.ok()) << r.error().message;
  for (const auto& w : r->warnings) EXPECT_EQ(w.find("object 'floor', light 0: the water grid"), std::string::npos) << w;
}

TEST_F(LevelMapTest, SphereHasEmptyLevelsAndSmartNeedsAboutHalfThePlanes) {
  BakeOptions opt;
  opt.level_maps.slicing.planes = 32;
  opt.level_maps.slicing.levels = 64;
  auto r = bake(pool_scene(sphere_at("[0, 0.6, 0]"), sun(0.3, -1, 0.2)), opt);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const LevelMap& m = r->level_maps.maps.at(0);
  expect_all_finite(m);
  // Fig. 4-18: the far hemisphere is hidden from the light, so the levels
  // beyond the equator hold no texel.
  std::size_t empty = 0;
  for (std::uint32_t c : m.histogram) empty += c == 0;
  EXPECT_GE(empty, 28u);
  EXPECT_LE(empty, 32u);
  ASSERT_EQ(m.sub_boxes.size(), 1u);
  EXPECT_EQ(m.sub_boxes[0].first_level, 0u);
  EXPECT_EQ(m.uniform_planes.size(), 33u);
  const double ratio = double(m.smart_planes.size()) / double(m.uniform_planes.size());
  EXPECT_GT(ratio, 0.4);
  EXPECT_LT(ratio, 0.65);
  // Acceptance windows of the smart planes tile the valid levels exactly.
  const double h = 2.0 * m.frame.half[1];
  const double top = h / 2, bottom = h / 2 - h * (m.sub_boxes[0].last_level + 1) / 64.0;
  EXPECT_NEAR(m.smart_planes.front().offset + m.smart_planes.front().epsilon, top, 1e-5);
  EXPECT_NEAR(m.smart_planes.back().offset - m.smart_planes.back().epsilon, bottom, 1e-5);
  for (std::size_t i = 1; i < m.smart_planes.size(); ++i) {
    EXPECT_NEAR(m.smart_planes[i - 1].offset - m.smart_planes[i - 1].epsilon,
                m.smart_planes[i].offset + m.smart_planes[i].epsilon, 1e-5);
    EXPECT_LE(m.smart_planes[i].epsilon, m.epsilon * 1.0001);
  }
  // Uniform planes: eq. 4-6..4-9.
  for (std::size_t i = 0; i < m.uniform_planes.size(); ++i) {
    EXPECT_NEAR(m.uniform_planes[i].offset, h / 2 - i * h / 32, 1e-5);
    EXPECT_NEAR(m.uniform_planes[i].epsilon, h / 64, 1e-6);
  }
}

TEST_F(LevelMapTest, BoxPlanesCollapseOntoTheLitFaces) {
  // An axis-aligned box lit straight down: only its top face is seen, so
  // the profile has one valid level and one plane, at the top.
  const std::string box = R"({"name": "box", "mesh": ")" + kMeshes + R"(box.obj", "transform": {"translate": [0, 0.6, 0]}})";
  auto r = bake(pool_scene(box, sun(0, -1, 0)));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const LevelMap& m = r->level_maps.maps.at(0);
  ASSERT_EQ(m.sub_boxes.size(), 1u);
  EXPECT_EQ(m.sub_boxes[0].first_level, 0u);
  EXPECT_EQ(m.sub_boxes[0].last_level, 0u);
  ASSERT_EQ(m.smart_planes.size(), 1u);
  EXPECT_NEAR(m.smart_planes[0].offset, 0.5 - 0.5 / 64, 1e-4);  // centre of level 0 of a 1 m box
  // Lit along a body diagonal, three faces show over the whole depth range:
  // no empty level, and smart slicing cannot drop planes.
  r = bake(pool_scene(box, sun(0.5, -1, 0.5)));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->level_maps.maps.at(0).sub_boxes.size(), 1u);
}

TEST_F(LevelMapTest, PositionMapAgreesWithAnIndependentRayCast) {
  BakeOptions opt;
  opt.level_maps.map_size = 128;
  auto r = bake(pool_scene(sphere_at("[0.3, 0.6, -0.2]", 0.7), sun(0.4, -1, 0.3)), opt);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const LevelMap& m = r->level_maps.maps.at(0);
  const BoundingFrame& f = m.frame;
  // The same mesh in world space, through CGAL's AABB tree.
  auto mesh = import_mesh(kMeshes + "sphere.obj");
  ASSERT_TRUE(mesh.ok());
  std::vector<Vec3d> world;
  for (const auto& p : mesh->mesh.positions) world.push_back({0.3 + 0.7 * p[0], 0.6 + 0.7 * p[1], -0.2 + 0.7 * p[2]});
  const RayCaster caster(world, mesh->mesh.triangles, std::vector<std::uint32_t>(mesh->mesh.triangles.size(), 0));
  const Vec3d down{-f.v[0], -f.v[1], -f.v[2]};
  const double precision = depth_precision(f);
  std::size_t both = 0, coverage_mismatch = 0;
  double worst = 0;
  for (std::uint32_t row = 0; row < m.map_size; ++row) {
    for (std::uint32_t col = 0; col < m.map_size; ++col) {
      const auto uw = texel_center(f, m.map_size, row, col);
      const double start_v = f.half[1] + 1.0;
      const auto hit = caster.first_hit(from_frame(f, {uw[0], start_v, uw[1]}), down);
      const std::uint16_t q = m.depth[std::size_t{row} * m.map_size + col];
      if (hit.has_value() != (q != kEmptyDepth)) {
        ++coverage_mismatch;  // a texel centre exactly on the silhouette
        continue;
      }
      if (!hit) continue;
      ++both;
      const double v_ray = start_v - *hit;
      // Every covered texel lies within the frame.
      EXPECT_LE(std::fabs(v_ray), f.half[1] * (1 + 1e-6) + 1e-9);
      EXPECT_LE(std::fabs(uw[0]), f.half[0]);
      EXPECT_LE(std::fabs(uw[1]), f.half[2]);
      worst = std::max(worst, std::fabs(depth_to_v(f, q) - v_ray));
    }
  }
  EXPECT_GT(both, 10000u);
  EXPECT_LE(coverage_mismatch, both / 200) << "silhouette disagreement over 0.5 %";
  // Quantisation (h / 131068) plus float rounding of the frame.
  EXPECT_LE(worst, precision + 1e-6) << "worst depth error " << worst << " m, stated precision " << precision << " m";
  ::testing::Test::RecordProperty("worst_depth_error_m", std::to_string(worst));
}

TEST_F(LevelMapTest, Extremes) {
  // Grazing light (0.5 degrees above the horizon), straight down.
  for (const auto& light : {sun(std::cos(0.5 * kPi / 180), -std::sin(0.5 * kPi / 180), 0), sun(0, -1, 0)}) {
    auto r = bake(pool_scene(sphere_at("[0, 0.6, 0]"), light));
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->level_maps.maps.size(), 1u);
    expect_all_finite(r->level_maps.maps[0]);
    expect_orthonormal_right_handed(r->level_maps.maps[0].frame);
  }
  // A flat quad with zero thickness along V: one valid level, one plane.
  const std::string quad = R"({"name": "quad", "mesh": ")" + kMeshes + R"(plane.obj", "transform": {"translate": [0, 0.5, 0]}})";
  auto r = bake(pool_scene(quad, sun(0, -1, 0)));
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_all_finite(r->level_maps.maps.at(0));
  EXPECT_EQ(r->level_maps.maps[0].smart_planes.size(), 1u);
  EXPECT_GT(r->level_maps.maps[0].frame.half[1], 0.0f);

  // Epsilon larger than the box: one plane; tiny: capped with a message.
  BakeOptions big;
  big.level_maps.slicing.epsilon = 10.0;
  r = bake(pool_scene(sphere_at("[0, 0.6, 0]"), sun(0, -1, 0)), big);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->level_maps.maps.at(0).smart_planes.size(), 1u);
  BakeOptions tiny;
  tiny.level_maps.slicing.epsilon = 1e-9;
  r = bake(pool_scene(sphere_at("[0, 0.6, 0]"), sun(0, -1, 0)), tiny);
  ASSERT_TRUE(r.ok());
  EXPECT_LE(r->level_maps.maps.at(0).smart_planes.size(), kMaxPlanes);
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_NE(r->warnings[0].find("capped at 4097"), std::string::npos) << r->warnings[0];

  // 10 km from the origin, and 1 mm across: the frame keeps precision
  // (origin in double; extents relative to it).
  for (const auto& [at, scale] : {std::pair{std::string("[10000, 0.6, -10000]"), 0.5}, std::pair{std::string("[0, 0.6, 0]"), 0.0005}}) {
    BakeOptions o;
    o.level_maps.map_size = 64;
    auto far = bake(pool_scene(sphere_at(at, scale), sun(0.3, -1, 0)).replace(
                        pool_scene(sphere_at(at, scale), sun(0.3, -1, 0)).find("[-50, -50, 50, 50]"), 18,
                        "[-20000, -20000, 20000, 20000]"),
                    o);
    ASSERT_TRUE(far.ok()) << far.error().message;
    const LevelMap& m = far->level_maps.maps.at(0);
    expect_all_finite(m);
    for (float hlf : m.frame.half) EXPECT_NEAR(hlf, scale, scale * 0.02) << at;
    std::size_t covered = 0;
    for (std::uint16_t q : m.depth) covered += q != kEmptyDepth;
    EXPECT_GT(covered, 64u * 64u / 2) << at;
  }
}

TEST_F(LevelMapTest, OutputIsIdenticalWithOneAndTwoThreads) {
  const std::string scene = pool_scene(sphere_at("[0, 0.6, 0]") + R"(, {"name": "floor", "mesh": ")" + kMeshes +
                                           R"(plane.obj", "transform": {"scale": [4, 1, 4]}})",
                                       sun(0.3, -1, 0.2) + "," + sun(-0.2, -1, 0.1));
  std::vector<std::uint8_t> one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    auto r = bake(scene);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->level_maps.maps.size(), 4u);
    one = r->cxb;
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    auto r = bake(scene);
    ASSERT_TRUE(r.ok());
    two = r->cxb;
  }
  EXPECT_EQ(one, two);
}

TEST_F(LevelMapTest, LevelMapsSurviveTheContainer) {
  auto r = bake(pool_scene(sphere_at("[0, 0.6, 0]"), sun(0.3, -1, 0.2)));
  ASSERT_TRUE(r.ok());
  auto c = cxb::read_container(r->cxb.data(), r->cxb.size());
  ASSERT_TRUE(c.ok());
  auto d = decode_scene(*c);
  ASSERT_TRUE(d.ok()) << d.error().message;
  ASSERT_EQ(d->level_maps.size(), 1u);
  const LevelMap& a = r->level_maps.maps[0];
  const LevelMap& b = d->level_maps[0];
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.diffuse, b.diffuse);
  EXPECT_EQ(a.histogram, b.histogram);
  ASSERT_EQ(a.smart_planes.size(), b.smart_planes.size());
  EXPECT_EQ(a.smart_planes.back().offset, b.smart_planes.back().offset);
  EXPECT_EQ(a.frame.origin, b.frame.origin);
  EXPECT_EQ(a.frame.v, b.frame.v);
  ASSERT_EQ(d->boxes.size(), 1u);
  for (float hlf : d->boxes[0].half) EXPECT_NEAR(hlf, 0.5, 0.02);  // the sphere's OBB
}

}  // namespace
}  // namespace caustix::bake

namespace caustix::bake {
namespace {

TEST_F(LevelMapTest, BoxesOfFlatObjectsAreOrthonormal) {
  // A tilted plane: CGAL's box has one edge of (nearly) zero length.
  for (const char* rot : {"[0, 0, 20]", "[33, 10, 71]", "[0, 0, 0]"}) {
    auto r = bake(pool_scene(R"({"name": "ramp", "mesh": ")" + kMeshes + R"(plane.obj", "transform": {"rotate_deg": )" +
                                 rot + R"(, "scale": [3, 1, 2]}})",
                             sun(0, -1, 0)));
    ASSERT_TRUE(r.ok()) << r.error().message;
    auto c = cxb::read_container(r->cxb.data(), r->cxb.size());
    ASSERT_TRUE(c.ok());
    auto d = decode_scene(*c);
    ASSERT_TRUE(d.ok()) << rot << ": " << d.error().message;
    // Every in-plane rotation of a planar set has zero volume, so the box
    // need not be the tight rectangle; it must be flat and contain the plane.
    const ObjectBox& b = d->boxes.at(0);
    EXPECT_LT(std::min({b.half[0], b.half[1], b.half[2]}), 1e-4) << rot;
    EXPECT_GE(std::max({b.half[0], b.half[1], b.half[2]}), 1.5 - 1e-3) << rot;
    const Mat4f& t = d->scene.objects[0].transform;
    for (const auto& corner : {std::array<float, 2>{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}}) {
      const Vec3d p{t[0] * corner[0] + t[8] * corner[1] + t[12], t[1] * corner[0] + t[9] * corner[1] + t[13],
                    t[2] * corner[0] + t[10] * corner[1] + t[14]};
      for (std::size_t a = 0; a < 3; ++a) {
        const double c = (p[0] - b.center[0]) * b.axes[a][0] + (p[1] - b.center[1]) * b.axes[a][1] +
                         (p[2] - b.center[2]) * b.axes[a][2];
        EXPECT_LE(std::fabs(c), b.half[a] + 1e-4) << rot << " axis " << a;
      }
    }
  }
}

}  // namespace
}  // namespace caustix::bake
