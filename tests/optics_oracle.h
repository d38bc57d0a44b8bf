#pragma once
// Closed-form optics the tests check against, written independently of the
// runtime's shaders and the reference tracer.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace caustix::test {

inline constexpr double kPi = 3.14159265358979323846;

// Unpolarised Fresnel transmittance from air into a medium of index n.
inline double fresnel_t(double cos_i, double n) {
  const double sin_t = std::sqrt(1 - cos_i * cos_i) / n, cos_t = std::sqrt(1 - sin_t * sin_t);
  const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t), rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  return 1 - 0.5 * (rs * rs + rp * rp);
}

// Exact 2-D trace of the ball lens: a ray at distance b from the axis
// refracts into and out of the sphere (radius r, centre height yc, index
// n) and lands on y = 0 at distance rho from the axis, carrying
// T(theta_i)^2 (the exit transmittance equals the entry one by symmetry);
// `weight` is the flux of the ring of incident rays it stands for, per unit
// incident irradiance.
struct Landing {
  double rho, weight;
};
inline std::vector<Landing> ball_lens(double r, double yc, double n, int samples) {
  std::vector<Landing> out;
  for (int i = 0; i < samples; ++i) {
    const double b = r * (i + 0.5) / samples;
    const double px = b, py = yc + std::sqrt(r * r - b * b);
    const double nx = px / r, ny = (py - yc) / r;  // outward normal at entry
    const double cos_i = ny;                        // incident (0, -1)
    const double sin_t = std::sqrt(1 - cos_i * cos_i) / n, cos_t = std::sqrt(1 - sin_t * sin_t);
    // Refracted direction: eta d + (eta cos_i - cos_t) normal.
    const double eta = 1 / n;
    double dx = eta * 0 + (eta * cos_i - cos_t) * nx, dy = eta * -1 + (eta * cos_i - cos_t) * ny;
    const double t = -2 * ((px - 0) * dx + (py - yc) * dy) / (dx * dx + dy * dy);
    const double qx = px + t * dx, qy = py + t * dy;
    const double mx = qx / r, my = (qy - yc) / r;  // outward normal at exit
    const double c1 = dx * mx + dy * my;           // cos of the internal angle
    const double k = 1 - n * n * (1 - c1 * c1);
    const double ox = n * dx + (std::sqrt(k) - n * c1) * mx, oy = n * dy + (std::sqrt(k) - n * c1) * my;
    const double s = -qy / oy;
    const double T = fresnel_t(cos_i, n);
    out.push_back({std::fabs(qx + s * ox), T * T * 2 * kPi * b * (r / samples)});
  }
  return out;
}

// Height at which the ray entering the ball lens (radius r, centre height
// yc, index n) at distance b from the axis, travelling straight down,
// crosses the axis after leaving the ball: the paraxial focus for b -> 0
// (yc - n r / (2 (n - 1))), moving up toward the ball as b grows
// (spherical aberration).
inline double axis_crossing(double r, double yc, double n, double b) {
  const double py = yc + std::sqrt(r * r - b * b);
  const double nx = b / r, ny = (py - yc) / r;
  const double cos_i = ny, eta = 1 / n;
  const double cos_t = std::sqrt(1 - (1 - cos_i * cos_i) / (n * n));
  const double dx = (eta * cos_i - cos_t) * nx, dy = -eta + (eta * cos_i - cos_t) * ny;
  const double t = -2 * (b * dx + (py - yc) * dy) / (dx * dx + dy * dy);
  const double qx = b + t * dx, qy = py + t * dy;
  const double mx = qx / r, my = (qy - yc) / r;
  const double c1 = dx * mx + dy * my;
  const double k = 1 - n * n * (1 - c1 * c1);
  const double ox = n * dx + (std::sqrt(k) - n * c1) * mx, oy = n * dy + (std::sqrt(k) - n * c1) * my;
  return qy + (-qx / ox) * oy;
}

// Radius of the disc that holds `fraction` of the landed flux.
inline double radius_enclosing(std::vector<Landing> l, double fraction) {
  std::sort(l.begin(), l.end(), [](const Landing& a, const Landing& b) { return a.rho < b.rho; });
  double total = 0, acc = 0;
  for (const auto& x : l) total += x.weight;
  for (const auto& x : l) {
    acc += x.weight;
    if (acc >= fraction * total) return x.rho;
  }
  return l.back().rho;
}

