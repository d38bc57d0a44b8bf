// The runtime's volume caustics and single scattering (Pfeuti)
// against physics and the reference: the analytic fog integral, energy
// (power in = scattered + absorbed + leaving + reflected + truncated, and
// the radiance grid holds what was scattered), the Schlick phase, flat
// scattering water's shafts, the ball lens's focus in fog against the
// exact photon tracer, and the extremes. Real GL (llvmpipe here).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <tuple>
#include <vector>

#include "bake_fixture.h"
#include "gl_objects.h"
#include "caustix/bake/bake.h"
#include "caustix/formats/spectrum.h"
#include "gl_fixture.h"
#include "media_oracle.h"
#include "reference.h"

namespace caustix::test {
namespace {

using sample::InscatterImage;
using sample::InscatterRequest;
using sample::Renderer;

class Volume : public GlTest {
 protected:
  static std::unique_ptr<Renderer> make(const nlohmann::json& j, const std::string& tag) {
    return bake_and_create(write_scene(j, tag));
  }
  static InscatterImage inscatter(Renderer& r, InscatterRequest q) {
    auto img = r.render_inscatter(q);
    EXPECT_TRUE(img.ok()) << img.error().message;
    return img.ok() ? std::move(*img) : InscatterImage{};
  }
  // The fog box (media_oracle.h) seen whole: 24 x 24 pixels of 12.5 cm,
  // 4 x 4 rays each, at the bake's options.
  static InscatterRequest fog_box_view(Renderer& r) {
    InscatterRequest q;
    q.x0 = -1.5, q.y0 = -0.5, q.x1 = 1.5, q.y1 = 2.5;
    q.width = q.height = 24;
    q.pixel_samples = 4;
    q.caustics = r.engine().default_options();
    return q;
  }
};

// The energy split of one run, to fixed-point rounding (the GPU adds
// integers: about 2^-28 of the light's power per photon and tally).
void expect_energy_balance(const runtime::VolumeStats& v) {
  ASSERT_TRUE(v.active);
  ASSERT_GT(v.power_in, 0);
  const double out = v.scattered + v.absorbed + v.leaving + v.reflected + v.truncated;
  EXPECT_NEAR(out / v.power_in, 1.0, 1e-3) << "in " << v.power_in << " out " << out;
  EXPECT_NEAR(v.deposited / v.scattered, 1.0, 1e-3) << "grid " << v.deposited << " scattered " << v.scattered;
}

TEST_F(Volume, FogWithoutObjectsIsTheAnalyticIntegral) {
  const double ss = 0.5, sa = 0.25, st = ss + sa;
  auto r = make(fog_box(ss, sa), "volume_fog");
  ASSERT_TRUE(r);
  const InscatterRequest q = fog_box_view(*r);
  const InscatterImage img = inscatter(*r, q);
  ASSERT_EQ(img.rgb.size(), 24u * 24u * 3u);
  const std::vector<double> want = fog_box_image(ss, st, q.x0, q.y0, q.x1, q.y1, 24, 24);
  double worst = 0, sum_err = 0, sum = 0;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const double expected = want[i], got = img.rgb[3 * i + 1];
    // 2 %: the radiance grid (3.1 cm voxels) samples e^(-sigma_t d)
    // trilinearly (0.01 % error) and the view rays sample it at half a
    // voxel with a jittered start (16 rays a pixel: 1 % ripple at most);
    // the photons are stratified, one per 0.8 cm cell.
    EXPECT_NEAR(got, expected, 0.02 * expected + 1e-6) << "row " << i / 24 << " col " << i % 24;
    if (expected > 0) worst = std::max(worst, std::fabs(got / expected - 1));
    sum_err += std::fabs(got - expected);
    sum += expected;
  }
  std::printf("[volume fog] worst pixel %.4f, relative L1 %.5f\n", worst, sum_err / sum);
  RecordProperty("fog_worst_relative_error", std::to_string(worst));
  // Every photon enters the box's top (4 m^2 at E0) and goes straight
  // down: the split is exact.
  const runtime::VolumeStats& v = img.stats;
  expect_energy_balance(v);
  const double taken = 4 * (1 - std::exp(-2 * st));
  EXPECT_NEAR(v.power_in, 4.0, 4e-3);
  EXPECT_NEAR(v.scattered, taken * ss / st, 1e-3 * taken);
  EXPECT_NEAR(v.absorbed, taken * sa / st, 1e-3 * taken);
  EXPECT_NEAR(v.leaving, 4 * std::exp(-2 * st), 4e-3);
  EXPECT_EQ(v.grid_size[0], 64u);
}

// Several suns in one viewing pass (volume_view.frag marches for as many
// lights as its texture units hold, five here, and draws again for the
// rest): seven suns over the fog box, straight down and tilted up to 40
// degrees, against each one's single scattering integrated here along the
// view rays: sigma_s p E_k e^(-sigma_t l_k) e^(-sigma_t (1 - z)) over z in
// the box, l_k the path from the point back to the box's surface towards
// sun k, per pixel the mean of 8 x 8 rays; the image in units of the
// first sun's irradiance.
TEST_F(Volume, SeveralSunsInOneMarchAddUp) {
  const double ss = 0.5, sa = 0.25, st = ss + sa;
  nlohmann::json j = fog_box(ss, sa);
  const double suns[7][3] = {{0.0, 0.0, 2.0},  {0.36, 0.0, 1.0},  {-0.58, 0.2, 0.5}, {0.0, 0.84, 1.0},
                             {0.3, -0.3, 0.7}, {-0.2, -0.5, 0.4}, {0.5, 0.5, 0.3}};  // direction's x and z for y = -1, irradiance
  j["lights"] = nlohmann::json::array();
  for (int k = 0; k < 7; ++k) {
    j["lights"].push_back({{"type", "directional"},
                           {"name", "sun" + std::to_string(k)},
                           {"direction", {suns[k][0], -1.0, suns[k][1]}},
                           {"irradiance", suns[k][2]}});
  }
  auto r = make(j, "volume_seven_suns");
  ASSERT_TRUE(r);
  const InscatterRequest q = fog_box_view(*r);
  const InscatterImage img = inscatter(*r, q);
  ASSERT_EQ(img.rgb.size(), 24u * 24u * 3u);
  // The path from p to the box [-1, 1] x [0, 2] x [-1, 1] along s.
  const auto to_surface = [](const double p[3], const double s[3]) {
    const double lo[3] = {-1, 0, -1}, hi[3] = {1, 2, 1};
    double t = 1e30;
    for (int a = 0; a < 3; ++a) {
      if (s[a] > 0) t = std::min(t, (hi[a] - p[a]) / s[a]);
      if (s[a] < 0) t = std::min(t, (lo[a] - p[a]) / s[a]);
    }
    return t;
  };
  const double dx = (q.x1 - q.x0) / 24, dy = (q.y1 - q.y0) / 24;
  double worst = 0, sum_err = 0, sum = 0;
  for (int row = 0; row < 24; ++row) {
    for (int col = 0; col < 24; ++col) {
      double expected = 0;
      for (int k = 0; k < 7; ++k) {
        const double n = std::sqrt(suns[k][0] * suns[k][0] + 1 + suns[k][1] * suns[k][1]);
        const double towards[3] = {-suns[k][0] / n, 1 / n, -suns[k][1] / n};
        double light = 0;
        for (int sy = 0; sy < 8; ++sy) {
          for (int sx = 0; sx < 8; ++sx) {
            const double x = q.x0 + (col + (sx + 0.5) / 8) * dx, y = q.y1 - (row + (sy + 0.5) / 8) * dy;
            if (std::fabs(x) > 1 || y < 0 || y > 2) continue;
            for (int iz = 0; iz < 200; ++iz) {
              const double z = -1 + (iz + 0.5) / 100, p[3] = {x, y, z};
              light += std::exp(-st * (to_surface(p, towards) + 1 - z)) / 100;
            }
          }
        }
        expected += ss / (4 * kPi) * suns[k][2] / suns[0][2] * light / 64;
      }
      const double got = img.rgb[3 * (std::size_t(row) * 24 + std::size_t(col)) + 1];
      // 2 %, as for one sun (FogWithoutObjectsIsTheAnalyticIntegral).
      EXPECT_NEAR(got, expected, 0.02 * expected + 1e-6) << "row " << row << " col " << col;
      if (expected > 0) worst = std::max(worst, std::fabs(got / expected - 1));
      sum_err += std::fabs(got - expected);
      sum += expected;
    }
  }
  std::printf("[volume suns] seven suns: worst pixel %.4f, relative L1 %.5f\n", worst, sum_err / sum);
}

// A spot light over the fog box: the power entering the fog is
// the integral over the box's top of I f(a) cos(theta) / r^2, f
// KHR_lights_punctual's falloff written here from the angles; against the
// same light without its cone (which takes the integral without f).
TEST_F(Volume, SpotLightFeedsTheFogItsFalloff) {
  const double lp[3] = {0.2, 4.0, 0.0}, tilt = 12 * 3.14159265358979 / 180;
  const double axis[3] = {std::sin(tilt), -std::cos(tilt), 0.0};
  const double co = std::cos(35 * 3.14159265358979 / 180), ci = std::cos(15 * 3.14159265358979 / 180);
  double with = 0, without = 0;
  const int n = 400;
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const double d[3] = {-1 + 2 * (a + 0.5) / n - lp[0], 2 - lp[1], -1 + 2 * (b + 0.5) / n - lp[2]};
      const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], r = std::sqrt(r2);
      const double t = std::clamp(((d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2]) / r - co) / (ci - co), 0.0, 1.0);
      const double e = 3.0 * (-d[1] / r) / r2 * (4.0 / (n * n));
      with += t * t * e;
      without += e;
    }
  }
  double power[2] = {0, 0};
  for (int cone = 0; cone < 2; ++cone) {
    nlohmann::json j = fog_box(0.5, 0.25);
    nlohmann::json l{{"type", cone ? "spot" : "point"}, {"position", {lp[0], lp[1], lp[2]}}, {"intensity", 3.0}};
    if (cone) {
      l["direction"] = {axis[0], axis[1], axis[2]};
      l["inner_cone_deg"] = 15;
      l["outer_cone_deg"] = 35;
    }
    j["lights"] = nlohmann::json::array({l});
    auto r = make(j, "volume_spot");
    ASSERT_TRUE(r);
    InscatterRequest q;
    q.x0 = -1.5, q.y0 = -0.5, q.x1 = 1.5, q.y1 = 2.5;
    q.width = q.height = 8;
    q.caustics = r->engine().default_options();
    const InscatterImage img = inscatter(*r, q);
    expect_energy_balance(img.stats);
    power[cone] = img.stats.power_in;
  }
  std::printf("[volume spot] power in: point %.4f (oracle %.4f), spot %.4f (oracle %.4f)\n", power[0], without, power[1], with);
  EXPECT_NEAR(power[0] / without, 1.0, 0.005);  // stratified photons, one per cell of the window
  EXPECT_NEAR(power[1] / with, 1.0, 0.005);
  EXPECT_LT(with, 0.8 * without);  // the cone cuts a part worth seeing
}

