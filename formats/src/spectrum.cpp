// Wavelength sampling for dispersion (spectrum.h).

#include "caustix/formats/spectrum.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace caustix {
namespace {

// Wyman, Sloan & Shirley 2013, eq. 2: a piecewise Gaussian with different
// widths left and right of its mean.
double lobe(double x, double mean, double sigma_left, double sigma_right) {
  const double t = (x - mean) / (x < mean ? sigma_left : sigma_right);
  return std::exp(-0.5 * t * t);
}

// Step of the midpoint rule the bin weights are integrated with: the fit's
// narrowest lobe is 11.8 nm wide, so 0.25 nm leaves the weights exact to
// far below float precision.
constexpr double kStep = 0.25;

std::array<double, 3> rgb_integral(double from, double to) {
  std::array<double, 3> sum{0, 0, 0};
  const auto steps = static_cast<int>(std::lround((to - from) / kStep));
  const double h = (to - from) / steps;
  for (int k = 0; k < steps; ++k) {
    const auto rgb = xyz_to_linear_srgb(cie_xyz(from + (k + 0.5) * h));
    for (int c = 0; c < 3; ++c) sum[c] += rgb[c] * h;
  }
  return sum;
}

}  // namespace

float index_at(float n_d, float dispersion, float nm) {
  if (dispersion <= 0.0f) return n_d;
  // KHR_materials_dispersion: (n_d - 1) / V_d with V_d = 20 / dispersion,
  // times the Cauchy term that vanishes at the d line (523655 / 587.56^2
  // = 1.5168).
  const double v_d = 20.0 / dispersion;
  const double lambda2 = static_cast<double>(nm) * nm;
  const double n = n_d + (n_d - 1.0) / v_d * (523655.0 / lambda2 - 1.5168);
  return static_cast<float>(std::max(n, 1.0));
}

std::array<double, 3> cie_xyz(double nm) {
  const double x = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) - 0.065 * lobe(nm, 501.1, 20.4, 26.2);
  const double y = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
  const double z = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
  return {x, y, z};
}

std::array<double, 3> xyz_to_linear_srgb(const std::array<double, 3>& c) {
  // IEC 61966-2-1 (sRGB), D65 white.
  return {3.2404542 * c[0] - 1.5371385 * c[1] - 0.4985314 * c[2],
          -0.9692660 * c[0] + 1.8760108 * c[1] + 0.0415560 * c[2],
          0.0556434 * c[0] - 0.2040259 * c[1] + 1.0572252 * c[2]};
}

std::array<double, 3> rgb_density(double nm) {
  if (!(nm >= kMinWavelength && nm <= kMaxWavelength)) return {0, 0, 0};
  static const std::array<double, 3> total = rgb_integral(kMinWavelength, kMaxWavelength);
  const auto rgb = xyz_to_linear_srgb(cie_xyz(nm));
  return {rgb[0] / total[0], rgb[1] / total[1], rgb[2] / total[2]};
}

std::vector<WavelengthSample> wavelength_samples(std::uint32_t count) {
  assert(count >= 1 && count <= kMaxWavelengths);
  if (count <= 1) return {WavelengthSample{}};
  const double lo = kMinWavelength, hi = kMaxWavelength;
  std::vector<WavelengthSample> out(count);
  std::vector<std::array<double, 3>> parts(count);
  std::array<double, 3> total{0, 0, 0};
  const double width = (hi - lo) / count;
  for (std::uint32_t i = 0; i < count; ++i) {
    const double a = lo + i * width;
    parts[i] = rgb_integral(a, a + width);
    for (int c = 0; c < 3; ++c) total[c] += parts[i][c];
    out[i].nm = static_cast<float>(a + 0.5 * width);
  }
  // Normalised by the bins' own sum, so the weights add up to 1 exactly
  // (to rounding) whatever the bin count.
  for (std::uint32_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) out[i].rgb[c] = static_cast<float>(parts[i][c] / total[c]);
  }
  return out;
}

}  // namespace caustix
