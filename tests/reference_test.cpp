// The reference photon tracer against physics: flat water gives
// T(theta) cos(theta) within its own noise estimate; doubling the light
// doubles every pixel; seeded runs are reproducible whatever the thread
// count; a sine wave conserves energy.

#include <gtest/gtest.h>

#include "media_oracle.h"
#include "optics_oracle.h"
#include "scene_fixture.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "caustix/formats/spectrum.h"
#include "reference.h"

namespace caustix::reference {
namespace {

using test::kScenes;
using test::fresnel_t;
using test::kPi;
using test::Landing;
using test::ball_lens;
using test::radius_enclosing;

// Mean of the image and the standard error of that mean (from the batches).
std::pair<double, double> mean_and_error(const Image& img) {
  double sum = 0, var = 0;
  const std::size_t n = img.sigma.size();
  for (std::size_t i = 0; i < n; ++i) {
    sum += img.rgb[3 * i + 1];
    var += double(img.sigma[i]) * img.sigma[i];
  }
  return {sum / n, std::sqrt(var) / n};
}

TEST(Reference, FlatPoolMatchesFresnelWithinItsNoise) {
  Request q{kScenes + "flat_pool.json", "floor", -2, -2, 2, 2, 32, 32, 0, 2'000'000, 8, 7};
  auto img = trace(q);
  ASSERT_TRUE(img.ok()) << img.error().message;
  const double expected = fresnel_t(std::cos(30 * kPi / 180), 1.33) * std::cos(30 * kPi / 180);
  const auto [mean, err] = mean_and_error(*img);
  EXPECT_LT(img->relative_noise, 0.1);
  EXPECT_NEAR(mean, expected, 4 * err + 1e-9) << "mean " << mean << " +- " << err;
  ::testing::Test::RecordProperty("flat_pool_reference_mean", std::to_string(mean));
}

TEST(Reference, DoublingTheLightDoublesEveryPixelAndRunsRepeat) {
  nlohmann::json j = test::canonical_scene("flat_pool");
  j["water"]["waves"] = {{{"amplitude", 0.05}, {"wavelength", 0.8}, {"direction", {1, 0.3}}}};
  const std::string path = test::write_scene(j, "reference_test");
  Request q{path, "floor", -1, -1, 1, 1, 16, 16, 0.5, 200'000, 4, 3};
  auto one = trace(q);
  ASSERT_TRUE(one.ok()) << one.error().message;
  j["lights"][0]["color"] = {2, 2, 2};  // twice the light, same E0 for the normalisation
  test::write_scene(j, "reference_test");
  auto two = trace(q);
  ASSERT_TRUE(two.ok());
  for (std::size_t i = 0; i < one->rgb.size(); ++i) EXPECT_FLOAT_EQ(two->rgb[i], 2 * one->rgb[i]);
  j["lights"][0]["color"] = {1, 1, 1};
  test::write_scene(j, "reference_test");
  std::vector<float> single;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    auto again = trace(q);
    ASSERT_TRUE(again.ok());
    single = again->rgb;
  }
  EXPECT_EQ(single, one->rgb) << "seeded runs must repeat exactly, on 1 thread or more";
}

TEST(Reference, WavyPoolConservesEnergy) {
  Request q{kScenes + "wavy_pool.json", "floor", 0, -0.05, 4, 0.05, 128, 2, 0, 4'000'000, 8, 11};
  auto img = trace(q);
  ASSERT_TRUE(img.ok()) << img.error().message;
  const auto [mean, err] = mean_and_error(*img);
  EXPECT_NEAR(mean, fresnel_t(1.0, 1.33), 4 * err + 0.005) << "mean " << mean << " +- " << err;
}

TEST(Reference, RefusesWhatItCannotTrace) {
  Request q{kScenes + "flat_pool.json", "nosuch", -1, -1, 1, 1, 8, 8, 0, 1000, 4, 1};
  EXPECT_FALSE(trace(q).ok());
  q.receiver = "floor";
  q.batches = 0;
  EXPECT_FALSE(trace(q).ok());
  Request glass{kScenes + "glass_ball.json", "ball", -1, -1, 1, 1, 8, 8, 0, 1000, 4, 1};
  auto r = trace(glass);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("not a receiver"), std::string::npos) << r.error().message;
}

// Without water the photons start above the highest object, over the
// region projected back along the light: a slanted sun on a bare floor
// lights every pixel with cos(theta), edges included.
TEST(Reference, SlantedSunOnABareFloorIsUniform) {
  nlohmann::json j = test::canonical_scene("glass_ball");
  j["objects"].erase(1);
  j["lights"][0]["direction"] = {0.35, -1, 0.2};
  Request q{test::write_scene(j, "reference_bare_floor"), "floor", -1.5, -1.5, 1.5, 1.5, 12, 12, 0, 400'000, 8, 9};
  auto img = trace(q);
  ASSERT_TRUE(img.ok()) << img.error().message;
  const double cos_theta = 1 / std::sqrt(0.35 * 0.35 + 1 + 0.2 * 0.2);
  // Against the pooled noise (mean standard error over pixels): the
  // per-pixel estimate from 8 batches is itself too noisy to divide by.
  double worst = 0;
  for (std::size_t p = 0; p < img->sigma.size(); ++p) worst = std::max(worst, std::fabs(img->rgb[3 * p + 1] / cos_theta - 1));
  const auto [mean, err] = mean_and_error(*img);
  std::printf("[reference bare floor] mean %.4f +- %.4f vs cos theta %.4f; worst pixel %.3f off (relative noise %.3f)\n", mean,
              err, cos_theta, worst, img->relative_noise);
  EXPECT_NEAR(mean, cos_theta, 4 * err);
  EXPECT_LT(worst, 5 * img->relative_noise);  // 144 pixels: 5 sigma is a 1-in-10^4 event for each
}

// A spot light over a bare floor: each pixel is the pixel's mean
// of I f(a) cos(theta) / r^2, f KHR_lights_punctual's falloff written here
// from the angles (tests/spot_light_test.cpp has the runtime's).
TEST(Reference, SpotLightOnABareFloorIsTheFalloffTimesTheInverseSquare) {
  nlohmann::json j = test::canonical_scene("glass_ball");
  j["objects"].erase(1);
  const double lp[3] = {0.2, 3.0, -0.1}, axis_len = std::sqrt(0.2 * 0.2 + 1.0);
  const double axis[3] = {0.2 / axis_len, -1.0 / axis_len, 0.0};
  j["lights"] = {{{"type", "spot"}, {"position", {lp[0], lp[1], lp[2]}}, {"direction", {axis[0], axis[1], axis[2]}},
                  {"intensity", 9.0}, {"inner_cone_deg", 15}, {"outer_cone_deg", 30}}};
  Request q{test::write_scene(j, "reference_spot"), "floor", -2, -2, 2, 2, 16, 16, 0, 1'600'000, 32, 5};
  auto img = trace(q);
  ASSERT_TRUE(img.ok()) << img.error().message;
  const double co = std::cos(30 * kPi / 180), ci = std::cos(15 * kPi / 180);
  double worst = 0, sum = 0, sum_expected = 0, var = 0;
  for (int row = 0; row < 16; ++row) {
    for (int col = 0; col < 16; ++col) {
      double expected = 0;
      for (int a = 0; a < 16; ++a) {
        for (int b = 0; b < 16; ++b) {
          const double x = -2 + (col + (a + 0.5) / 16) * 0.25, z = -2 + (row + (b + 0.5) / 16) * 0.25;
          const double d[3] = {x - lp[0], -lp[1], z - lp[2]};
          const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], r = std::sqrt(r2);
          const double t = std::clamp(((d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2]) / r - co) / (ci - co), 0.0, 1.0);
          expected += 9.0 * t * t * (lp[1] / r) / r2 / 256;
        }
      }
      const std::size_t i = std::size_t(row) * 16 + std::size_t(col);
      const double got = img->rgb[3 * i + 1], sigma = img->sigma[i];
      sum += got;
      sum_expected += expected;
      var += sigma * sigma;
      worst = std::max(worst, std::fabs(got - expected) / std::max(sigma, 1e-4));
    }
  }
  std::printf("[reference spot] power %.4f vs %.4f (+- %.4f); worst pixel %.2f sigma\n", sum, sum_expected, std::sqrt(var), worst);
  EXPECT_NEAR(sum, sum_expected, 4 * std::sqrt(var));
  // Each pixel's sigma comes from 32 batches (Student's t, 31 degrees of
  // freedom): 5.5 of them is a 1-in-10^5 event per pixel.
  EXPECT_LT(worst, 5.5);
}

