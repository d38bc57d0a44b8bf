// Dispersion's index model and wavelength sampling (spectrum.h):
// KHR_materials_dispersion's index at the d, F and C lines, its clamp at 1
// and its extremes; the bin weights sum to 1 per channel for every count,
// the density integrates to 1, and the white of a flat spectrum is neutral.

#include <gtest/gtest.h>

#include <cmath>

#include "caustix/formats/spectrum.h"

namespace caustix {
namespace {

TEST(Spectrum, IndexFollowsTheAbbeNumber) {
  // dispersion 20 / V_d: n_F - n_C = (n_d - 1) / V_d times 523655 (1/486.13^2
  // - 1/656.27^2) = 1.0000 (the formula's constant makes it the Abbe
  // number's definition).
  for (float v_d : {64.17f, 36.4f, 20.0f}) {
    const float dispersion = 20.0f / v_d;
    const double spread = index_at(1.5f, dispersion, kWavelengthF) - index_at(1.5f, dispersion, kWavelengthC);
    EXPECT_NEAR(spread, 0.5 / v_d, 2e-4 / v_d) << "V_d " << v_d;
    EXPECT_NEAR(index_at(1.5f, dispersion, kWavelengthD), 1.5, 1e-4);
  }
  EXPECT_EQ(index_at(1.333f, 0.0f, 380.0f), 1.333f);  // no dispersion: n_d exactly
  EXPECT_EQ(index_at(1.333f, 0.0f, 780.0f), 1.333f);
  // Extremes: dispersion 20 (Abbe number 1) stays finite and above 1 over
  // the whole range (n_d - 0.66 (n_d - 1) at 780 nm); the clamp at 1 acts
  // only beyond it (2 um).
  for (float nm : {kMinWavelength, 500.0f, kMaxWavelength}) {
    const float n = index_at(1.5f, kMaxDispersion, nm);
    EXPECT_TRUE(std::isfinite(n));
    EXPECT_GE(n, 1.0f);
  }
  EXPECT_NEAR(index_at(1.5f, kMaxDispersion, kMaxWavelength), 1.5 - 0.5 * (1.5168 - 523655.0 / (780.0 * 780.0)), 1e-5);
  EXPECT_EQ(index_at(1.5f, kMaxDispersion, 2000.0f), 1.0f);
  EXPECT_GT(index_at(1.5f, kMaxDispersion, kMinWavelength), 2.5f);
}

TEST(Spectrum, WeightsSumToOnePerChannel) {
  for (std::uint32_t count = 1; count <= kMaxWavelengths; ++count) {
    const auto s = wavelength_samples(count);
    ASSERT_EQ(s.size(), count);
    double sum[3] = {0, 0, 0};
    for (std::size_t i = 0; i < s.size(); ++i) {
      EXPECT_GE(s[i].nm, kMinWavelength);
      EXPECT_LE(s[i].nm, kMaxWavelength);
      if (i > 0) EXPECT_GT(s[i].nm, s[i - 1].nm);
      for (int c = 0; c < 3; ++c) sum[c] += s[i].rgb[c];
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], 1.0, 1e-5) << count << " bins, channel " << c;
  }
  EXPECT_EQ(wavelength_samples(1)[0].nm, kWavelengthD);
  // Blue light in the blue bins, red in the red ones.
  const auto s8 = wavelength_samples(8);
  EXPECT_GT(s8[1].rgb[2], s8[1].rgb[0]);
  EXPECT_GT(s8[5].rgb[0], s8[5].rgb[2]);
}

TEST(Spectrum, DensityIntegratesToOne) {
  double sum[3] = {0, 0, 0};
  const int steps = 4000;
  const double h = (kMaxWavelength - kMinWavelength) / steps;
  for (int k = 0; k < steps; ++k) {
    const auto d = rgb_density(kMinWavelength + (k + 0.5) * h);
    for (int c = 0; c < 3; ++c) sum[c] += d[c] * h;
  }
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], 1.0, 1e-4);
  EXPECT_EQ(rgb_density(300.0)[1], 0.0);
  // The CIE fit's white: a flat spectrum's XYZ is near equal-energy white
  // (x = y = 1/3 within the fit's accuracy).
  double xyz[3] = {0, 0, 0};
  for (int k = 0; k < steps; ++k) {
    const auto c = cie_xyz(kMinWavelength + (k + 0.5) * h);
    for (int i = 0; i < 3; ++i) xyz[i] += c[i] * h;
  }
  const double total = xyz[0] + xyz[1] + xyz[2];
  EXPECT_NEAR(xyz[0] / total, 1.0 / 3, 0.01);
  EXPECT_NEAR(xyz[1] / total, 1.0 / 3, 0.01);
}

}  // namespace
}  // namespace caustix
