// Variance shadow maps (timofy 2009, Donnelly & Lauritzen 2006)
// against PCF and geometry: a unit box on a floor under a sun at 45 degrees
// takes E0 cos 45 from its footprint and the 1 m^2 its shadow covers, and
// no more whichever filter draws it (a box filter of a step keeps its area,
// and Chebyshev's bound is exact for one planar occluder over a planar
// receiver); the lit floor keeps E0 cos 45 exactly and the umbra is dark;
// the penumbra widens with the filter width; absurd knobs are refused.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <vector>

#include "bake_fixture.h"
#include "caustix/sample/renderer.h"
#include "gl_fixture.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

nlohmann::json box_scene() {
  const std::string meshes = test::kScenes + "../meshes/";
  return {{"name", "vsm_box"},
          {"objects",
           {{{"name", "floor"}, {"mesh", meshes + "plane.obj"}, {"material", {{"albedo", 0.8}}}, {"transform", {{"scale", {5, 1, 5}}}}},
            {{"name", "box"}, {"mesh", meshes + "box.obj"}, {"transform", {{"translate", {0, 0.5, 0}}}}}}},
          {"lights", {{{"type", "directional"}, {"direction", {1, -1, 0}}, {"irradiance", 1.0}}}},
          {"camera", {{"position", {0, 6, 0.01}}, {"target", {0, 0, 0}}}}};
}

class Shadows : public test::GlTest {
 protected:
  void SetUp() override {
    test::GlTest::SetUp();
    auto scene = test::bake_and_load(test::write_scene(box_scene(), "shadow_test"));
    ASSERT_TRUE(scene.has_value());
    auto r = sample::Renderer::create(*scene);
    ASSERT_TRUE(r.ok()) << r.error().message;
    renderer_ = std::move(*r);
  }
  // Floor irradiance / E0 over [x0, x1] x [z0, z1], w x h pixels.
  std::vector<float> floor(const runtime::ShadowOptions& so, float x0, float x1, float z0, float z1, int w, int h) {
    sample::IrradianceRequest q;
    q.receiver = "floor";
    q.x0 = x0;
    q.x1 = x1;
    q.z0 = z0;
    q.z1 = z1;
    q.width = w;
    q.height = h;
    q.caustics.shadows = so;
    auto img = renderer_->render_irradiance(q);
    EXPECT_TRUE(img.ok()) << img.error().message;
    std::vector<float> e;
    if (!img.ok()) return e;
    for (std::size_t i = 0; i < img->rgb.size(); i += 3) e.push_back(img->rgb[i]);
    return e;
  }
  std::unique_ptr<sample::Renderer> renderer_;
};

runtime::ShadowOptions vsm(std::uint32_t width) {
  runtime::ShadowOptions so;
  so.filter = runtime::ShadowFilter::kVsm;
  so.vsm_filter = width;
  return so;
}

// 10-90 % width of the shadow's far edge (x = 1.5) along a strip, metres.
double penumbra(const std::vector<float>& e, double x0, double pix, double lit) {
  double a = -1, b = -1;
  for (std::size_t i = 0; i < e.size(); ++i) {
    const double x = x0 + (static_cast<double>(i) + 0.5) * pix;
    if (a < 0 && e[i] > 0.1 * lit) a = x;
    if (b < 0 && e[i] > 0.9 * lit) b = x;
  }
  return b - a;
}

TEST_F(Shadows, VarianceShadowMapsKeepTheShadowsAreaAndSoftenItsEdge) {
  const double lit = std::sqrt(0.5);  // E0 cos 45
  const float half = 2.4f;
  const int n = 240;  // 2 cm pixels; the box's and shadow's edges on pixel boundaries
  const double pix = 2.0 * half / n;
  auto deficit = [&](const std::vector<float>& e) {
    double d = 0;
    for (float v : e) d += (lit - v) * pix * pix;
    return d / lit;  // m^2 of full shadow
  };
  const std::vector<float> pcf = floor(runtime::ShadowOptions{}, -half, half, -half, half, n, n);
  for (std::uint32_t width : {1u, 5u, 21u}) {
    const std::vector<float> e = floor(vsm(width), -half, half, -half, half, n, n);
    ASSERT_EQ(e.size(), pcf.size());
    std::printf("[vsm %u] shadow area %.4f m^2 (PCF %.4f, exact 2: footprint and shadow)\n", width, deficit(e), deficit(pcf));
    EXPECT_NEAR(deficit(e), 2.0, 0.04) << "filter " << width;
    // Lit floor away from the shadow, and the umbra's middle.
    EXPECT_NEAR(e[static_cast<std::size_t>(n / 2) * n + 20], lit, 1e-3 * lit);
    EXPECT_LT(e[static_cast<std::size_t>(n / 2) * n + static_cast<std::size_t>((1.0 + half) / pix)], 0.02 * lit);
  }
  EXPECT_NEAR(deficit(pcf), 2.0, 0.04);

  // The far edge of the shadow, 2 mm pixels.
  const float sx0 = 1.3f, sx1 = 1.7f;
  const int sw = 200;
  const double spix = (sx1 - sx0) / sw;
  double last = 0;
  for (std::uint32_t width : {1u, 5u, 21u}) {
    const std::vector<float> strip = floor(vsm(width), sx0, sx1, -0.01f, 0.01f, sw, 1);
    const double p = penumbra(strip, sx0, spix, lit);
    std::printf("[vsm %u] penumbra 10-90 %%: %.1f mm\n", width, 1e3 * p);
    EXPECT_GT(p, last) << "filter " << width;
    last = p;
  }
  const double p1 = penumbra(floor(vsm(1), sx0, sx1, -0.01f, 0.01f, sw, 1), sx0, spix, lit);
  EXPECT_GT(last, 4 * p1) << "a 21-texel filter softens the edge";
}

TEST_F(Shadows, AbsurdVsmKnobsAreRefusedByName) {
  for (int k = 0; k < 3; ++k) {
    runtime::ShadowOptions so = vsm(5);
    if (k == 0) so.vsm_filter = 4;
    if (k == 1) so.vsm_filter = 65;
    if (k == 2) so.vsm_bleeding = std::nanf("");
    sample::IrradianceRequest q;
    q.receiver = "floor";
    q.width = q.height = 8;
    q.caustics.shadows = so;
    auto img = renderer_->render_irradiance(q);
    ASSERT_FALSE(img.ok()) << k;
    EXPECT_EQ(img.error().code, ErrorCode::kUsage);
    EXPECT_NE(img.error().message.find(k == 2 ? "vsm_bleeding" : "vsm_filter"), std::string::npos) << img.error().message;
  }
}

}  // namespace
}  // namespace caustix