// Flux landing within radius r.
inline double encircled(const std::vector<Landing>& l, double r) {
  double sum = 0;
  for (const auto& x : l) sum += x.rho < r ? x.weight : 0;
  return sum;
}

// The wedge prism of assets/meshes/prism.obj (slope normal (1, 2, 0)/sqrt 5,
// bottom at y = 0.3) under a sun straight down: light entering the slope
// and leaving through the bottom lands shifted along x by this (negative:
// towards the thick end) on the floor y = 0; Snell at both faces.
inline double prism_floor_shift(double n) {
  const double eta = 1 / n, s5 = std::sqrt(5.0);
  const double n1[2] = {1 / s5, 2 / s5};
  const double cos1 = n1[1], cos1t = std::sqrt(1 - eta * eta * (1 - cos1 * cos1));
  const double d1[2] = {(eta * cos1 - cos1t) * n1[0], -eta + (eta * cos1 - cos1t) * n1[1]};
  const double sin2t = d1[0] / eta;  // out of the bottom: the tangential part scaled by n
  return 0.3 * sin2t / std::sqrt(1 - sin2t * sin2t);
}

// glass_ball's floor image (E/E0, n x n pixels over |x|, |z| < half, row 0
// at z = -half) against the exact trace: the light through the ball that
// lands on the floor (everything minus the direct light outside the ball's
// shadow, its silhouette the UV sphere's 48-gon equator), the peak, and
// the radius holding half the transmitted flux, measured and exact.
struct BallLensFloor {
  double transmitted = 0, expected = 0;
  double peak_x = 0, peak_z = 0, peak_e = 0;
  double m50 = 0, r50 = 0;
  std::vector<Landing> measured, exact;  // for encircled()
};
inline BallLensFloor ball_lens_floor(const std::vector<float>& e, int n, double half, double ior = 1.5) {
  BallLensFloor b;
  const double pix = 2 * half / n;
  for (const auto& l : ball_lens(0.5, 0.75, ior, 20000)) {
    if (l.rho < half) b.exact.push_back(l);
  }
  for (const auto& l : b.exact) b.expected += l.weight;
  const double shadow = 0.5 * 48 * std::sin(2 * kPi / 48) * 0.25;
  double total = 0;
  for (float v : e) total += v * pix * pix;
  b.transmitted = total - (4 * half * half - shadow);
  const double r_shadow = 0.5 * std::cos(kPi / 48);
  std::size_t peak = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double x = -half + (j + 0.5) * pix, z = -half + (i + 0.5) * pix, rho = std::hypot(x, z);
      const std::size_t k = static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j);
      if (e[k] > e[peak]) peak = k;
      const double direct = rho > r_shadow ? 1.0 : 0.0;
      b.measured.push_back({rho, std::max(0.0, e[k] - direct) * pix * pix});
    }
  }
  b.peak_x = -half + (static_cast<double>(peak % static_cast<std::size_t>(n)) + 0.5) * pix;
  b.peak_z = -half + (static_cast<double>(peak / static_cast<std::size_t>(n)) + 0.5) * pix;
  b.peak_e = e[peak];
  b.r50 = radius_enclosing(b.exact, 0.5);
  b.m50 = radius_enclosing(b.measured, 0.5);
  return b;
}