// Schlick with k = 0 is the isotropic image (bit for bit: the same photons
// and the same phase value); with k the image scales by p_k(0) / p_0 =
// 1 - k^2 (light down, camera along z: cos a = 0 exactly).
TEST_F(Volume, SchlickPhaseScalesAsThePhaseFunction) {
  auto image = [&](const nlohmann::json& j) {
    auto r = make(j, "volume_phase");
    EXPECT_TRUE(r);
    if (!r) return std::vector<float>{};
    InscatterRequest q;
    q.x0 = -1, q.y0 = 0, q.x1 = 1, q.y1 = 2;
    q.width = q.height = 12;
    q.caustics = r->engine().default_options();
    q.caustics.volume.photons = 64;
    return inscatter(*r, q).rgb;
  };
  expect_schlick_scaling(image, 1e-4);
}

// The flat scattering pool from the side: 12 x 20 pixels over x in
// [-1.5, 1.5], y in [0, 2.5]; and the analytic value of a row's pixels.
InscatterRequest pool_side_view(Renderer& r) {
  InscatterRequest q;
  q.x0 = -1.5, q.y0 = 0, q.x1 = 1.5, q.y1 = 2.5;
  q.width = 12, q.height = 20;
  q.pixel_samples = 4;
  q.caustics = r.engine().default_options();
  return q;
}
double pool_side_row(int row) {
  const double dy = 2.5 / 20;
  return flat_water_pixel(2.5 - (row + 1) * dy, 2.5 - row * dy);
}