// The ball lens of glass_ball (radius 0.5, centre 0.75, n = 1.5, light
// straight down) against the exact 2-D trace: the flux landing within
// 0.3 m of the axis (all inside the ball's shadow, so all of it came
// through the glass) and the radius holding half of it. The reference
// also follows internal reflections, which the 2-D trace leaves out; near
// the axis they leave upward, so they add nothing here.
TEST(Reference, GlassBallFocusesWhereTheBallLensFormulaDoes) {
  const double half = 0.3;
  const int n = 60;  // 1 cm pixels
  Request q{kScenes + "glass_ball.json", "floor", -half, -half, half, half, n, n, 0, 1'500'000, 8, 5};
  auto img = trace(q);
  ASSERT_TRUE(img.ok()) << img.error().message;
  const double pix = 2 * half / n;
  double flux = 0, flux_var = 0;
  std::vector<Landing> measured;
  std::size_t peak = 0;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < n; ++k) {
      const std::size_t p = static_cast<std::size_t>(i) * n + k;
      const double rho = std::hypot(-half + (k + 0.5) * pix, -half + (i + 0.5) * pix);
      if (img->rgb[3 * p + 1] > img->rgb[3 * peak + 1]) peak = p;
      if (rho >= half) continue;
      flux += img->rgb[3 * p + 1] * pix * pix;
      flux_var += std::pow(img->sigma[p] * pix * pix, 2);
      measured.push_back({rho, img->rgb[3 * p + 1] * pix * pix});
    }
  }
  std::vector<Landing> near;
  double expected = 0;
  for (const Landing& l : ball_lens(0.5, 0.75, 1.5, 20000)) {
    if (l.rho < half) {
      near.push_back(l);
      expected += l.weight;
    }
  }
  const double r50 = radius_enclosing(near, 0.5), m50 = radius_enclosing(measured, 0.5);
  const double px = -half + (peak % n + 0.5) * pix, pz = -half + (peak / n + 0.5) * pix;
  std::printf("[reference glass_ball] flux within %.1f m: %.5f +- %.5f vs %.5f exact; R50 %.4f vs %.4f m; peak E/E0 %.0f at "
              "(%.3f, %.3f); relative noise %.3f\n",
              half, flux, std::sqrt(flux_var), expected, m50, r50, img->rgb[3 * peak + 1], px, pz, img->relative_noise);
  // 1 % for the disc's pixelated edge (pixels straddling rho = 0.3 are in
  // or out whole; the exact trace puts 1.35 % of the disc's flux within one
  // pixel of the edge, and pixels in and out cancel to first order) plus
  // 4 sigma of the reference's own noise.
  EXPECT_NEAR(flux / expected, 1.0, 0.01 + 4 * std::sqrt(flux_var) / expected);
  EXPECT_NEAR(m50, r50, std::max(1.5 * pix, 0.05 * r50));
  EXPECT_LT(std::hypot(px, pz), 1.5 * pix);
}

