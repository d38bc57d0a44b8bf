#include "caustix/metrics/image_metrics.h"

#include <cmath>

namespace caustix::metrics {
namespace {

bool use(const std::vector<bool>* mask, std::size_t i) { return !mask || (*mask)[i]; }

// D65 white point chromaticity in u'v'.
constexpr double kUn = 0.19783;
constexpr double kVn = 0.46832;

}  // namespace

Luv to_luv(double r, double g, double b, double white) {
  // Linear Rec. 709 -> XYZ (D65).
  const double x = 0.4124 * r + 0.3576 * g + 0.1805 * b;
  const double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  const double z = 0.0193 * r + 0.1192 * g + 0.9505 * b;
  const double yr = y / white;
  const double L = yr > 216.0 / 24389.0 ? 116.0 * std::cbrt(yr) - 16.0 : 24389.0 / 27.0 * yr;
  const double d = x + 15.0 * y + 3.0 * z;
  const double up = d > 0 ? 4.0 * x / d : kUn;
  const double vp = d > 0 ? 9.0 * y / d : kVn;
  return {L, 13.0 * L * (up - kUn), 13.0 * L * (vp - kVn)};
}

double average_luv_difference(const Image& a, const Image& b, const std::vector<bool>* mask, double white) {
  double sum = 0;
  std::size_t n = 0;
  const std::size_t pixels = a.rgb.size() / 3;
  for (std::size_t i = 0; i < pixels; ++i) {
    if (!use(mask, i)) continue;
    const Luv p = to_luv(a.rgb[3 * i], a.rgb[3 * i + 1], a.rgb[3 * i + 2], white);
    const Luv q = to_luv(b.rgb[3 * i], b.rgb[3 * i + 1], b.rgb[3 * i + 2], white);
    sum += std::sqrt((p.L - q.L) * (p.L - q.L) + (p.u - q.u) * (p.u - q.u) + (p.v - q.v) * (p.v - q.v));  // eq. 2-9
    ++n;
  }
  return n ? sum / static_cast<double>(n) : 0.0;
}

double relative_l1(const Image& a, const Image& b, const std::vector<bool>* mask) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < a.rgb.size() / 3; ++i) {
    if (!use(mask, i)) continue;
    num += std::fabs(luminance(a, i) - luminance(b, i));
    den += std::fabs(luminance(b, i));
  }
  return den > 0 ? num / den : (num > 0 ? INFINITY : 0.0);
}

double rms(const Image& a, const Image& b, const std::vector<bool>* mask) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.rgb.size() / 3; ++i) {
    if (!use(mask, i)) continue;
    const double d = luminance(a, i) - luminance(b, i);
    sum += d * d;
    ++n;
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

double flux_ratio(const Image& a, const Image& b, const std::vector<bool>* mask) {
  double sa = 0, sb = 0;
  for (std::size_t i = 0; i < a.rgb.size() / 3; ++i) {
    if (!use(mask, i)) continue;
    sa += luminance(a, i);
    sb += luminance(b, i);
  }
  return sb > 0 ? sa / sb : (sa > 0 ? INFINITY : 1.0);
}

std::array<double, 2> peak_position(const Image& im) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < im.rgb.size() / 3; ++i) {
    if (luminance(im, i) > luminance(im, best)) best = i;
  }
  const auto w = static_cast<std::size_t>(im.width);
  return {static_cast<double>(best % w) + 0.5, static_cast<double>(best / w) + 0.5};
}

Comparison compare(const Image& a, const Image& b, const std::optional<std::array<double, 4>>& region) {
  Comparison c;
  c.eq29 = average_luv_difference(a, b);
  c.rel_l1 = relative_l1(a, b);
  c.rms = rms(a, b);
  c.flux_ratio = flux_ratio(a, b);
  const auto pa = peak_position(a), pb = peak_position(b);
  c.peak_error_px = std::hypot(pa[0] - pb[0], pa[1] - pb[1]);
  const auto brightest = [](const Image& im) {
    double m = 0;
    for (std::size_t i = 0; i < im.rgb.size() / 3; ++i) m = std::max(m, luminance(im, i));
    return m;
  };
  const double peak_b = brightest(b);
  c.peak_ratio = peak_b > 0 ? brightest(a) / peak_b : 1.0;
  if (region) {
    const auto& r = *region;
    const double sx = (r[2] - r[0]) / b.width, sz = (r[3] - r[1]) / b.height;
    c.peak_error_m = std::hypot((pa[0] - pb[0]) * sx, (pa[1] - pb[1]) * sz);
    const double cx = r[0] + pb[0] * sx, cz = r[1] + pb[1] * sz;
    const auto ratio = [&](double radius) -> std::optional<double> {
      const double want = power_within(b, r, cx, cz, radius);
      if (!(want > 0)) return std::nullopt;
      return power_within(a, r, cx, cz, radius) / want;
    };
    c.focus_1cm = ratio(0.01);
    c.focus_2cm = ratio(0.02);
  }
  return c;
}

double power_within(const Image& im, const std::array<double, 4>& region, double cx, double cz, double radius) {
  const double sx = (region[2] - region[0]) / im.width, sz = (region[3] - region[1]) / im.height;
  double sum = 0;
  for (int i = 0; i < im.height; ++i) {
    for (int j = 0; j < im.width; ++j) {
      if (std::hypot(region[0] + (j + 0.5) * sx - cx, region[1] + (i + 0.5) * sz - cz) >= radius) continue;
      sum += luminance(im, static_cast<std::size_t>(i) * static_cast<std::size_t>(im.width) + static_cast<std::size_t>(j));
    }
  }
  return sum * sx * sz;
}

double srgb_to_linear(double v8) {
  const double c = v8 / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

}  // namespace caustix::metrics