// Exact landings (a radially symmetric pattern about the origin) as an
// n x n image of E/E0 in pixels `pix` wide, pixel (i, j) over
// [x0 + j pix, x0 + (j + 1) pix] x [x0 + i pix, ...]: each landing's ring
// spread over `angles` points (their angles offset per ring, so that no
// ray of points lines up with the pixel grid). What a renderer's pixel
// image is compared with, pixel set for pixel set.
inline std::vector<double> landing_image(const std::vector<Landing>& l, int n, double x0, double pix, int angles = 512) {
  std::vector<double> img(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
  for (std::size_t k = 0; k < l.size(); ++k) {
    const double w = l[k].weight / angles / (pix * pix);
    for (int a = 0; a < angles; ++a) {
      const double phi = 2 * kPi * (a + 0.618034 * static_cast<double>(k % 97)) / angles;
      const int j = static_cast<int>(std::floor((l[k].rho * std::cos(phi) - x0) / pix));
      const int i = static_cast<int>(std::floor((l[k].rho * std::sin(phi) - x0) / pix));
      if (i < 0 || j < 0 || i >= n || j >= n) continue;
      img[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] += w;
    }
  }
  return img;
}

// Exact landings (a radially symmetric pattern about (cx, cz)) as an
// n x n image of E/E0 averaged over pixels `pix` wide, pixel (i, j) over
// [x0 + j pix, x0 + (j + 1) pix] x [x0 + i pix, ...]: each landing's ring
// of light split among the pixels by the exact length of its arc in each
// (the angles where the circle crosses the pixel grid's lines), so that
// the image changes continuously as the pattern moves, unlike points.
inline std::vector<double> ring_image(const std::vector<Landing>& l, int n, double x0, double pix, double cx, double cz) {
  std::vector<double> img(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
  const auto add = [&](double x, double z, double w) {
    const int j = static_cast<int>(std::floor((x - x0) / pix)), i = static_cast<int>(std::floor((z - x0) / pix));
    if (i >= 0 && j >= 0 && i < n && j < n) img[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] += w;
  };
  std::vector<double> angles;
  for (const Landing& ring : l) {
    const double r = ring.rho, w = ring.weight / (pix * pix);
    if (r < 1e-12) {
      add(cx, cz, w);
      continue;
    }
    angles.assign({0.0, 2 * kPi});
    for (int k = 0; k <= n; ++k) {
      const double line = x0 + k * pix, c = (line - cx) / r, s = (line - cz) / r;
      if (std::fabs(c) < 1) {
        angles.push_back(std::acos(c));
        angles.push_back(2 * kPi - std::acos(c));
      }
      if (std::fabs(s) < 1) {
        const double a = std::asin(s);
        angles.push_back(a < 0 ? a + 2 * kPi : a);
        angles.push_back(kPi - a);
      }
    }
    std::sort(angles.begin(), angles.end());
    for (std::size_t q = 0; q + 1 < angles.size(); ++q) {
      const double d = angles[q + 1] - angles[q], mid = 0.5 * (angles[q] + angles[q + 1]);
      if (d > 0) add(cx + r * std::cos(mid), cz + r * std::sin(mid), w * d / (2 * kPi));
    }
  }
  return img;
}

// Focal measures of an n x n image of E/E0 (pixels `pix` wide, corner at
// (x0, x0)): the power (m^2 E0) of the pixels whose centres lie within r
// of the origin, and the brightest `bin` x `bin` block of pixels' mean
// (blocks aligned to the image's corner).
inline double power_within(const std::vector<double>& img, int n, double x0, double pix, double r) {
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (std::hypot(x0 + (j + 0.5) * pix, x0 + (i + 0.5) * pix) < r) {
        sum += img[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] * pix * pix;
      }
    }
  }
  return sum;
}
inline double peak_block(const std::vector<double>& img, int n, int bin) {
  double best = 0;
  for (int bi = 0; bi + bin <= n; bi += bin) {
    for (int bj = 0; bj + bin <= n; bj += bin) {
      double sum = 0;
      for (int i = bi; i < bi + bin; ++i) {
        for (int j = bj; j < bj + bin; ++j) sum += img[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)];
      }
      best = std::max(best, sum / (bin * bin));
    }
  }
  return best;
}

// A dispersive ball's images at the F, d and C lines (got[0..2]): whether
// the check tells the lines apart, the F image against the C line's exact
// pattern (and back) missing its encircled power within 2 cm by more than
// 15 % (beyond the tests' own 10 %). Prints both under `label`.
inline bool lines_apart(const std::vector<BallLensFloor>& got, const char* label) {
  auto miss = [&](std::size_t a, std::size_t b) { return encircled(got[a].measured, 0.02) / encircled(got[b].exact, 0.02) - 1; };
  const double f_on_c = miss(0, 2), c_on_f = miss(2, 0);
  std::printf("%s F image against the C line's exact pattern: encircled power within 2 cm %+.1f %%; C against F's %+.1f %%\n", label,
              100 * f_on_c, 100 * c_on_f);
  return std::fabs(f_on_c) > 0.15 && std::fabs(c_on_f) > 0.15;
}

}  // namespace caustix::test
