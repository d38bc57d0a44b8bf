#include "caustix/metrics/temporal.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace caustix::metrics {
namespace {

// The focus's mean shift: steps at most, and the move (in pixels) below
// which it has settled.
constexpr int kMaxShifts = 200;
constexpr double kSettled = 1e-3;
// Sub-samples a pixel axis where a pixel straddles the focus's circle.
constexpr int kCoverSamples = 16;
// The focus's pattern search: the eight compass moves, down to this
// fraction of a pixel (the circle's coverage is resolved to 1/16).
constexpr double kFinestStep = 1.0 / 32;
constexpr double kCompass[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};

// Each pixel's luminance weighted by the share of its area inside the
// circle (cx, cz, radius): the sum, and the weighted centre. Counting whole
// pixels by their centres would make the power jump by a pixel's share
// whenever the circle's edge crosses a pixel centre: with 5 mm pixels and
// a 1 cm radius, some 8 % of the power a pixel, a jump of the measure and
// not of the picture.
struct Covered {
  double power = 0, x = 0, z = 0;
};
Covered covered(const Image& im, const std::array<double, 4>& rg, double cx, double cz, double radius) {
  const double sx = (rg[2] - rg[0]) / im.width, sz = (rg[3] - rg[1]) / im.height;
  const int c0 = std::max(0, static_cast<int>(std::floor((cx - radius - rg[0]) / sx)));
  const int c1 = std::min(im.width - 1, static_cast<int>(std::floor((cx + radius - rg[0]) / sx)));
  const int r0 = std::max(0, static_cast<int>(std::floor((cz - radius - rg[1]) / sz)));
  const int r1 = std::min(im.height - 1, static_cast<int>(std::floor((cz + radius - rg[1]) / sz)));
  const double r2 = radius * radius;
  Covered c;
  for (int row = r0; row <= r1; ++row) {
    for (int col = c0; col <= c1; ++col) {
      const double x0 = rg[0] + col * sx - cx, z0 = rg[1] + row * sz - cz;
      // Nearest and farthest points of the pixel from the centre.
      const double nx = std::max({x0, 0.0, -(x0 + sx)}), nz = std::max({z0, 0.0, -(z0 + sz)});
      const double fx = std::max(std::fabs(x0), std::fabs(x0 + sx)), fz = std::max(std::fabs(z0), std::fabs(z0 + sz));
      double share = 0;
      if (fx * fx + fz * fz <= r2) {
        share = 1;
      } else if (nx * nx + nz * nz < r2) {
        int in = 0;
        for (int a = 0; a < kCoverSamples; ++a) {
          for (int b = 0; b < kCoverSamples; ++b) {
            const double x = x0 + (a + 0.5) * sx / kCoverSamples, z = z0 + (b + 0.5) * sz / kCoverSamples;
            in += x * x + z * z <= r2 ? 1 : 0;
          }
        }
        share = static_cast<double>(in) / (kCoverSamples * kCoverSamples);
      }
      if (share == 0) continue;
      const double y = share * luminance(im, static_cast<std::size_t>(row) * static_cast<std::size_t>(im.width) + static_cast<std::size_t>(col));
      c.power += y;
      c.x += y * (cx + x0 + 0.5 * sx);
      c.z += y * (cz + z0 + 0.5 * sz);
    }
  }
  if (c.power > 0) {
    c.x /= c.power;
    c.z /= c.power;
  }
  c.power *= sx * sz;
  return c;
}

// Largest |v[k+1] - v[k]| (order 1) or |v[k+1] - 2 v[k] + v[k-1]| (order
// 2) over the mean of |v|; 0 where the mean is 0.
double largest_change(const std::vector<double>& v, int order) {
  double mean = 0, worst = 0;
  for (double x : v) mean += std::fabs(x) / static_cast<double>(v.size());
  for (std::size_t k = static_cast<std::size_t>(order); k < v.size(); ++k) {
    const double d = order == 1 ? v[k] - v[k - 1] : v[k] - 2 * v[k - 1] + v[k - 2];
    worst = std::max(worst, std::fabs(d));
  }
  return mean > 0 ? worst / mean : 0.0;
}

}  // namespace

TemporalStats temporal_stats(const std::vector<Image>& frames, const std::optional<std::array<double, 4>>& region,
                             double focus_radius) {
  if (frames.size() < 3) throw std::invalid_argument("temporal_stats: fewer than three frames");
  const int w = frames.front().width, h = frames.front().height;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  for (const Image& f : frames) {
    if (f.width != w || f.height != h || f.rgb.size() != 3 * pixels) throw std::invalid_argument("temporal_stats: frames differ in size");
  }
  TemporalStats s;
  s.frames = static_cast<int>(frames.size());
  double first = 0, second = 0;
  std::vector<double> flux(frames.size(), 0.0), peak(frames.size(), 0.0);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    for (std::size_t i = 0; i < pixels; ++i) {
      const double y = luminance(frames[k], i);
      flux[k] += y;
      peak[k] = std::max(peak[k], y);
      if (k >= 1) first += std::fabs(y - luminance(frames[k - 1], i));
      if (k >= 2) second += std::fabs(y - 2 * luminance(frames[k - 1], i) + luminance(frames[k - 2], i));
    }
  }
  s.rho = first > 0 ? second / first : 0.0;
  s.flux_jump = largest_change(flux, 1);
  s.peak_jump = largest_change(peak, 1);
  s.peak_second = largest_change(peak, 2);
  if (region && focus_radius > 0) {
    const auto& rg = *region;
    const double sx = (rg[2] - rg[0]) / w, sz = (rg[3] - rg[1]) / h;
    const auto p = peak_position(frames.front());
    double cx = rg[0] + p[0] * sx, cz = rg[1] + p[1] * sz;
    // The first frame's focus: mean shift from the brightest pixel until it
    // settles, onto the brightest part nearby (on a focal line, its
    // brightest stretch).
    for (int iteration = 0; iteration < kMaxShifts; ++iteration) {
      const Covered c = covered(frames.front(), rg, cx, cz, focus_radius);
      if (!(c.power > 0)) break;
      const double moved = std::hypot((c.x - cx) / sx, (c.z - cz) / sz);
      cx = c.x;
      cz = c.z;
      if (moved < kSettled) break;
    }
    std::vector<double> power;
    for (const Image& f : frames) {
      // Then in every frame, from the last frame's centre, the centre whose
      // circle holds the most light (a local maximum, by pattern search).
      // There the power is stationary: a centre a little off costs it only
      // to second order. The mean shift's centre is not such a point: on a
      // focal line it slid along the line as the line changed, and the
      // power within it changed at first order with the slide.
      double best = covered(f, rg, cx, cz, focus_radius).power;
      for (double step = 1.0; step >= kFinestStep;) {
        bool better = false;
        for (int d = 0; d < 8; ++d) {
          const double px = cx + step * sx * kCompass[d][0], pz = cz + step * sz * kCompass[d][1];
          const double trial = covered(f, rg, px, pz, focus_radius).power;
          if (trial > best) {
            best = trial;
            cx = px;
            cz = pz;
            better = true;
          }
        }
        if (!better) step *= 0.5;
      }
      power.push_back(best);
    }
    s.focus_jump = largest_change(power, 1);
  }
  return s;
}

}  // namespace caustix::metrics
