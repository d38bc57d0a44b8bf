#include "caustix/metrics/temporal.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace caustix::metrics {
namespace {

constexpr int kShifts = 4;  // mean-shift steps per frame (temporal_stats' focus)

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
    std::vector<double> power;
    for (const Image& f : frames) {
      // Mean shift: the centre moves to the luminance-weighted centre of
      // the pixels within the radius, a few times, and settles on the
      // brightest part nearby (on a focal line, on its brightest stretch).
      for (int iteration = 0; iteration < kShifts; ++iteration) {
        double sum = 0, mx = 0, mz = 0;
        for (int row = 0; row < h; ++row) {
          for (int col = 0; col < w; ++col) {
            const double x = rg[0] + (col + 0.5) * sx, z = rg[1] + (row + 0.5) * sz;
            if ((x - cx) * (x - cx) + (z - cz) * (z - cz) > focus_radius * focus_radius) continue;
            const double y = luminance(f, static_cast<std::size_t>(row) * static_cast<std::size_t>(w) + static_cast<std::size_t>(col));
            sum += y;
            mx += y * x;
            mz += y * z;
          }
        }
        if (!(sum > 0)) break;
        cx = mx / sum;
        cz = mz / sum;
      }
      power.push_back(power_within(f, rg, cx, cz, focus_radius));
    }
    s.focus_jump = largest_change(power, 1);
  }
  return s;
}

}  // namespace caustix::metrics