// The reference on a fine sphere (sphere_fine.obj, 8 066
// vertices, as glass_ball's ball) agrees with the exact sphere where the
// light concentrates, so that it can judge what the oracle cannot reach:
// the power within 1, 2 and 5 cm of the focus in 1 mm pixels, both sides
// in the same pixels (optics_oracle.h), within 4 sigma of the reference's
// own noise plus 0.5 % for the mesh's facets. 40 M photons over +-5.1 cm
// in 0.5 mm pixels measured -0.40, -0.37, -0.22, -0.06 % within 0.5, 1, 2,
// 5 cm and the brightest 2 mm pixel 7 075 against 7 151 E0 (docs/glass-focus.md).
TEST(Reference, FineSphereFocusAgreesWithOptics) {
  const int n = 102;
  const double x0 = -0.051, pix = 0.001;
  nlohmann::json j = test::canonical_scene("glass_ball");
  j["objects"][1]["mesh"] = kScenes + "../meshes/sphere_fine.obj";
  Request q{test::write_scene(j, "reference_fine_ball"), "floor", x0, x0, x0 + n * pix, x0 + n * pix, n, n, 0, 1'500'000, 8, 5};
  auto img = trace(q);
  ASSERT_TRUE(img.ok()) << img.error().message;
  std::vector<double> e, var;  // irradiance and its variance per pixel
  for (std::size_t i = 0; i < static_cast<std::size_t>(n) * n; ++i) {
    e.push_back(img->rgb[3 * i + 1]);
    var.push_back(std::pow(img->sigma[i], 2));
  }
  const auto want = test::landing_image(ball_lens(0.5, 0.75, 1.5, 20000), n, x0, pix);
  for (const double radius : {0.01, 0.02, 0.05}) {
    // The power's variance: the sum of (sigma pix^2)^2 over the same pixels.
    const double got = test::power_within(e, n, x0, pix, radius);
    const double w = test::power_within(want, n, x0, pix, radius);
    const double sigma = std::sqrt(test::power_within(var, n, x0, pix, radius) * pix * pix) / w;
    std::printf("[reference, fine ball] power within %.2f m: %.5f vs %.5f optics (%+.2f %%, sigma %.2f %%)\n", radius, got, w,
                100 * (got / w - 1), 100 * sigma);
    EXPECT_NEAR(got / w, 1.0, 0.005 + 4 * sigma) << "within " << radius << " m";
  }
}

