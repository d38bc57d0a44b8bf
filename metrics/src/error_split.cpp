#include "caustix/metrics/error_split.h"

#include <algorithm>
#include <cmath>

namespace caustix::metrics {
namespace {

enum Class : std::uint8_t { kOutside, kSilhouette, kSelfShadow, kTerminator, kCastShadow, kFold, kSlope0 };
constexpr double kSlopeEdges[] = {0.2, 0.5, 0.8, 0.95};  // |n_y| bin edges
constexpr double kGrazing = 0.2;                         // |cosine| below which light grazes
constexpr double kDark = 0.1;                            // of the covered lit mean: in shadow
constexpr double kFoldRatio = 2.0;                       // 3 x 3 max / min of the reference

}  // namespace

ErrorSplit split_error(const Image& a, const Image& b, const Image& aux) {
  const std::size_t n = static_cast<std::size_t>(a.width) * static_cast<std::size_t>(a.height);
  ErrorSplit out;
  out.classes = {{"outside"}, {"silhouette"}, {"self-shadow"}, {"terminator"}, {"cast-shadow"}, {"fold"},
                 {"n_y 0-0.2"}, {"n_y 0.2-0.5"}, {"n_y 0.5-0.8"}, {"n_y 0.8-0.95"}, {"n_y 0.95-1"}};
  out.class_of.assign(n, kOutside);
  auto coverage = [&](std::size_t i) { return aux.rgb[3 * i]; };
  auto cosine = [&](std::size_t i) { return aux.rgb[3 * i + 2]; };
  auto covered = [&](std::size_t i) { return coverage(i) >= 1.0f; };
  // The reference's mean over covered pixels facing the light: the scale
  // for "dark".
  double lit_sum = 0;
  std::size_t lit = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (covered(i) && cosine(i) >= kGrazing) {
      lit_sum += luminance(b, i);
      ++lit;
    }
  }
  const double dark = lit > 0 ? kDark * lit_sum / static_cast<double>(lit) : 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(a.width) + static_cast<std::size_t>(x);
      const double ref = luminance(b, i);
      std::uint8_t c;
      if (coverage(i) <= 0.0f) {
        c = ref > 0 ? kSilhouette : kOutside;
      } else if (!covered(i)) {
        c = kSilhouette;
      } else if (cosine(i) < -kGrazing) {
        c = kSelfShadow;
      } else if (cosine(i) < kGrazing) {
        c = kTerminator;
      } else if (ref < dark) {
        c = kCastShadow;
      } else {
        double lo = ref, hi = ref;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int yy = y + dy, xx = x + dx;
            if (yy < 0 || xx < 0 || yy >= a.height || xx >= a.width) continue;
            const std::size_t j = static_cast<std::size_t>(yy) * static_cast<std::size_t>(a.width) + static_cast<std::size_t>(xx);
            if (coverage(j) <= 0.0f) continue;
            lo = std::min(lo, luminance(b, j));
            hi = std::max(hi, luminance(b, j));
          }
        }
        if (hi > kFoldRatio * lo) {
          c = kFold;
        } else {
          const double ny = aux.rgb[3 * i + 1];
          c = kSlope0;
          for (double edge : kSlopeEdges) c = static_cast<std::uint8_t>(c + (ny >= edge ? 1 : 0));
        }
      }
      out.class_of[i] = c;
      ClassError& e = out.classes[c];
      const double d = luminance(a, i) - ref;
      ++e.pixels;
      e.reference += ref;
      e.abs_error += std::fabs(d);
      e.signed_error += d;
      out.total_abs_error += std::fabs(d);
      out.total_reference += ref;
    }
  }
  return out;
}

}  // namespace caustix::metrics
