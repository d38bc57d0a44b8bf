#pragma once
// Image error metrics for comparing methods and against the reference.
// Images are linear RGB floats, row-major, 3 channels, equal sizes.
//
// average_luv_difference() is Tipprasert 2006 §2.7, eq. 2-9: the mean over pixels
// of the Euclidean distance in CIE L*u*v* (D65 white, Y_n = `white`).
// Pixels where `mask` is given and false are left out.

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

namespace caustix::metrics {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // linear
};

// CIE L*u*v* of a linear sRGB/Rec.709 colour, relative to white Y_n.
struct Luv {
  double L, u, v;
};
Luv to_luv(double r, double g, double b, double white = 1.0);

double average_luv_difference(const Image& a, const Image& b, const std::vector<bool>* mask = nullptr,
                              double white = 1.0);

// sum |a - b| / sum |b| over the masked pixels' luminance (b the reference).
double relative_l1(const Image& a, const Image& b, const std::vector<bool>* mask = nullptr);
// sqrt(mean (a - b)^2) of luminance.
double rms(const Image& a, const Image& b, const std::vector<bool>* mask = nullptr);
// sum a / sum b of luminance: the total flux ratio.
double flux_ratio(const Image& a, const Image& b, const std::vector<bool>* mask = nullptr);

// Centre of the brightest pixel (luminance; the first one in row order
// on ties), in pixels: (column + 1/2, row + 1/2).
std::array<double, 2> peak_position(const Image& im);

// Every metric of A against the reference B (caustix-compare, the
// trade-off sweeps). With the reference's world rectangle (x0, z0, x1, z1)
// the peak error is also given in metres.
struct Comparison {
  double eq29 = 0, rel_l1 = 0, rms = 0, flux_ratio = 1;
  double peak_error_px = 0;
  std::optional<double> peak_error_m;
  // The focus, where averages hide the error: A's brightest
  // pixel over B's (luminance), and, with the region, the power of the
  // pixels whose centres lie within 1 and 2 cm of B's brightest pixel,
  // A's over B's (nothing where B has no power there). Meaningful where the
  // pixels are well below the radius.
  double peak_ratio = 1;
  std::optional<double> focus_1cm, focus_2cm;
};
// Luminance power (sum of luminance x pixel area) of the pixels whose
// centres lie within `radius` of (cx, cz), the image over the world
// rectangle `region`.
double power_within(const Image& im, const std::array<double, 4>& region, double cx, double cz, double radius);
Comparison compare(const Image& a, const Image& b, const std::optional<std::array<double, 4>>& region = {});

// Rec. 709 luminance of pixel i.
inline double luminance(const Image& im, std::size_t i) {
  return 0.2126 * im.rgb[3 * i] + 0.7152 * im.rgb[3 * i + 1] + 0.0722 * im.rgb[3 * i + 2];
}

// sRGB 8-bit display value -> linear.
double srgb_to_linear(double v8);

}  // namespace caustix::metrics