// --- media ---------------------------------------------------------

using test::fog_box;
using test::fog_pixel;

TEST(ReferenceMedia, FogWithoutObjectsIsTheAnalyticIntegral) {
  const double ss = 0.5, sa = 0.25, st = ss + sa;
  const std::string path = test::write_scene(fog_box(ss, sa), "reference_fog");
  InscatterRequest q;
  q.scene_path = path;
  q.x0 = -1.5, q.y0 = -0.5, q.x1 = 1.5, q.y1 = 2.5;
  q.width = 24, q.height = 24;
  q.photons = 400'000;
  InscatterStats stats;
  auto img = trace_inscatter(q, &stats);
  ASSERT_TRUE(img.ok()) << img.error().message;
  const std::vector<double> want = test::fog_box_image(ss, st, q.x0, q.y0, q.x1, q.y1, 24, 24);
  double worst = 0;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const double expected = want[i], got = img->rgb[3 * i + 1];
    // Within four standard errors, plus float rounding.
    EXPECT_NEAR(got, expected, 4 * img->sigma[i] + 1e-6 * expected) << "row " << i / 24 << " col " << i % 24;
    if (expected > 0) worst = std::max(worst, std::fabs(got / expected - 1));
  }
  EXPECT_LT(img->relative_noise, 0.02);
  ::testing::Test::RecordProperty("fog_worst_relative_error", std::to_string(worst));
  // Energy: every photon enters the box's top (4 m^2 at E0) and goes
  // straight down, so the split is exact: sigma_s / sigma_t of what the
  // box takes scattered, the rest absorbed, e^(-2 sigma_t) leaving.
  const double taken = 4 * (1 - std::exp(-2 * st));
  EXPECT_NEAR(stats.power_in, 4.0, 1e-9);
  EXPECT_NEAR(stats.scattered, taken * ss / st, 1e-9);
  EXPECT_NEAR(stats.absorbed, taken * sa / st, 1e-9);
  EXPECT_NEAR(stats.leaving, 4 * std::exp(-2 * st), 1e-9);
  EXPECT_NEAR(stats.power_in, stats.scattered + stats.absorbed + stats.leaving, 1e-9);
}