TEST_F(Volume, FlatScatteringWaterIsUniformAndAnalytic) {
  auto r = make(scattering_flat_pool(), "volume_water");
  ASSERT_TRUE(r);
  const InscatterImage img = inscatter(*r, pool_side_view(*r));
  ASSERT_EQ(img.rgb.size(), 12u * 20u * 3u);
  for (int row = 0; row < 20; ++row) {
    const double expected = pool_side_row(row);
    for (int col = 0; col < 12; ++col) {
      const double got = img.rgb[3 * (std::size_t(row) * 12 + std::size_t(col)) + 1];
      // 2 % as for the fog; the row holding the surface (y 2.0 is a pixel
      // edge) is exact in coverage.
      EXPECT_NEAR(got, expected, 0.02 * expected + 1e-6) << "row " << row << " col " << col;
    }
  }
  // The water's top (16 m^2 under the sun) takes T(0) of E0.
  const double t0 = fresnel_t(1.0, 1.33), st = 0.5, ss = 0.4;
  expect_energy_balance(img.stats);
  EXPECT_NEAR(img.stats.power_in, 16 * t0, 16e-3);
  EXPECT_NEAR(img.stats.scattered, 16 * t0 * (1 - std::exp(-2 * st)) * ss / st, 1e-2);
}

