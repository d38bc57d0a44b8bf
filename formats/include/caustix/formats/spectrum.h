#pragma once
// Dispersion (docs/dispersion.md): the index of refraction as a
// function of wavelength, and the wavelengths the renderers sample.
//
// A material's and the water's `dispersion` has glTF
// KHR_materials_dispersion's meaning, 20 / V_d (V_d the Abbe number), and
// its index model
//   n(lambda) = max(n_d + (n_d - 1) / V_d * (523655 / lambda^2 - 1.5168), 1),
// lambda in nm, n_d the `ior` (the index at the helium d line, 587.56 nm).
// Dispersion 0 keeps n = n_d at every wavelength.
//
// Light keeps its RGB colour; its spectrum is flat over
// [kMinWavelength, kMaxWavelength]. A renderer that samples N wavelengths
// splits that range into N equal bins, traces each bin at its centre and
// adds the result into RGB with the bin's weights: the CIE 1931 2-degree
// colour-matching functions (Wyman, Sloan & Shirley 2013's multi-lobe fit)
// taken into linear sRGB, integrated over the bin and normalised per
// channel so that the weights of all bins sum to (1, 1, 1). A result that
// does not depend on wavelength therefore comes out exactly as the light's
// RGB colour times it: a scene without dispersion renders as before.
// Some weights are negative (the sRGB primaries do not span the spectral
// locus: the red channel's weight is below zero between about 440 and
// 540 nm); sums stay right, a single saturated band can leave a channel
// slightly below zero, which display paths clamp.

#include <array>
#include <cstdint>
#include <vector>

namespace caustix {

inline constexpr float kMinWavelength = 380.0f;  // nm
inline constexpr float kMaxWavelength = 780.0f;  // nm
inline constexpr float kWavelengthD = 587.56f;   // nm, the helium d line (n_d)
inline constexpr float kWavelengthF = 486.13f;   // nm, hydrogen F (blue)
inline constexpr float kWavelengthC = 656.27f;   // nm, hydrogen C (red)
inline constexpr float kMaxDispersion = 20.0f;   // 20 / V_d: Abbe number 1 (any real glass is above 15)
inline constexpr std::uint32_t kMaxWavelengths = 32;

// KHR_materials_dispersion's index at `nm` (any positive wavelength; the
// renderers use [kMinWavelength, kMaxWavelength]). dispersion 0 returns n_d.
float index_at(float n_d, float dispersion, float nm);

struct WavelengthSample {
  float nm = kWavelengthD;
  std::array<float, 3> rgb{1, 1, 1};  // linear-sRGB weight of this sample's bin
};

// `count` bins (1..kMaxWavelengths): count 1 is the single sample at the d
// line with weight (1, 1, 1), which is exactly what a renderer without
// dispersion does. Deterministic; the weights of all samples sum to 1 per
// channel to float rounding.
std::vector<WavelengthSample> wavelength_samples(std::uint32_t count);

// The weights' density per nm: linear sRGB of the colour-matching
// functions at `nm`, divided per channel by their integral over
// [kMinWavelength, kMaxWavelength]; integrates to (1, 1, 1) over the range,
// zero outside it. A photon whose wavelength is drawn uniformly from the
// range carries (kMaxWavelength - kMinWavelength) times this (the spectral
// reference's estimator); wavelength_samples() integrates it over bins.
std::array<double, 3> rgb_density(double nm);

// CIE 1931 2-degree colour-matching functions x, y, z at `nm` (Wyman,
// Sloan & Shirley 2013, "Simple Analytic Approximations to the CIE XYZ
// Color Matching Functions", JCGT 2(2), the multi-lobe fit).
std::array<double, 3> cie_xyz(double nm);
// Linear sRGB (D65 primaries) of an XYZ colour.
std::array<double, 3> xyz_to_linear_srgb(const std::array<double, 3>& xyz);

}  // namespace caustix
