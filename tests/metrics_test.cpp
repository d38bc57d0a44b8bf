// Image metrics: zero for identical images, the known value for known
// perturbations; the temporal statistic's ratio is 1/2 for smooth motion
// and 1 for noise.

#include <gtest/gtest.h>

#include <cmath>

#include "caustix/metrics/error_split.h"
#include "caustix/metrics/image_metrics.h"
#include "caustix/metrics/temporal.h"

#include <random>

namespace caustix::metrics {
namespace {

Image constant(int w, int h, float r, float g, float b) {
  Image im{w, h, {}};
  for (int i = 0; i < w * h; ++i) im.rgb.insert(im.rgb.end(), {r, g, b});
  return im;
}

TEST(Metrics, IdenticalImagesAreZero) {
  Image a = constant(8, 4, 0.3f, 0.5f, 0.7f);
  a.rgb[5] = 4.0f;
  EXPECT_EQ(average_luv_difference(a, a), 0.0);
  EXPECT_EQ(relative_l1(a, a), 0.0);
  EXPECT_EQ(rms(a, a), 0.0);
  EXPECT_EQ(flux_ratio(a, a), 1.0);
}

TEST(Metrics, KnownPerturbations) {
  const Image ref = constant(10, 10, 0.5f, 0.5f, 0.5f);
  Image scaled = ref;
  for (float& v : scaled.rgb) v *= 1.1f;
  EXPECT_NEAR(relative_l1(scaled, ref), 0.1, 1e-6);
  EXPECT_NEAR(flux_ratio(scaled, ref), 1.1, 1e-6);
  Image offset = ref;
  for (float& v : offset.rgb) v += 0.05f;
  EXPECT_NEAR(rms(offset, ref), 0.05, 1e-6);
  // Grey 1 against grey 0.18: L* 100 against 116 * 0.18^(1/3) - 16, u* = v* = 0.
  const double l18 = 116.0 * std::cbrt(0.18) - 16.0;
  EXPECT_NEAR(average_luv_difference(constant(4, 4, 1, 1, 1), constant(4, 4, 0.18f, 0.18f, 0.18f)), 100.0 - l18, 1e-3);
  // Half the pixels changed: half the mean difference.
  Image half = constant(4, 4, 1, 1, 1);
  for (std::size_t i = 0; i < half.rgb.size() / 2; ++i) half.rgb[i] = 0.18f;
  EXPECT_NEAR(average_luv_difference(half, constant(4, 4, 1, 1, 1)), (100.0 - l18) / 2, 1e-3);
  // A mask leaves pixels out.
  std::vector<bool> mask(16, false);
  for (std::size_t i = 8; i < 16; ++i) mask[i] = true;
  EXPECT_NEAR(average_luv_difference(half, constant(4, 4, 1, 1, 1), &mask), 0.0, 1e-9);
}

TEST(Metrics, PeakPositionInPixelsAndMetres) {
  Image ref = constant(8, 4, 0.1f, 0.1f, 0.1f), moved = ref;
  ref.rgb[3 * (1 * 8 + 2) + 1] = 5.0f;    // row 1, column 2
  moved.rgb[3 * (3 * 8 + 6) + 1] = 5.0f;  // row 3, column 6
  EXPECT_EQ(peak_position(ref), (std::array<double, 2>{2.5, 1.5}));
  const Comparison c = compare(moved, ref, std::array<double, 4>{-2, 0, 2, 4});  // 0.5 m x 1 m pixels
  EXPECT_NEAR(c.peak_error_px, std::hypot(4.0, 2.0), 1e-12);
  ASSERT_TRUE(c.peak_error_m);
  EXPECT_NEAR(*c.peak_error_m, std::hypot(4 * 0.5, 2 * 1.0), 1e-12);
  EXPECT_FALSE(compare(moved, ref).peak_error_m);
  const Comparison self = compare(ref, ref);
  EXPECT_EQ(self.eq29, 0.0);
  EXPECT_EQ(self.rel_l1, 0.0);
  EXPECT_EQ(self.peak_error_px, 0.0);
  EXPECT_EQ(self.flux_ratio, 1.0);
}

TEST(Metrics, LuvOfColours) {
  const Luv white = to_luv(1, 1, 1);
  EXPECT_NEAR(white.L, 100.0, 1e-6);
  EXPECT_NEAR(white.u, 0.0, 0.05);
  EXPECT_NEAR(white.v, 0.0, 0.05);
  const Luv red = to_luv(1, 0, 0);
  EXPECT_GT(red.u, 100.0);  // sRGB red: u* about 175
  EXPECT_NEAR(to_luv(0, 0, 0).L, 0.0, 1e-9);
}

// Each pixel lands in the class its auxiliary values and the reference put
// it in, and the classes' errors add up to the image's.
TEST(ErrorSplit, ClassesFollowCoverageCosineFoldsAndSlope) {
  // One row: facing away, grazing, in a cast shadow, unseen, partly
  // covered, a lit pixel of slope 0.3, then two lit pixels 4x apart (a
  // fold on both).
  const std::vector<float> ref_y = {0, 0.1f, 0.01f, 0, 0.6f, 1, 1, 4};
  const std::vector<float> a_y = {0, 0.1f, 0.02f, 0, 0.5f, 1.1f, 1, 4};
  const std::vector<float> cov = {1, 1, 1, 0, 0.5f, 1, 1, 1}, ny = {0.5f, 0.5f, 1, 0, 0.1f, 0.3f, 1, 1};
  const std::vector<float> cosine = {-0.5f, 0.1f, 1, 0, 0.5f, 1, 1, 1};
  Image a{8, 1, {}}, b{8, 1, {}}, aux{8, 1, {}};
  for (std::size_t i = 0; i < 8; ++i) {
    a.rgb.insert(a.rgb.end(), {a_y[i], a_y[i], a_y[i]});
    b.rgb.insert(b.rgb.end(), {ref_y[i], ref_y[i], ref_y[i]});
    aux.rgb.insert(aux.rgb.end(), {cov[i], ny[i], cosine[i]});
  }
  const ErrorSplit s = split_error(a, b, aux);
  const std::vector<std::string> expected = {"self-shadow", "terminator", "cast-shadow", "outside",
                                             "silhouette", "n_y 0.2-0.5", "fold", "fold"};
  double abs_sum = 0;
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(s.classes[s.class_of[i]].name, expected[i]) << "pixel " << i;
  for (const auto& c : s.classes) abs_sum += c.abs_error;
  EXPECT_NEAR(abs_sum, s.total_abs_error, 1e-12);
  EXPECT_NEAR(s.total_abs_error, 0.01 + 0.1 + 0.1, 1e-6);
  const auto& slope = s.classes[s.class_of[5]];
  EXPECT_NEAR(slope.rel_l1(), 0.1, 1e-6);
  EXPECT_NEAR(slope.bias(), 0.1, 1e-6);
}

// A Gaussian spot (sigma 0.1 m, peak 1) at x = x0 + k * step over
// [-1, 1]^2 in 64^2 pixels, plus noise of the given amplitude per pixel.
std::vector<Image> moving_spot(double step, double noise, int frames, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Image> out;
  for (int k = 0; k < frames; ++k) {
    Image im{64, 64, {}};
    const double cx = -0.2 + k * step;
    for (int row = 0; row < 64; ++row) {
      for (int col = 0; col < 64; ++col) {
        const double x = -1 + (col + 0.5) / 32.0, z = -1 + (row + 0.5) / 32.0;
        const double v = std::exp(-((x - cx) * (x - cx) + z * z) / (2 * 0.01)) + noise * u(rng);
        im.rgb.insert(im.rgb.end(), 3, static_cast<float>(v));
      }
    }
    out.push_back(std::move(im));
  }
  return out;
}

TEST(Temporal, SmoothMotionHalvesRhoAndNoiseKeepsIt) {
  // Smooth: second differences shrink as step^2, first as step.
  const TemporalStats a = temporal_stats(moving_spot(0.02, 0, 12, 1)), b = temporal_stats(moving_spot(0.01, 0, 12, 1));
  EXPECT_NEAR(b.rho / a.rho, 0.5, 0.05);
  // Noise: the same rho whatever the step, near sqrt(3) (independent
  // noise's second difference spreads sqrt(6) times its amplitude, the
  // first sqrt(2)).
  const TemporalStats n1 = temporal_stats(moving_spot(0.02, 1e-1, 12, 2)), n2 = temporal_stats(moving_spot(0, 1e-1, 12, 3));
  EXPECT_NEAR(n2.rho / n1.rho, 1.0, 0.15);
  EXPECT_GT(n1.rho, 1.4);
}

TEST(Temporal, JumpsOfFluxPeakAndFocus) {
  // A still spot whose brightness steps up 10 % at frame 3: the flux, the
  // peak and the focus power jump by 10 % of their means (to the mean's
  // share of frames after the step).
  std::vector<Image> frames = moving_spot(0, 0, 6, 1);
  for (std::size_t k = 3; k < frames.size(); ++k) {
    for (float& v : frames[k].rgb) v *= 1.1f;
  }
  const TemporalStats s = temporal_stats(frames, std::array<double, 4>{-1, -1, 1, 1}, 0.1);
  const double mean = (3 * 1.0 + 3 * 1.1) / 6;
  EXPECT_NEAR(s.flux_jump, 0.1 / mean, 1e-5);
  EXPECT_NEAR(s.peak_jump, 0.1 / mean, 1e-5);
  ASSERT_TRUE(s.focus_jump);
  EXPECT_NEAR(*s.focus_jump, 0.1 / mean, 1e-4);  // the followed centre moves by the floats' rounding
  // The focus followed: a spot moving 1 cm a frame keeps its power within
  // 10 cm and within 2 pixels (6.25 cm). Pixels count by their area inside
  // the circle: counted whole by their centres, the measure jumped by up to
  // a pixel's share as the circle's edge crossed pixel centres (4.4 % at
  // 10 cm, 8.3 % at 6.25 cm). What is left is the pixels' point sampling of
  // the spot (0.2 and 0.6 %).
  for (const double radius : {0.1, 0.0625}) {
    const TemporalStats moving = temporal_stats(moving_spot(0.01, 0, 8, 1), std::array<double, 4>{-1, -1, 1, 1}, radius);
    EXPECT_LT(*moving.focus_jump, 0.01) << radius;
  }
  EXPECT_THROW(temporal_stats(std::vector<Image>(2, frames[0])), std::invalid_argument);
}

}  // namespace
}  // namespace caustix::metrics