// Dispersion in the media: the flat scattering pool with the
// water's dispersion at its largest, 20 (V_d 1: n 1.9096 at 400 nm, 1.1823
// at 700 nm). The light comes straight down, so only the Fresnel
// transmittance at the top depends on the wavelength:
// - a monochromatic run takes T(0, n(lambda)) of E0 in (16 m^2, to the
//   fixed point's 1e-3 as above; T 0.9032 at 400 nm, 0.9931 at 700 nm);
// - the RGB image of 4 bins is the flat-water image times each channel's
//   bin-weighted sum of T(0, n) over T(0, 1.33) (2 % as above), and the
//   energy balances;
// - one wavelength is the pool without dispersion, bit for bit.
TEST_F(Volume, DispersiveScatteringWaterTakesFresnelPerWavelength) {
  constexpr float kDispersion = 20.0f;
  nlohmann::json j = scattering_flat_pool();
  j["water"]["dispersion"] = kDispersion;
  auto r = make(j, "volume_dispersive_water");
  ASSERT_TRUE(r);
  InscatterRequest q = pool_side_view(*r);
  for (float nm : {400.0f, 700.0f}) {
    q.caustics.wavelength_nm = nm;
    const InscatterImage img = inscatter(*r, q);
    const double t = fresnel_t(1.0, index_at(1.33f, kDispersion, nm));
    expect_energy_balance(img.stats);
    EXPECT_NEAR(img.stats.power_in / (16 * t), 1.0, 1e-3) << nm << " nm";
  }
  q.caustics.wavelength_nm.reset();
  q.caustics.wavelengths = 4;
  const InscatterImage rgb = inscatter(*r, q);
  expect_energy_balance(rgb.stats);
  std::array<double, 3> gain{};
  for (const WavelengthSample& w : wavelength_samples(4)) {
    for (int c = 0; c < 3; ++c) gain[c] += w.rgb[c] * fresnel_t(1.0, index_at(1.33f, kDispersion, w.nm)) / fresnel_t(1.0, 1.33);
  }
  for (int row = 0; row < 20; ++row) {
    const double expected = pool_side_row(row);
    for (int col = 0; col < 12; ++col) {
      for (int c = 0; c < 3; ++c) {
        const double got = rgb.rgb[3 * (std::size_t(row) * 12 + std::size_t(col)) + c];
        EXPECT_NEAR(got, expected * gain[c], 0.02 * expected * gain[c] + 1e-6) << "row " << row << " col " << col << " channel " << c;
      }
    }
  }

  q.caustics.wavelengths = 1;
  auto plain = make(scattering_flat_pool(), "volume_water");
  ASSERT_TRUE(plain);
  EXPECT_EQ(inscatter(*r, q).rgb, inscatter(*plain, q).rgb) << "one wavelength against water without dispersion";
}

