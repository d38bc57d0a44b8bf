// Spot lights (KHR_lights_punctual's cone): a spot light is a
// point light whose intensity towards a direction is its own times the
// specification's falloff, t^2 with t = clamp((cos a - cos outer) / (cos
// inner - cos outer), 0, 1), a the angle from the axis. The oracle is that
// falloff written here from the angles, evaluated along the light's real
// path (Snell at flat water, solved here), and the same scene lit by the
// point light without a cone: the spot's image over the point's is the
// falloff wherever the point light arrives -- on a bare floor, through
// water by the level map, through a glass ball by its tables and by caustic
// maps -- and the reference tracer's the same.

#include <gtest/gtest.h>

#include "bake_fixture.h"
#include "gl_fixture.h"
#include "optics_oracle.h"
#include "scene_fixture.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>

#include "caustix/bake/bake.h"
#include "caustix/sample/renderer.h"

namespace caustix {
namespace {

using runtime::CausticsMethod;
using sample::IrradianceRequest;
using test::kPi;
using V3 = std::array<double, 3>;

V3 unit(V3 v) {
  const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / l, v[1] / l, v[2] / l};
}
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

struct Spot {
  V3 position, axis;
  double inner_deg, outer_deg, intensity = 16;
  // The falloff towards unit direction d (away from the light).
  double factor(const V3& d) const {
    const double co = std::cos(outer_deg * kPi / 180), ci = std::cos(inner_deg * kPi / 180);
    const double t = std::clamp((dot(d, axis) - co) / (ci - co), 0.0, 1.0);
    return t * t;
  }
  nlohmann::json json(bool cone) const {
    nlohmann::json l{{"type", cone ? "spot" : "point"}, {"position", position}, {"intensity", intensity}};
    if (cone) {
      l["direction"] = axis;
      l["inner_cone_deg"] = inner_deg;
      l["outer_cone_deg"] = outer_deg;
    }
    return nlohmann::json::array({l});
  }
};

class SpotLight : public test::GlTest {
 protected:
  // The floor's irradiance under the scene lit by `s`, with and without its cone.
  std::pair<std::vector<float>, std::vector<float>> images(nlohmann::json j, const Spot& s, IrradianceRequest q,
                                                           const bake::BakeOptions& opt = {}) {
    std::vector<float> out[2];
    for (int cone = 0; cone < 2; ++cone) {
      j["lights"] = s.json(cone == 1);
      auto r = test::bake_and_create(test::write_scene(j, "spot_light_test"), opt);
      if (!r) return {};
      auto img = r->render_irradiance(q);
      EXPECT_TRUE(img.ok()) << img.error().message;
      if (!img.ok()) return {};
      for (float v : img->rgb) EXPECT_TRUE(std::isfinite(v));
      out[cone] = img->rgb;
    }
    return {std::move(out[1]), std::move(out[0])};
  }
  static V3 pixel(const IrradianceRequest& q, int i, int k) {
    return {q.x0 + (q.x1 - q.x0) * (i + 0.5) / q.width, 0.0, q.z0 + (q.z1 - q.z0) * (k + 0.5) / q.height};
  }
};

// A bare floor: the include's direct light, exact per fragment.
TEST_F(SpotLight, BareFloorIsThePointLightTimesTheFalloff) {
  nlohmann::json j = test::canonical_scene("flat_pool");
  j.erase("water");
  const Spot s{{0.4, 4.0, -0.3}, unit({0.15, -1.0, 0.1}), 12, 20};
  IrradianceRequest q{"floor", -2, -2, 2, 2, 64, 64, 0.0f, {}};
  q.pixel_samples = 1;
  const auto [spot, point] = images(j, s, q);
  ASSERT_EQ(spot.size(), point.size());
  ASSERT_FALSE(spot.empty());
  double worst = 0;
  int inside = 0, outside = 0;
  for (int k = 0; k < q.height; ++k) {
    for (int i = 0; i < q.width; ++i) {
      const V3 p = pixel(q, i, k);
      const double f = s.factor(unit({p[0] - s.position[0], p[1] - s.position[1], p[2] - s.position[2]}));
      const std::size_t at = 3 * (static_cast<std::size_t>(k) * q.width + i);
      ASSERT_GT(point[at], 0.0f);
      worst = std::max(worst, std::fabs(double{spot[at]} / point[at] - f));
      inside += f == 1.0;
      outside += f == 0.0;
    }
  }
  std::printf("[spot] bare floor: worst |spot/point - falloff| %.2e over %d px inside, %d outside\n", worst, inside, outside);
  EXPECT_LT(worst, 2e-3) << "spot / point against the falloff";
  EXPECT_GT(inside, 100);  // the floor holds all three parts of the cone
  EXPECT_GT(outside, 100);
}

// Flat water (level map): the falloff along the refracted path's air part,
// found here by Snell's law, per water triangle; a 256-cell water grid
// quantises the direction by 1.6 cm at the surface.
TEST_F(SpotLight, ThroughFlatWaterTheFalloffFollowsTheRefractedPath) {
  nlohmann::json j = test::canonical_scene("flat_pool");
  j["water"]["grid"]["cells"] = {256, 256};
  const Spot s{{0.3, 4.0, 0.2}, unit({0.1, -1.0, -0.05}), 10, 22};
  IrradianceRequest q{"floor", -2, -2, 2, 2, 48, 48, 0.0f, {}};
  q.caustics.method = CausticsMethod::kLevelMap;
  const auto [spot, point] = images(j, s, q);
  ASSERT_FALSE(spot.empty());
  const double n = 1.33, h_air = 4.0 - 2.0, depth = 2.0;
  double sum_spot = 0, sum_oracle = 0, worst_in = 0, worst_out = 0;
  for (int k = 0; k < q.height; ++k) {
    for (int i = 0; i < q.width; ++i) {
      const V3 p = pixel(q, i, k);
      const double dx = p[0] - s.position[0], dz = p[2] - s.position[2], D = std::hypot(dx, dz);
      // Entry point at horizontal distance r from the light's foot:
      // sin(a1) = n sin(a2), r = h_air tan a1, D - r = depth tan a2.
      double lo = 0, hi = D;
      for (int it = 0; it < 60; ++it) {
        const double r = 0.5 * (lo + hi);
        const double s1 = r / std::hypot(r, h_air), s2 = (D - r) / std::hypot(D - r, depth);
        (s1 > n * s2 ? hi : lo) = r;
      }
      const double r = 0.5 * (lo + hi), u = D > 0 ? r / D : 0;
      const double f = s.factor(unit({u * dx, -h_air, u * dz}));
      const std::size_t at = 3 * (static_cast<std::size_t>(k) * q.width + i);
      sum_spot += spot[at];
      sum_oracle += f * point[at];
      // Away from the falloff's edges by more than the water grid's step.
      const double c = dot(unit({u * dx, -h_air, u * dz}), s.axis);
      if (c > std::cos((s.inner_deg - 1) * kPi / 180)) worst_in = std::max(worst_in, std::fabs(double{spot[at]} / point[at] - 1));
      if (c < std::cos((s.outer_deg + 1) * kPi / 180)) worst_out = std::max(worst_out, double(spot[at] / point[at]));
    }
  }
  std::printf("[spot] flat water, level map: inside %.2e, outside %.2e, power / oracle %.4f\n", worst_in, worst_out, sum_spot / sum_oracle);
  EXPECT_LT(worst_in, 0.01) << "inside the inner cone the spot is the point light";
  EXPECT_LT(worst_out, 1e-3) << "outside the outer cone it is dark";
  EXPECT_NEAR(sum_spot / sum_oracle, 1.0, 0.01) << "power on the floor against the falloff along Snell's path";
}

// Water cells wider than the cone (wavy_pool's 3 m cells across its waves
// put every cell's centre outside a 0.7 m cone, and the level map's floor
// went dark): each water triangle takes its falloff averaged over itself,
// so the level map's power on the floor stays the photon splats' (which
// take it per photon) within what a cell's single Fresnel and cosine cost.
TEST_F(SpotLight, WaterCellsWiderThanTheConeKeepItsPower) {
  const Spot s{{0.3, 4.0, 0.2}, unit({0.1, -1.0, -0.05}), 10, 22};
  for (const auto& cells : {std::array<int, 2>{8, 8}, std::array<int, 2>{48, 4}}) {
    nlohmann::json j = test::canonical_scene("flat_pool");
    j["water"]["grid"]["cells"] = cells;
    j["lights"] = s.json(true);
    auto r = test::bake_and_create(test::write_scene(j, "spot_light_cells"));
    ASSERT_TRUE(r);
    double power[2] = {0, 0};
    for (int m = 0; m < 2; ++m) {
      IrradianceRequest q{"floor", -6, -6, 6, 6, 96, 96, 0.0f, {}};
      q.caustics.method = m == 0 ? CausticsMethod::kLevelMap : CausticsMethod::kSplat;
      auto img = r->render_irradiance(q);
      ASSERT_TRUE(img.ok()) << img.error().message;
      for (std::size_t i = 0; i < img->rgb.size(); i += 3) power[m] += img->rgb[i];
    }
    std::printf("[spot] %d x %d water cells: level map / splat power %.4f\n", cells[0], cells[1], power[0] / power[1]);
    EXPECT_NEAR(power[0] / power[1], 1.0, 0.05);  // before: 1.083 at 8 x 8, 0 at 48 x 4
  }
}

// A glass ball in the falloff: the light through it, by tables and by caustic
// maps, is the point light's times the falloff averaged over the ball's
// disc seen from the light (each entry direction's own factor), and dark
// where the cone does not reach.
TEST_F(SpotLight, GlassBallInTheFalloffByTablesAndCausticMaps) {
  const nlohmann::json j = test::canonical_scene("glass_ball");
  const V3 lp{0.0, 6.0, 0.0}, ball{0.0, 0.75, 0.0};
  // The ball (5.4 degrees across from the light) 17 degrees off the axis,
  // inside a 10-25 degree falloff.
  const double tilt = 17 * kPi / 180;
  const Spot s{lp, unit({std::sin(tilt), -std::cos(tilt), 0.0}), 10, 25};
  // The oracle: the falloff's mean over the ball's disc (uniform flux per
  // area of the disc at this distance), by quadrature.
  const V3 to_ball = unit({ball[0] - lp[0], ball[1] - lp[1], ball[2] - lp[2]});
  const V3 e1{1, 0, 0}, e2 = unit({0, to_ball[2], -to_ball[1]});
  double mean = 0, count = 0;
  for (int a = 0; a < 200; ++a) {
    for (int b = 0; b < 200; ++b) {
      const double x = (a + 0.5) / 100 - 1, y = (b + 0.5) / 100 - 1;
      if (x * x + y * y > 1) continue;
      const V3 q{ball[0] + 0.5 * (x * e1[0] + y * e2[0]) - lp[0], ball[1] + 0.5 * (x * e1[1] + y * e2[1]) - lp[1],
                 ball[2] + 0.5 * (x * e1[2] + y * e2[2]) - lp[2]};
      mean += s.factor(unit(q));
      count += 1;
    }
  }
  mean /= count;
  ASSERT_GT(mean, 0.15);
  ASSERT_LT(mean, 0.85);
  bake::BakeOptions opt;
  opt.transport.resolution = 16;
  for (auto method : {runtime::GlassMethod::kTable, runtime::GlassMethod::kCausticMap}) {
    SCOPED_TRACE(runtime::to_string(method));
    IrradianceRequest q{"floor", -0.55f, -0.55f, 0.55f, 0.55f, 64, 64, 0.0f, {}};
    q.caustics.glass_method = method;
    const auto [spot, point] = images(j, s, q, opt);
    ASSERT_FALSE(spot.empty());
    // The ball's shadow on the floor (0.57 m across from this light; within
    // 0.5 m of the axis) holds only light through the glass: its power.
    double ps = 0, pp = 0;
    for (int k = 0; k < q.height; ++k) {
      for (int i = 0; i < q.width; ++i) {
        const V3 p = pixel(q, i, k);
        if (std::hypot(p[0], p[2]) > 0.5) continue;
        const std::size_t at = 3 * (static_cast<std::size_t>(k) * q.width + i);
        ps += spot[at];
        pp += point[at];
      }
    }
    ASSERT_GT(pp, 0);
    std::printf("[spot] glass ball, %s: power ratio %.4f, falloff over the ball %.4f\n", runtime::to_string(method), ps / pp, mean);
    EXPECT_NEAR(ps / pp, mean, 0.01 * mean) << "glass light under the spot against the falloff over the ball";
  }
}

}  // namespace
}  // namespace caustix
