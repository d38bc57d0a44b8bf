#include "caustix/bake/position_map.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace caustix::bake {
namespace {

double dotd(const Vec3d& a, const Vec3f& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

struct ScreenTri {
  double x[3], y[3], v[3];  // texel-space x (columns), y (rows), frame V
  int row0, row1;           // rows whose centres may be covered
};

}  // namespace

Vec3d to_frame(const BoundingFrame& f, const Vec3d& p) {
  const Vec3d d{p[0] - f.origin[0], p[1] - f.origin[1], p[2] - f.origin[2]};
  return {dotd(d, f.u), dotd(d, f.v), dotd(d, f.w)};
}

Vec3d from_frame(const BoundingFrame& f, const Vec3d& c) {
  Vec3d p = f.origin;
  for (std::size_t k = 0; k < 3; ++k) p[k] += c[0] * f.u[k] + c[1] * f.v[k] + c[2] * f.w[k];
  return p;
}

std::array<double, 2> texel_center(const BoundingFrame& f, std::uint32_t size, std::uint32_t row, std::uint32_t col) {
  const double hu = f.half[0], hw = f.half[2];
  return {-hu + (col + 0.5) * 2.0 * hu / size, -hw + (row + 0.5) * 2.0 * hw / size};
}

double depth_to_v(const BoundingFrame& f, std::uint16_t q) {
  const double t = static_cast<double>(q) / kDepthQuantum;
  return f.half[1] - t * 2.0 * f.half[1];
}

double depth_precision(const BoundingFrame& f) { return 2.0 * f.half[1] / kDepthQuantum / 2.0; }

void rasterize_position_map(const std::vector<Vec3d>& world, const std::vector<std::array<std::uint32_t, 3>>& tris,
                            const Vec3f& albedo, LevelMap& map) {
  const BoundingFrame& f = map.frame;
  const std::uint32_t s = map.map_size;
  const double sx = s / (2.0 * f.half[0]), sy = s / (2.0 * f.half[2]);

  std::vector<ScreenTri> screen;
  screen.reserve(tris.size());
  for (const auto& t : tris) {
    ScreenTri st{};
    double ymin = 1e300, ymax = -1e300;
    for (int k = 0; k < 3; ++k) {
      const Vec3d c = to_frame(f, world[t[static_cast<std::size_t>(k)]]);
      st.x[k] = (c[0] + f.half[0]) * sx;
      st.y[k] = (c[2] + f.half[2]) * sy;
      st.v[k] = c[1];
      ymin = std::min(ymin, st.y[k]);
      ymax = std::max(ymax, st.y[k]);
    }
    // Rows r with centre r + 0.5 in [ymin, ymax].
    st.row0 = static_cast<int>(std::max(0.0, std::ceil(ymin - 0.5)));
    st.row1 = static_cast<int>(std::min(static_cast<double>(s) - 1, std::floor(ymax - 0.5)));
    if (st.row0 <= st.row1) screen.push_back(st);
  }

  const double empty = -std::numeric_limits<double>::infinity();
  std::vector<double> best(std::size_t{s} * s, empty);
  constexpr int kBand = 16;
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>((s + kBand - 1) / kBand)), [&](const tbb::blocked_range<int>& bands) {
    for (int band = bands.begin(); band != bands.end(); ++band) {
      const int r0 = band * kBand, r1 = std::min(static_cast<int>(s) - 1, r0 + kBand - 1);
      for (const ScreenTri& t : screen) {
        if (t.row1 < r0 || t.row0 > r1) continue;
        const double area = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.x[2] - t.x[0]) * (t.y[1] - t.y[0]);
        if (std::fabs(area) < 1e-12) continue;  // seen edge-on: covers no texel centre
        const double xmin = std::min({t.x[0], t.x[1], t.x[2]}), xmax = std::max({t.x[0], t.x[1], t.x[2]});
        const int c0 = static_cast<int>(std::max(0.0, std::ceil(xmin - 0.5)));
        const int c1 = static_cast<int>(std::min(static_cast<double>(s) - 1, std::floor(xmax - 0.5)));
        for (int r = std::max(r0, t.row0); r <= std::min(r1, t.row1); ++r) {
          const double py = r + 0.5;
          for (int c = c0; c <= c1; ++c) {
            const double px = c + 0.5;
            // Barycentric weights from edge functions; inclusive edges so
            // shared edges leave no crack (max() makes double cover harmless).
            const double w0 = ((t.x[2] - t.x[1]) * (py - t.y[1]) - (t.y[2] - t.y[1]) * (px - t.x[1])) / area;
            const double w1 = ((t.x[0] - t.x[2]) * (py - t.y[2]) - (t.y[0] - t.y[2]) * (px - t.x[2])) / area;
            const double w2 = 1.0 - w0 - w1;
            constexpr double kTol = -1e-9;
            if (w0 < kTol || w1 < kTol || w2 < kTol) continue;
            const double v = w0 * t.v[0] + w1 * t.v[1] + w2 * t.v[2];
            double& b = best[static_cast<std::size_t>(r) * s + static_cast<std::size_t>(c)];
            b = std::max(b, v);
          }
        }
      }
    }
  });

  map.depth.assign(best.size(), kEmptyDepth);
  map.diffuse.assign(best.size() * 3, 0);
  const double h = 2.0 * f.half[1];
  std::array<std::uint8_t, 3> rgb{};
  for (std::size_t k = 0; k < 3; ++k) rgb[k] = static_cast<std::uint8_t>(std::lround(std::clamp(albedo[k], 0.0f, 1.0f) * 255.0f));
  for (std::size_t i = 0; i < best.size(); ++i) {
    if (best[i] == empty) continue;
    const double t = std::clamp((f.half[1] - best[i]) / h, 0.0, 1.0);
    map.depth[i] = static_cast<std::uint16_t>(std::lround(t * kDepthQuantum));
    std::copy(rgb.begin(), rgb.end(), map.diffuse.begin() + static_cast<std::ptrdiff_t>(i * 3));
  }
}

}  // namespace caustix::bake