// fog_ball: the cone below the ball peaks where the exact photon tracer's
// does, within 2 voxels of the radiance grid (4.7 cm at the default 64
// over the 3 m box); the energy balances with Fresnel at the ball's
// surface; the octree takes fewer steps than uniform steps for the same
// picture.
TEST_F(Volume, FogBallFocusMatchesTheTracedBallLens) {
  auto r = bake_and_create(kScenes + "fog_ball.json");
  ASSERT_TRUE(r);
  InscatterRequest q;
  q.x0 = -0.5, q.y0 = 0, q.x1 = 0.5, q.y1 = 1.0;
  q.width = 20, q.height = 100;
  q.caustics = r->engine().default_options();
  const InscatterImage img = inscatter(*r, q);
  ASSERT_EQ(img.rgb.size(), 20u * 100u * 3u);
  auto peak_y = [](const std::vector<float>& rgb) {
    int best = -1;
    double best_value = 0;
    for (int row = 0; row < 100; ++row) {
      for (int col = 9; col <= 10; ++col) {
        const double v = rgb[3 * (std::size_t(row) * 20 + std::size_t(col)) + 1];
        if (v > best_value) {
          best_value = v;
          best = row;
        }
      }
    }
    return std::pair{1.0 - (best + 0.5) * 0.01, best_value};
  };
  reference::InscatterRequest rq;
  rq.scene_path = kScenes + "fog_ball.json";
  rq.x0 = q.x0, rq.y0 = q.y0, rq.x1 = q.x1, rq.y1 = q.y1;
  rq.width = q.width, rq.height = q.height;
  rq.photons = 400'000;
  rq.batches = 4;
  auto ref = reference::trace_inscatter(rq);
  ASSERT_TRUE(ref.ok()) << ref.error().message;
  const auto [y_run, v_run] = peak_y(img.rgb);
  const auto [y_ref, v_ref] = peak_y(ref->rgb);
  const double voxel = 3.0 / 64;
  std::printf("[volume fog_ball] peak y %.3f (runtime) vs %.3f (reference), %.2f voxels; peak %.4f vs %.4f\n", y_run, y_ref,
              std::fabs(y_run - y_ref) / voxel, v_run, v_ref);
  EXPECT_LE(std::fabs(y_run - y_ref), 2 * voxel);
  RecordProperty("fog_ball_focus_voxels", std::to_string(std::fabs(y_run - y_ref) / voxel));
  expect_energy_balance(img.stats);
  EXPECT_GT(img.stats.reflected, 0);

  InscatterRequest uniform = q;
  uniform.caustics.volume.octree = false;
  const InscatterImage u = inscatter(*r, uniform);
  ASSERT_EQ(u.rgb.size(), img.rgb.size());
  double diff = 0, sum = 0;
  for (std::size_t i = 0; i < u.rgb.size(); ++i) {
    diff += std::fabs(double(u.rgb[i]) - img.rgb[i]);
    sum += u.rgb[i];
  }
  std::printf("[volume fog_ball] octree: %llu steps in index grids vs %llu uniform; images differ by %.4f relative L1\n",
              static_cast<unsigned long long>(img.stats.grid_steps), static_cast<unsigned long long>(u.stats.grid_steps), diff / sum);
  EXPECT_LT(img.stats.grid_steps, u.stats.grid_steps);
  EXPECT_LT(diff / sum, 0.02);
}

