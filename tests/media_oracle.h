#pragma once
// Analytic single scattering for the media tests of the reference
// (reference_test.cpp) and the runtime (volume_test.cpp): the same scenes
// and the same closed forms, so both are held to one oracle.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

#include "optics_oracle.h"
#include "scene_fixture.h"

namespace caustix::test {

// A fog box [-1, 1] x [0, 2] x [-1, 1] over a bare floor, sun straight
// down (E0 = 2): the in-scatter image along -z is, per pixel, the
// pixel-box average over y of sigma_s p E0 e^(-sigma_t (2 - y))
// (1 - e^(-2 sigma_t)) / sigma_t / E0 (the light's path down to y, the
// view's path out of the box's front).
inline nlohmann::json fog_box(double scattering, double absorption) {
  nlohmann::json j = canonical_scene("glass_ball");
  j["objects"].erase(1);
  j["lights"][0]["irradiance"] = 2.0;
  j["medium"] = {{"extent", {-1, 0, -1, 1, 2, 1}}, {"scattering", scattering}, {"absorption", absorption}};
  return j;
}

// The fog box's pixel spanning [ya, yb] in height (whole in x).
inline double fog_pixel(double ss, double st, double phase, double ya, double yb) {
  const double height = yb - ya;
  ya = std::clamp(ya, 0.0, 2.0);
  yb = std::clamp(yb, 0.0, 2.0);
  if (yb <= ya) return 0;
  const double light = (std::exp(-st * (2 - yb)) - std::exp(-st * (2 - ya))) / st;  // integral over y
  return ss * phase * light / height * (1 - std::exp(-2 * st)) / st;
}

// fog_box's whole in-scatter image over [x0, x1] x [y0, y1], width x
// height pixels, row 0 at y1 (isotropic phase), row-major.
inline std::vector<double> fog_box_image(double ss, double st, double x0, double y0, double x1, double y1, int width, int height) {
  const double dx = (x1 - x0) / width, dy = (y1 - y0) / height;
  std::vector<double> out(std::size_t(width) * std::size_t(height));
  for (int row = 0; row < height; ++row) {
    const double yb = y1 - row * dy, ya = yb - dy;
    for (int col = 0; col < width; ++col) {
      const double xa = x0 + col * dx, xb = xa + dx;
      const double cover = std::max(0.0, std::min(xb, 1.0) - std::max(xa, -1.0)) / dx;
      out[std::size_t(row) * std::size_t(width) + std::size_t(col)] = cover * fog_pixel(ss, st, 1 / (4 * kPi), ya, yb);
    }
  }
  return out;
}

// flat_pool with the sun straight down, its water scattering (sigma_s 0.4,
// sigma_a 0.1) over the extent [-2, 2]^2.
inline nlohmann::json scattering_flat_pool() {
  nlohmann::json j = canonical_scene("flat_pool");
  j["lights"][0]["direction"] = {0, -1, 0};
  j["water"]["scattering"] = 0.4;
  j["water"]["absorption"] = 0.1;
  j["water"]["grid"]["extent"] = {-2, -2, 2, 2};
  return j;
}

// Its shafts at depths within the pixel [ya, yb] of height: sigma_s p E0
// T(0) e^(-sigma_t d) (1 - e^(-4 sigma_t)) / sigma_t averaged over the
// pixel, T(0) the Fresnel transmittance at normal incidence, 4 m of water
// between the point's z and the camera side of the water's extent.
inline double flat_water_pixel(double ya, double yb) {
  const double ss = 0.4, st = 0.5, level = 2.0, t0 = fresnel_t(1.0, 1.33);
  const double height = yb - ya;
  yb = std::min(yb, level);
  const double light = yb > ya ? (std::exp(-st * (level - yb)) - std::exp(-st * (level - ya))) / st / height : 0.0;
  return ss / (4 * kPi) * t0 * light * (1 - std::exp(-4 * st)) / st;
}

// fog_box(0.5, 0) under the isotropic phase and Schlick's at k = 0, 0.6
// and -0.6, imaged by `image`: k = 0 is the isotropic image (to
// `k0_tolerance` relative; 0: bit for bit) and +-0.6 scale it by
// p_k(0) / p_0 = 1 - k^2 (light down, camera along z: cos a = 0 exactly)
// to `tolerance` relative.
inline void expect_schlick_scaling(const std::function<std::vector<float>(const nlohmann::json&)>& image, double tolerance) {
  nlohmann::json j = fog_box(0.5, 0.0);
  const auto iso = image(j);
  j["medium"]["phase"] = "schlick";
  j["medium"]["anisotropy"] = 0.0;
  const auto k0 = image(j);
  j["medium"]["anisotropy"] = 0.6;
  const auto k6 = image(j);
  j["medium"]["anisotropy"] = -0.6;
  const auto km6 = image(j);
  ASSERT_EQ(iso.size(), k0.size());
  ASSERT_EQ(iso.size(), k6.size());
  ASSERT_EQ(iso.size(), km6.size());
  double sum = 0;
  for (std::size_t i = 0; i < iso.size(); ++i) {
    EXPECT_EQ(k0[i], iso[i]) << i;
    EXPECT_NEAR(k6[i], 0.64 * iso[i], tolerance * iso[i]) << i;
    EXPECT_NEAR(km6[i], 0.64 * iso[i], tolerance * iso[i]) << i;
    sum += iso[i];
  }
  EXPECT_GT(sum, 0);
}

// A glass ball (radius r, centre (0, yc, 0), index n) in a fog box
// [-h, h] x [0, top] x [-h, h] (sigma_s ss, sigma_t st, isotropic, nothing
// in the glass), sun straight down (E0 = 1) over a floor at y = 0: the
// in-scatter image along -z (scale 1/E0, the view's path out through the
// box's front z = h), the pixels of the column x in [xa, xb] and rows of
// height dy from y1 down, every row below the ball (y1 <= yc - r: no view
// ray meets the glass). Two parts, both exact:
//  - the direct beam outside the ball's shadow cylinder, from the box's
//    top: closed form in y and z, 256 points across the column;
//  - the light through the ball: the exact 3-D trace of `rings` x
//    `angles` rays (stratified over the ball's disc by area), each
//    T(theta_i)^2 (Snell at both surfaces, Fresnel in and out), attenuated
//    from the top to its entry and from its exit on, and its path's
//    in-scatter integrated in closed form over each pixel it crosses
//    (e^(-st s) for the light and e^(-st (h - z)) for the view are both
//    exponential in the path length s).
// What it leaves out, as the runtime does: light reflected at the ball
// (its Fresnel loss is counted, the reflected light not followed) and
// light leaving after an internal reflection. Row-major from y1 down.
struct FogBallColumn {
  std::vector<double> direct, through;  // per row
  double at(std::size_t row) const { return direct[row] + through[row]; }
};
inline FogBallColumn fog_ball_column(double r, double yc, double n, double h, double top, double ss, double st, double xa, double xb,
                                     double y1, double dy, int rows, int rings = 3000, int angles = 2048) {
  const double phase = 1 / (4 * kPi), dx = xb - xa;
  FogBallColumn out{std::vector<double>(std::size_t(rows)), std::vector<double>(std::size_t(rows))};
  // Integral of e^(-st (z1 - z)) dz over [za, zb] (the view's path to z1 = h).
  auto view = [&](double za, double zb) { return (std::exp(-st * (h - zb)) - std::exp(-st * (h - za))) * (zb > za ? 1 : 0) / st; };
  for (int row = 0; row < rows; ++row) {
    const double yb = y1 - row * dy, ya = yb - dy;
    const double light = (std::exp(-st * (top - yb)) - std::exp(-st * (top - ya))) / st / dy;  // mean over the row
    double zsum = 0;
    const int m = 256;
    for (int k = 0; k < m; ++k) {
      const double x = xa + (k + 0.5) * dx / m;
      double z = view(-h, h);
      if (std::fabs(x) < r) {
        const double c = std::sqrt(r * r - x * x);
        z -= view(-c, c);
      }
      zsum += z / m;
    }
    out.direct[std::size_t(row)] = ss * phase * light * zsum;
  }
  const double eta = 1 / n;
  for (int i = 0; i < rings; ++i) {
    // Equal areas: b^2 uniform.
    const double b = r * std::sqrt((i + 0.5) / rings);
    const double py = yc + std::sqrt(r * r - b * b);
    const double cos_i = (py - yc) / r, nx = b / r, ny = cos_i;
    const double cos_t = std::sqrt(1 - (1 - cos_i * cos_i) * eta * eta);
    const double dxr = (eta * cos_i - cos_t) * nx, dyr = -eta + (eta * cos_i - cos_t) * ny;
    const double t = -2 * (b * dxr + (py - yc) * dyr);
    const double qx = b + t * dxr, qy = py + t * dyr;
    const double mx = qx / r, my = (qy - yc) / r;
    const double c1 = dxr * mx + dyr * my;
    const double k = 1 - n * n * (1 - c1 * c1);
    if (k <= 0) continue;
    const double ox = n * dxr + (std::sqrt(k) - n * c1) * mx, oy = n * dyr + (std::sqrt(k) - n * c1) * my;
    const double tr = fresnel_t(cos_i, n);
    const double power = tr * tr * std::exp(-st * (top - py)) * kPi * r * r / (double(rings) * angles);
    if (oy >= 0) continue;
    const double s_floor = -qy / oy;
    for (int j = 0; j < angles; ++j) {
      const double phi = 2 * kPi * (j + 0.5 + 0.37 * (i % 7) / 7.0) / angles;
      const double cp = std::cos(phi), sp = std::sin(phi);
      const double X = qx * cp, Z = qx * sp, Dx = ox * cp, Dz = ox * sp;
      // s where the path is inside the column, the box's sides and above the floor.
      double s0 = 0, s1 = s_floor;
      auto clip = [&](double o, double d, double lo, double hi) {
        if (std::fabs(d) < 1e-15) {
          if (o < lo || o > hi) s1 = -1;
          return;
        }
        double a = (lo - o) / d, c = (hi - o) / d;
        if (a > c) std::swap(a, c);
        s0 = std::max(s0, a);
        s1 = std::min(s1, c);
      };
      clip(X, Dx, xa, xb);
      clip(X, Dx, -h, h);
      clip(Z, Dz, -h, h);
      if (s1 <= s0) continue;
      // Rows: y = qy + s oy falls with s.
      const double k_s = st * (1 - Dz);  // e^(-st s) e^(-st (h - Z - s Dz)) = e^(-st (h - Z)) e^(-k_s s)
      const double base = power * ss * phase * std::exp(-st * (h - Z)) / (dx * dy);
      int row = std::max(0, int(std::floor((y1 - (qy + s0 * oy)) / dy)));
      for (; row < rows; ++row) {
        const double yb = y1 - row * dy, ya = yb - dy;
        const double sa = std::max(s0, (yb - qy) / oy), sb = std::min(s1, (ya - qy) / oy);
        if (sa >= s1) break;
        if (sb <= sa) continue;
        const double len = k_s * (sb - sa) < 1e-9 ? (sb - sa) * std::exp(-k_s * sa) : (std::exp(-k_s * sa) - std::exp(-k_s * sb)) / k_s;
        out.through[std::size_t(row)] += base * len;
      }
    }
  }
  return out;
}

}  // namespace caustix::test