// Schlick with k = 0 is the isotropic image; with k the image scales by
// p_k(cos a) / p_0 = 1 - k^2 (cos a = 0: light down, camera along z). The
// same seed traces the same photons, so the ratio is exact.
TEST(ReferenceMedia, SchlickPhaseScalesAsThePhaseFunction) {
  auto image = [](const nlohmann::json& j) {
    InscatterRequest q;
    q.scene_path = test::write_scene(j, "reference_phase");
    q.width = q.height = 12;
    q.x0 = -1, q.y0 = 0, q.x1 = 1, q.y1 = 2;
    q.photons = 20'000;
    q.batches = 2;
    auto img = trace_inscatter(q);
    EXPECT_TRUE(img.ok()) << img.error().message;
    return img.ok() ? img->rgb : std::vector<float>{};
  };
  test::expect_schlick_scaling(image, 1e-5);

  // Nothing scatters: refused, with the reason.
  const nlohmann::json j = fog_box(0.0, 0.0);
  InscatterRequest q;
  q.scene_path = test::write_scene(j, "reference_phase");
  auto none = trace_inscatter(q);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("nothing in the scene scatters"), std::string::npos) << none.error().message;
}

// fog_ball: the bright cone below the ball peaks on the axis between the
// paraxial focus (the ball-lens formula) and where rays entering at 0.95 of
// the radius cross it (spherical aberration; past 0.95 r the Fresnel
// transmittance falls steeply), far above the plain fog.
TEST(ReferenceMedia, FogBallConeConvergesToTheBallLensFocus) {
  InscatterRequest q;
  q.scene_path = kScenes + "fog_ball.json";
  q.x0 = -0.5, q.y0 = 0, q.x1 = 0.5, q.y1 = 1.0;
  q.width = 20, q.height = 100;
  q.photons = 400'000;
  q.batches = 4;
  auto img = trace_inscatter(q);
  ASSERT_TRUE(img.ok()) << img.error().message;
  // Brightest pixel of the two middle columns below the ball.
  int best = -1;
  double best_value = 0;
  for (int row = 0; row < 100; ++row) {
    for (int col = 9; col <= 10; ++col) {
      const double v = img->rgb[3 * (std::size_t(row) * 20 + std::size_t(col)) + 1];
      if (v > best_value) {
        best_value = v;
        best = row;
      }
    }
  }
  const double y_peak = 1.0 - (best + 0.5) * 0.01;
  const double paraxial = 1.25 - 1.5 * 0.5 / (2 * 0.5);
  const double marginal = test::axis_crossing(0.5, 1.25, 1.5, 0.475);
  EXPECT_GT(y_peak, paraxial - 0.01) << "peak at y " << y_peak;
  EXPECT_LT(y_peak, marginal) << "peak at y " << y_peak << ", 0.95-radius rays cross at " << marginal;
  // Plain fog, unshadowed, at y = 1 (its view path is 1.5 m of fog): the
  // cone's peak is several times brighter.
  const double st = 0.3;
  const double fog = 0.3 / (4 * kPi) * std::exp(-st * 1.5) * (1 - std::exp(-3 * st)) / st;
  EXPECT_GT(best_value, 2 * fog);  // 3.4x with 5 cm wide pixels
  ::testing::Test::RecordProperty("fog_ball_peak_y", std::to_string(y_peak));
}

// Flat scattering water (flat_pool with the sun straight down): the shafts
// are uniform across x and, at depth d, read sigma_s p E0 T(0) e^(-sigma_t d)
// (1 - e^(-4 sigma_t)) / sigma_t averaged over the pixel: T(0) the Fresnel
// transmittance at normal incidence, 4 m of water between the point's
// z and the camera side of the water's extent.
TEST(ReferenceMedia, FlatScatteringWaterIsUniformAndAnalytic) {
  const nlohmann::json j = test::scattering_flat_pool();
  InscatterRequest q;
  q.scene_path = test::write_scene(j, "reference_water");
  q.x0 = -1.5, q.y0 = 0, q.x1 = 1.5, q.y1 = 2.5;
  q.width = 12, q.height = 20;
  q.photons = 400'000;
  InscatterStats stats;
  auto img = trace_inscatter(q, &stats);
  ASSERT_TRUE(img.ok()) << img.error().message;
  const double ss = 0.4, st = 0.5, t0 = fresnel_t(1.0, 1.33);
  const double dy = 2.5 / 20;
  for (int row = 0; row < 20; ++row) {
    const double expected = test::flat_water_pixel(2.5 - (row + 1) * dy, 2.5 - row * dy);
    for (int col = 0; col < 12; ++col) {
      const std::size_t i = std::size_t(row) * 12 + std::size_t(col);
      EXPECT_NEAR(img->rgb[3 * i + 1], expected, 4 * img->sigma[i] + 1e-6) << "row " << row << " col " << col;
    }
  }
  // The water's top (16 m^2 under the sun) takes T(0) of E0; no glass.
  EXPECT_NEAR(stats.power_in, 16 * t0, 1e-6);
  EXPECT_NEAR(stats.scattered, 16 * t0 * (1 - std::exp(-2 * st)) * ss / st, 1e-6);
}