// The focal line under fog_ball's glass ball against exact
// optics (media_oracle.h: the sphere traced in the test, Fresnel in and
// out): the in-scatter of the 1 cm column on the axis, 1 cm rows from the
// ball's bottom to the floor. With rays refracted at the surface (the
// default): the peak within 5 % of optics (the reference's own bound
// below) and at its height within 1 cm; every row where optics holds a
// quarter of its peak within 12 % (measured: +0.1 %, the same row; every
// row within 8.8 %, 6.5 cm under the focus: the focus grid's voxels,
// 7.2 mm tall, and the radiance grid's around it). By the seed's curved
// paths (surface_refraction off) the targets: the peak within 15 % and
// 2 cm, every row from 5 cm below the ball within 20 % (measured: -6.9 %,
// the same row, 14.8 %; nearer the ball the rows were off by up to 73 %,
// where the path crosses the blurred surface, 1.6 cm voxels).
// caustix-reference (its own tracer, the mesh) agrees with optics within
// 5 % at the peak and 1 cm in height (measured with 4 M photons: -0.8 %,
// the same row).
// Cost: fog_ball's bake (its index grids), three in-scatter images (with
// and without the focus grid, and by the curved paths) and a 1.5 M-photon
// in-scatter reference.
TEST_F(Volume, FogBallFocalLineAgreesWithOptics) {
  auto r = bake_and_create(kScenes + "fog_ball.json");
  ASSERT_TRUE(r);
  const int rows = 75, width = 11, axis = 5;
  const double dy = 0.01, y1 = 0.75;
  InscatterRequest q;
  q.x0 = -0.055f, q.x1 = 0.055f, q.y0 = float(y1 - rows * dy), q.y1 = float(y1);
  q.width = width, q.height = rows;
  q.caustics = r->engine().default_options();
  const InscatterImage img = inscatter(*r, q);
  ASSERT_EQ(img.rgb.size(), std::size_t(width * rows * 3));
  ASSERT_EQ(img.stats.focus_boxes.size(), 1u);
  const auto& box = img.stats.focus_boxes[0];
  std::printf("[volume fog_ball axis] focus grid %.3f %.3f %.3f .. %.3f %.3f %.3f\n", box[0], box[1], box[2], box[3], box[4], box[5]);
  EXPECT_GT(box[3], box[0]);
  // (P/2)^2 photons of the glass's own, besides P^2 over the light's window.
  const std::uint64_t side = q.caustics.volume.photons;
  EXPECT_EQ(img.stats.glass_photons, (side / 2) * (side / 2));
  EXPECT_EQ(img.stats.photons, side * side + (side / 2) * (side / 2));
  const FogBallColumn exact = fog_ball_column(0.5, 1.25, 1.5, 1.5, 2.5, 0.3, 0.3, -0.005, 0.005, y1, dy, rows);
  auto at = [&](const std::vector<float>& rgb, int row) { return double(rgb[3 * (std::size_t(row) * width + axis) + 1]); };
  auto peak_row = [&](auto value) {
    int best = 0;
    for (int row = 1; row < rows; ++row) best = value(row) > value(best) ? row : best;
    return best;
  };
  const int pe = peak_row([&](int row) { return exact.at(std::size_t(row)); });
  const double v_exact = exact.at(std::size_t(pe));
  // The peak's ratio to optics, how far apart the two peaks lie (m), and
  // the worst row from `first` on where optics holds a quarter of its peak.
  auto against_optics = [&](const std::vector<float>& rgb, int first, const char* label) {
    const int pr = peak_row([&](int row) { return at(rgb, row); });
    double worst = 0;
    for (int row = first; row < rows; ++row) {
      const double e = exact.at(std::size_t(row));
      if (e >= 0.25 * v_exact) worst = std::max(worst, std::fabs(at(rgb, row) / e - 1));
    }
    std::printf("[volume fog_ball axis] %s: peak %.4f at y %.3f (runtime) vs %.4f at y %.3f (optics): %+.1f %%, %+.0f cm; worst row %.1f %%\n",
                label, at(rgb, pr), y1 - (pr + 0.5) * dy, v_exact, y1 - (pe + 0.5) * dy, 100 * (at(rgb, pr) / v_exact - 1),
                100 * dy * (pe - pr), 100 * worst);
    return std::tuple{at(rgb, pr) / v_exact, std::abs(pr - pe) * dy, worst};
  };
  const auto [ratio, apart, worst] = against_optics(img.rgb, 0, "at the surface");
  RecordProperty("fog_ball_axis_peak_ratio", std::to_string(ratio));
  EXPECT_NEAR(ratio, 1.0, 0.05);
  EXPECT_LE(apart, 0.01 + 1e-9);
  EXPECT_LT(worst, 0.12);

  InscatterRequest curved = q;
  curved.caustics.volume.surface_refraction = false;
  const InscatterImage cv = inscatter(*r, curved);
  const auto [ratio_c, apart_c, worst_c] = against_optics(cv.rgb, 5, "curved paths");  // from 5 cm below the ball
  EXPECT_NEAR(ratio_c, 1.0, 0.15);
  EXPECT_LE(apart_c, 0.02 + 1e-9);
  EXPECT_LT(worst_c, 0.20);

  // Without the focus grid the line is what was first found: the test
  // tells the two apart (measured: -59 %, 13 cm high; with it -5.8 %, the
  // same row).
  InscatterRequest coarse = q;
  coarse.caustics.volume.focus_grid = 0;
  const InscatterImage c = inscatter(*r, coarse);
  EXPECT_EQ(c.stats.glass_photons, 0u);
  const int pc = peak_row([&](int row) { return at(c.rgb, row); });
  std::printf("[volume fog_ball axis] without the focus grid: peak %.4f at y %.3f\n", at(c.rgb, pc), y1 - (pc + 0.5) * dy);
  EXPECT_LT(at(c.rgb, pc) / v_exact, 0.7);

  reference::InscatterRequest rq;
  rq.scene_path = kScenes + "fog_ball.json";
  rq.x0 = q.x0, rq.y0 = q.y0, rq.x1 = q.x1, rq.y1 = q.y1;
  rq.width = width, rq.height = rows;
  rq.photons = 1'500'000;
  rq.batches = 4;
  auto ref = reference::trace_inscatter(rq);
  ASSERT_TRUE(ref.ok()) << ref.error().message;
  const int pf = peak_row([&](int row) { return at(ref->rgb, row); });
  std::printf("[volume fog_ball axis] reference: peak %.4f at y %.3f (%+.1f %% of optics)\n", at(ref->rgb, pf), y1 - (pf + 0.5) * dy,
              100 * (at(ref->rgb, pf) / v_exact - 1));
  EXPECT_NEAR(at(ref->rgb, pf) / v_exact, 1.0, 0.05);
  EXPECT_LE(std::abs(pf - pe) * dy, 0.01 + 1e-9);

  // The profiles for docs/results/fog_focus_axis.png (scripts/plot_fog_focus.py).
  if (const char* csv = std::getenv("CAUSTIX_FOG_AXIS_CSV")) {
    std::FILE* f = std::fopen(csv, "w");
    ASSERT_NE(f, nullptr) << csv;
    std::fprintf(f, "y_m,optics,optics_direct,runtime_focus_grid,runtime_no_focus_grid,reference,runtime_curved_paths\n");
    for (int row = 0; row < rows; ++row) {
      std::fprintf(f, "%.3f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", y1 - (row + 0.5) * dy, exact.at(std::size_t(row)), exact.direct[std::size_t(row)],
                   at(img.rgb, row), at(c.rgb, row), at(ref->rgb, row), at(cv.rgb, row));
    }
    std::fclose(f);
  }
}

