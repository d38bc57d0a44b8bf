// The reference photon tracer against physics: flat water gives
// T(theta) cos(theta) within its own noise estimate; doubling the light
// doubles every pixel; seeded runs are reproducible whatever the thread
// count; a sine wave conserves energy.

#include <gtest/gtest.h>

#include "optics_oracle.h"
#include "scene_fixture.h"

#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "reference.h"

namespace caustix::reference {
namespace {

using test::kScenes;
using test::fresnel_t;
using test::kPi;

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
}

}  // namespace
}  // namespace caustix::reference
