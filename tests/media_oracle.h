#pragma once
// Analytic single scattering for the media tests of the reference
// (reference_test.cpp) and the runtime (volume_test.cpp): the same scenes
// and the same closed forms, so both are held to one oracle.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

#include "optics_oracle.h"
#include "scene_fixture.h"

namespace caustix::test {

// A fog box [-1, 1] x [0, 2] x [-1, 1] over a bare floor, sun straight
// down (E0 = 2): the in-scatter image along -z is, per pixel, the
// pixel-box average over y of sigma_s p E0 e^(-sigma_t (2 - y))
// (1 - e^(-2 sigma_t)) / sigma_t / E0 (the light's path down to y, the
// view's path out of the box's front).
inline nlohmann::json fog_box(double scattering, double absorption) {
  nlohmann::json j = canonical_scene("glass_ball");
  j["objects"].erase(1);
  j["lights"][0]["irradiance"] = 2.0;
  j["medium"] = {{"extent", {-1, 0, -1, 1, 2, 1}}, {"scattering", scattering}, {"absorption", absorption}};
  return j;
}

// The fog box's pixel spanning [ya, yb] in height (whole in x).
inline double fog_pixel(double ss, double st, double phase, double ya, double yb) {
  const double height = yb - ya;
  ya = std::clamp(ya, 0.0, 2.0);
  yb = std::clamp(yb, 0.0, 2.0);
  if (yb <= ya) return 0;
  const double light = (std::exp(-st * (2 - yb)) - std::exp(-st * (2 - ya))) / st;  // integral over y
  return ss * phase * light / height * (1 - std::exp(-2 * st)) / st;
}

// fog_box's whole in-scatter image over [x0, x1] x [y0, y1], width x
// height pixels, row 0 at y1 (isotropic phase), row-major.
inline std::vector<double> fog_box_image(double ss, double st, double x0, double y0, double x1, double y1, int width, int height) {
  const double dx = (x1 - x0) / width, dy = (y1 - y0) / height;
  std::vector<double> out(std::size_t(width) * std::size_t(height));
  for (int row = 0; row < height; ++row) {
    const double yb = y1 - row * dy, ya = yb - dy;
    for (int col = 0; col < width; ++col) {
      const double xa = x0 + col * dx, xb = xa + dx;
      const double cover = std::max(0.0, std::min(xb, 1.0) - std::max(xa, -1.0)) / dx;
      out[std::size_t(row) * std::size_t(width) + std::size_t(col)] = cover * fog_pixel(ss, st, 1 / (4 * kPi), ya, yb);
    }
  }
  return out;
}

// flat_pool with the sun straight down, its water scattering (sigma_s 0.4,
// sigma_a 0.1) over the extent [-2, 2]^2.
inline nlohmann::json scattering_flat_pool() {
  nlohmann::json j = canonical_scene("flat_pool");
  j["lights"][0]["direction"] = {0, -1, 0};
  j["water"]["scattering"] = 0.4;
  j["water"]["absorption"] = 0.1;
  j["water"]["grid"]["extent"] = {-2, -2, 2, 2};
  return j;
}

// Its shafts at depths within the pixel [ya, yb] of height: sigma_s p E0
// T(0) e^(-sigma_t d) (1 - e^(-4 sigma_t)) / sigma_t averaged over the
// pixel, T(0) the Fresnel transmittance at normal incidence, 4 m of water
// between the point's z and the camera side of the water's extent.
inline double flat_water_pixel(double ya, double yb) {
  const double ss = 0.4, st = 0.5, level = 2.0, t0 = fresnel_t(1.0, 1.33);
  const double height = yb - ya;
  yb = std::min(yb, level);
  const double light = yb > ya ? (std::exp(-st * (level - yb)) - std::exp(-st * (level - ya))) / st / height : 0.0;
  return ss / (4 * kPi) * t0 * light * (1 - std::exp(-4 * st)) / st;
}

// fog_box(0.5, 0) under the isotropic phase and Schlick's at k = 0, 0.6
// and -0.6, imaged by `image`: k = 0 is the isotropic image (to
// `k0_tolerance` relative; 0: bit for bit) and +-0.6 scale it by
// p_k(0) / p_0 = 1 - k^2 (light down, camera along z: cos a = 0 exactly)
// to `tolerance` relative.
inline void expect_schlick_scaling(const std::function<std::vector<float>(const nlohmann::json&)>& image, double tolerance) {
  nlohmann::json j = fog_box(0.5, 0.0);
  const auto iso = image(j);
  j["medium"]["phase"] = "schlick";
  j["medium"]["anisotropy"] = 0.0;
  const auto k0 = image(j);
  j["medium"]["anisotropy"] = 0.6;
  const auto k6 = image(j);
  j["medium"]["anisotropy"] = -0.6;
  const auto km6 = image(j);
  ASSERT_EQ(iso.size(), k0.size());
  ASSERT_EQ(iso.size(), k6.size());
  ASSERT_EQ(iso.size(), km6.size());
  double sum = 0;
  for (std::size_t i = 0; i < iso.size(); ++i) {
    EXPECT_EQ(k0[i], iso[i]) << i;
    EXPECT_NEAR(k6[i], 0.64 * iso[i], tolerance * iso[i]) << i;
    EXPECT_NEAR(km6[i], 0.64 * iso[i], tolerance * iso[i]) << i;
    sum += iso[i];
  }
  EXPECT_GT(sum, 0);
}

}  // namespace caustix::test