// Extremes: nothing scattering costs nothing (no media, no in-scatter
// image, the same beauty bit for bit as with the media switched off);
// dense fog, one photon, a 2-voxel grid and a grid over the memory limit.
TEST_F(Volume, Extremes) {
  {
    auto r = make(fog_box(0.0, 0.5), "volume_clear");
    ASSERT_TRUE(r);
    EXPECT_FALSE(r->engine().has_media());
    InscatterRequest q;
    auto img = r->render_inscatter(q);
    ASSERT_FALSE(img.ok());
    EXPECT_NE(img.error().message.find("nothing in the scene scatters"), std::string::npos) << img.error().message;
  }
  {
    // fog_ball's beauty with the media off is fog_ball without its medium's
    // scattering, to the bit.
    nlohmann::json j = canonical_scene("fog_ball");
    auto with = make(j, "volume_beauty_media");
    j.erase("medium");
    auto without = make(j, "volume_beauty_clear");
    ASSERT_TRUE(with && without);
    sample::FrameParams f{with->default_camera(), 0.0f, 64, 48, with->engine().default_options(), {}, {}, {}, 1};
    f.caustics.volume.enabled = false;
    ASSERT_TRUE(with->render(f).ok());
    const std::vector<float> a = with->read_hdr();
    ASSERT_TRUE(without->render(f).ok());
    EXPECT_EQ(a, without->read_hdr());
    f.caustics.volume.enabled = true;
    ASSERT_TRUE(with->render(f).ok());
    EXPECT_NE(a, with->read_hdr());  // and with them on, the fog shows
  }
  auto r = make(fog_box(1000.0, 10.0), "volume_dense");
  ASSERT_TRUE(r);
  InscatterRequest q;
  q.x0 = -1.5, q.y0 = -0.5, q.x1 = 1.5, q.y1 = 2.5;
  q.width = q.height = 12;
  q.caustics = r->engine().default_options();
  for (std::uint32_t grid : {2u, 64u}) {
    for (std::uint32_t photons : {1u, 256u}) {
      q.caustics.volume.grid = grid;
      q.caustics.volume.photons = photons;
      const InscatterImage img = inscatter(*r, q);
      ASSERT_EQ(img.rgb.size(), 12u * 12u * 3u);
      // All light is taken within millimetres of the top; single scattering
      // there, seen through the fog's front, is bounded by the top face's
      // sigma_s / sigma_t p E0 / sigma_t per metre of view.
      for (float v : img.rgb) {
        EXPECT_TRUE(std::isfinite(v));
        EXPECT_GE(v, 0.0f);
        EXPECT_LT(v, 1000.0 / 1010.0 / (4 * kPi));
      }
      expect_energy_balance(img.stats);
    }
  }
  // Bad arguments to draw_media are refused by name.
  runtime::Engine& e = r->engine();
  EXPECT_EQ(e.draw_media(glm::mat4(1.0f), 0, 12345).error().code, ErrorCode::kUsage);
  runtime::gl::Texture depth = runtime::gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(depth.get(), 1, GL_DEPTH_COMPONENT32F, 4, 4);
  runtime::gl::Texture color = runtime::gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA8UI, 4, 4);  // integer colour: no format the draws read
  const auto wrong = e.draw_media(glm::mat4(1.0f), color.get(), depth.get());
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.error().message.find("scene colour"), std::string::npos) << wrong.error().message;
  EXPECT_EQ(e.draw_media(glm::mat4(0.0f), 0, depth.get()).error().code, ErrorCode::kUsage);  // singular
  EXPECT_EQ(e.draw_media(glm::mat4(1.0f), 0, depth.get(), -1.0f).error().code, ErrorCode::kUsage);
  // Into the caller's framebuffer.
  runtime::gl::Texture target = runtime::gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(target.get(), 1, GL_RGBA32F, 4, 4);
  runtime::gl::Framebuffer fbo = runtime::gl::make_framebuffer();
  glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, target.get(), 0);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
  glViewport(0, 0, 4, 4);
  const auto drawn = e.draw_media(glm::mat4(1.0f), 0, depth.get());
  EXPECT_TRUE(drawn.ok()) << drawn.error().message;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);

  q.caustics.volume.grid = 1024;  // 1024^3 voxels over the cube
  auto refused = r->render_inscatter(q);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, ErrorCode::kUsage);
  EXPECT_NE(refused.error().message.find("lower the volume grid"), std::string::npos) << refused.error().message;

  // The focus grid: none without glass, and its size checked.
  q.caustics.volume.grid = 64;
  q.caustics.volume.photons = 16;
  const InscatterImage plain = inscatter(*r, q);
  ASSERT_EQ(plain.stats.focus_boxes.size(), 1u);
  EXPECT_EQ(plain.stats.focus_boxes[0], (std::array<float, 6>{0, 0, 0, 0, 0, 0}));
  for (std::uint32_t focus : {1u, 129u}) {
    q.caustics.volume.focus_grid = focus;
    auto bad = r->render_inscatter(q);
    ASSERT_FALSE(bad.ok()) << focus;
    EXPECT_EQ(bad.error().code, ErrorCode::kUsage);
    EXPECT_NE(bad.error().message.find("focus grid"), std::string::npos) << bad.error().message;
  }
}

}  // namespace
}  // namespace caustix::test