// The in-scatter reference with dispersion: the flat scattering
// pool's water at dispersion 20 (V_d 1, the extreme), sun straight down,
// so only the Fresnel transmittance at the top depends on the wavelength.
// A monochromatic run takes exactly 16 m^2 x T(0, n(lambda)) of E0 in (no
// noise: every photon enters with it); the RGB run (each photon at its own
// drawn wavelength) is the analytic image times each channel's
// integral of T(0, n) over the CIE-sRGB density, over T(0, 1.33): gains
// about 1.008 / 0.991 / 0.949, so a blue channel within 1 % of its gain is
// 5 % from the image without dispersion.
TEST(ReferenceMedia, DispersiveScatteringWaterTakesFresnelPerWavelength) {
  nlohmann::json j = test::scattering_flat_pool();
  j["water"]["dispersion"] = 20.0;
  InscatterRequest q;
  q.scene_path = test::write_scene(j, "reference_water_dispersion");
  q.x0 = -1.5, q.y0 = 0, q.x1 = 1.5, q.y1 = 2.5;
  q.width = 12, q.height = 20;
  q.photons = 400'000;
  for (const double nm : {400.0, 700.0}) {
    q.wavelength_nm = nm;
    InscatterStats stats;
    auto img = trace_inscatter(q, &stats);
    ASSERT_TRUE(img.ok()) << img.error().message;
    const double t = fresnel_t(1.0, index_at(1.33f, 20.0f, static_cast<float>(nm)));
    EXPECT_NEAR(stats.power_in, 16 * t, 1e-6) << nm << " nm";
  }
  q.wavelength_nm = 0;
  q.photons = 4'000'000;  // seeds 1-4: red within 0.4 % of its gain (its weights change sign), green and blue 0.3 %
  auto img = trace_inscatter(q);
  ASSERT_TRUE(img.ok()) << img.error().message;
  std::array<double, 3> gain{0, 0, 0};
  for (double nm = kMinWavelength + 0.125; nm < kMaxWavelength; nm += 0.25) {
    const auto w = rgb_density(nm);
    const double t = fresnel_t(1.0, index_at(1.33f, 20.0f, static_cast<float>(nm)));
    for (std::size_t c = 0; c < 3; ++c) gain[c] += 0.25 * w[c] * t / fresnel_t(1.0, 1.33);
  }
  std::array<double, 3> got{0, 0, 0};
  double want = 0;
  for (int row = 0; row < 20; ++row) {
    want += 12 * test::flat_water_pixel(2.5 - (row + 1) * 0.125, 2.5 - row * 0.125);
    for (int col = 0; col < 12; ++col) {
      for (std::size_t c = 0; c < 3; ++c) got[c] += img->rgb[3 * (std::size_t(row) * 12 + std::size_t(col)) + c];
    }
  }
  for (std::size_t c = 0; c < 3; ++c) {
    std::printf("[reference, dispersive pool] channel %zu: in-scatter / analytic %.4f, expected gain %.4f\n", c, got[c] / want, gain[c]);
    EXPECT_NEAR(got[c] / want, gain[c], 0.01) << "channel " << c;
  }
}

}  // namespace
}  // namespace caustix::reference
