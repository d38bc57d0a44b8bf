// Glass caustics (Iwasaki et al.) with physics as the oracle: the glass ball's
// transmitted flux and focal spot against an exact 2-D trace of a sphere;
// table look-ups against direct traces; an IOR-1 object leaves the light
// unchanged; rotating glass and light together rotates the image; glass
// modelled low-poly (a 6-vertex prism, an 8-vertex cube, a pane of two
// triangles per face) casts the light Snell and Fresnel put on the floor.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <tuple>

#include <tbb/global_control.h>

#include "caustix/bake/bake.h"
#include "caustix/bake/glass_refine.h"
#include "caustix/bake/light_transport.h"
#include "caustix/bake/mesh_import.h"
#include "caustix/common/mesh_topology.h"
#include "caustix/formats/frame.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/sample/renderer.h"
#include "bake_fixture.h"
#include "gl_fixture.h"
#include "hostile_meshes.h"
#include "optics_oracle.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

using test::fresnel_t;
using test::kPi;
using test::Landing;
using test::ball_lens;
using test::encircled;

using test::kScenes;
nlohmann::json scene(const std::string& name) { return test::canonical_scene(name); }

runtime::RuntimeScene bake_and_load(const nlohmann::json& j, const bake::BakeOptions& opt = {}) {
  return test::bake_and_load(test::write_scene(j, "glass_test"), opt).value();
}

// The floor's irradiance image over |x|, |z| < half, n x n pixels.
sample::IrradianceRequest floor_request(int n, double half) {
  sample::IrradianceRequest q;
  q.receiver = "floor";
  q.x0 = q.z0 = static_cast<float>(-half);
  q.x1 = q.z1 = static_cast<float>(half);
  q.width = q.height = n;
  return q;
}

class Glass : public test::GlTest {
 protected:
  // Irradiance / E0 of the floor over |x|, |z| < half (default: the whole 4 x 4 m floor).
  static std::vector<float> floor_irradiance(const nlohmann::json& j, int n, const bake::BakeOptions& opt = {},
                                             std::uint32_t glass_map_size = runtime::CausticsOptions{}.glass_map_size,
                                             double half = 2) {
    auto r = sample::Renderer::create(bake_and_load(j, opt));
    EXPECT_TRUE(r.ok()) << r.error().message;
    sample::IrradianceRequest q = floor_request(n, half);
    q.caustics.glass_map_size = glass_map_size;
    auto img = (*r)->render_irradiance(q);
    EXPECT_TRUE(img.ok()) << img.error().message;
    std::vector<float> e;
    for (std::size_t i = 0; i < img->rgb.size(); i += 3) {
      EXPECT_TRUE(std::isfinite(img->rgb[i])) << "non-finite irradiance";
      e.push_back(img->rgb[i]);
    }
    return e;
  }

};

TEST_F(Glass, BallLensFluxAndFocalSpot) {
  const int n = 512;
  const double half = 2.0, pix = 2 * half / n;
  const auto e = floor_irradiance(scene("glass_ball"), n);
  const test::BallLensFloor b = test::ball_lens_floor(e, n, half);
  EXPECT_NEAR(b.transmitted / b.expected, 1.0, 0.05) << "transmitted " << b.transmitted << " expected " << b.expected;
  EXPECT_LT(std::hypot(b.peak_x, b.peak_z), 1.5 * pix) << "peak at (" << b.peak_x << ", " << b.peak_z << ")";
  std::printf("[glass_ball] transmitted %.4f / expected %.4f; R50 %.4f m measured vs %.4f m exact; peak E/E0 %.1f\n",
              b.transmitted, b.expected, b.m50, b.r50, b.peak_e);
  EXPECT_NEAR(b.m50, b.r50, std::max(2 * pix, 0.1 * b.r50));

  // Encircled power at the defaults (once measured 8 % low at 2 cm
  // against caustix-reference in 4 mm pixels; these are 7.8 mm).
  for (double r : {0.02, 0.03, 0.05, 0.1, 0.2}) {
    const double got = encircled(b.measured, r), want = encircled(b.exact, r);
    std::printf("[glass_ball] encircled power within %.2f m: %.4f vs %.4f exact (%+.1f %%)\n", r, got, want,
                100 * (got / want - 1));
  }
}

// The focal spot at the defaults against the exact trace of a
// true sphere (optics_oracle.h, Fresnel at both surfaces), rasterised into
// the same pixels: 0.5 mm pixels over +-5.1 cm, 4 x 4 samples each; the
// power within 0.5, 1, 2 and 5 cm of the axis and the brightest 2 mm pixel
// (4 x 4 of them, aligned so that one is centred on the axis: optics puts
// 7151 E0 there). Bounds: the targets, 10 % at 0.5 cm, 5 % beyond,
// 25 % at the peak; measured at the defaults (the window's texels by the
// tent) -2.5, -2.4, -1.1, -0.8 % and -17.4 %, by the box -2.4, -2.3,
// -1.1, -0.8 % and -15.9 %. Without the focus window the 7.8 mm texels of
// the floor's texture spread the spot: -55 % at 0.5 cm, -13 % at 1 cm,
// the peak -94 % (asserted worse than -15 % at 0.5 cm, so that the test
// tells the two apart). The window's wide triangles, drawn with their
// one-edge texels covered in closed form (glass_focus_wide), give the
// image of every triangle clipped exactly, both by the box (measured:
// relative L1 2.4e-4, flux +0.001 %; bounds 0.5 % and 0.1 %, and the two
// must differ, or the second program drew nothing). Also printed: each
// image's relative L1 against the optics image, pixel by pixel (0.135 by
// the tent, 0.134 by the box; the spokes, docs/glass-focus.md), to judge
// a change of the window's drawing by.
TEST_F(Glass, BallLensFocusAgreesWithOptics) {
  const int n = 204;
  const double x0 = -0.051, pix = 0.0005;
  const auto want = test::landing_image(ball_lens(0.5, 0.75, 1.5, 20000), n, x0, pix);
  auto r = sample::Renderer::create(bake_and_load(scene("glass_ball")));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto render = [&](bool focus, float wide, bool tent) {
    sample::IrradianceRequest q;
    q.receiver = "floor";
    q.x0 = q.z0 = static_cast<float>(x0);
    q.x1 = q.z1 = static_cast<float>(x0 + n * pix);
    q.width = q.height = n;
    q.caustics.glass_focus = focus;
    q.caustics.glass_focus_wide = wide;
    q.caustics.glass_focus_tent = tent;
    auto img = (*r)->render_irradiance(q);
    EXPECT_TRUE(img.ok()) << img.error().message;
    std::vector<double> e;
    for (std::size_t i = 0; img.ok() && i < img->rgb.size(); i += 3) e.push_back(img->rgb[i]);
    return e;
  };
  const runtime::CausticsOptions defaults;
  ASSERT_TRUE(defaults.glass_focus_tent) << "the focal figures below are the tent's";
  // The window's wide primitives (glass_focus_wide) take the light inside
  // each texel in closed form: against every triangle clipped, both by the
  // box, the same light.
  const std::vector<double> box = render(true, defaults.glass_focus_wide, false);
  {
    const std::vector<double> clipped = render(true, 0.0f, false);
    double diff = 0, total = 0, flux = 0;
    for (std::size_t i = 0; i < box.size(); ++i) {
      diff += std::fabs(box[i] - clipped[i]);
      total += clipped[i];
      flux += box[i];
    }
    std::printf("[glass_ball, focus window by the box] wide triangles in closed form vs all clipped: relative L1 %.2e, flux %.5f\n",
                diff / total, flux / total);
    EXPECT_LT(diff / total, 0.005);
    EXPECT_GT(diff / total, 1e-6) << "no triangle took the wide program";
    EXPECT_NEAR(flux / total, 1.0, 0.001);
  }
  // The focal figures of the window by the tent (the default), without a
  // window, and by the box.
  const auto judge = [&](const std::vector<double>& got, const char* label, bool window) {
    ASSERT_EQ(got.size(), want.size());
    if (window) {
      double dg = 0, wt = 0;
      for (std::size_t i = 0; i < got.size(); ++i) {
        dg += std::fabs(got[i] - want[i]);
        wt += want[i];
      }
      std::printf("[glass_ball, %s] against optics: relative L1 %.4f\n", label, dg / wt);
    }
    for (const double radius : {0.005, 0.01, 0.02, 0.05}) {
      const double g = test::power_within(got, n, x0, pix, radius), w = test::power_within(want, n, x0, pix, radius);
      std::printf("[glass_ball, %s] power within %.3f m: %.5f vs %.5f optics (%+.1f %%)\n", label, radius, g, w, 100 * (g / w - 1));
      if (window) EXPECT_NEAR(g / w, 1.0, radius < 0.01 ? 0.10 : 0.05) << label << ", within " << radius << " m";
      // Without a window the main texture's 7.8 mm texels hold 0.45 of the
      // light within 5 mm (0.87 within 1 cm since each texel's share of a
      // triangle is weighted at the part's centroid).
      if (!window && radius == 0.005) EXPECT_LT(g / w, 0.85) << "the main texture alone resolves the spot: the test tells nothing";
    }
    const double gp = test::peak_block(got, n, 4), wp = test::peak_block(want, n, 4);
    std::printf("[glass_ball, %s] brightest 2 mm pixel %.1f vs %.1f E0 optics (%+.1f %%)\n", label, gp, wp, 100 * (gp / wp - 1));
    if (window) EXPECT_NEAR(gp / wp, 1.0, 0.25) << label;
  };
  const std::vector<double> tent = render(true, defaults.glass_focus_wide, true);
  judge(tent, "focus window", true);
  // The window: a square around the focus, far smaller than the floor.
  const auto lit = (*r)->engine().lighting(0, 0);
  ASSERT_TRUE(lit.ok());
  EXPECT_GT(lit->block.glass_half.w, 0.0f);
  EXPECT_LT(lit->block.glass_half.w, 0.05f);
  EXPECT_NEAR(lit->block.glass_v.w, 0.5f, lit->block.glass_half.w);
  EXPECT_NEAR(lit->block.glass_w.w, 0.5f, lit->block.glass_half.w);
  judge(render(false, defaults.glass_focus_wide, true), "no window", false);
  const auto unlit = (*r)->engine().lighting(0, 0);
  ASSERT_TRUE(unlit.ok());
  EXPECT_EQ(unlit->block.glass_half.w, 0.0f);
  // By the box the same light, a texel less spread.
  judge(box, "focus window by the box", true);
  double diff = 0, total = 0, flux = 0;
  for (std::size_t i = 0; i < box.size(); ++i) {
    diff += std::fabs(tent[i] - box[i]);
    total += box[i];
    flux += tent[i];
  }
  std::printf("[glass_ball, focus window] the tent against the box: relative L1 %.2e, flux %.5f\n", diff / total, flux / total);
  EXPECT_GT(diff / total, 1e-3) << "the tent changed nothing";
  EXPECT_NEAR(flux / total, 1.0, 0.001);
}

// Smooth glass caustics ("the glass ball's shadow ring has radial
// spokes"). Under the vertical sun the exact floor is radially symmetric;
// per one-pixel ring (4 mm) the spread of the pixels around it over their
// mean, averaged over the rings of 0.12-0.30 m, measures spokes and steps
// (caustix-reference with 16 M photons: 0.076-0.131, mostly its photon
// noise; caustic maps 0.016). The 48-facet ball prints a wedge per facet
// with one intensity per triangle (0.067-0.106); interpolated from the
// one-rings they go, and each triangle keeps its flux, so the transmitted
// power is unchanged.
TEST_F(Glass, SmoothCausticsLeaveNoFacetSpokes) {
  const int n = 300;
  const double half = 0.6, pix = 2 * half / n;
  auto r = sample::Renderer::create(bake_and_load(scene("glass_ball")));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto floor = [&](bool smooth) {
    sample::IrradianceRequest q = floor_request(n, half);
    q.caustics.glass_smooth = smooth;
    auto img = (*r)->render_irradiance(q);
    EXPECT_TRUE(img.ok());
    return img.ok() ? img->rgb : std::vector<float>();
  };
  const auto spread_and_power = [&](const std::vector<float>& rgb) {
    const int bins = static_cast<int>(0.18 / pix);
    std::vector<double> s(bins), s2(bins), c(bins);
    double power = 0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const double v = rgb[(static_cast<std::size_t>(i) * n + j) * 3];
        power += v * pix * pix;
        const int b = static_cast<int>(std::floor((std::hypot(-half + (j + 0.5) * pix, -half + (i + 0.5) * pix) - 0.12) / pix));
        if (b < 0 || b >= bins) continue;
        s[b] += v, s2[b] += v * v, c[b] += 1;
      }
    }
    double sum = 0;
    for (int b = 0; b < bins; ++b) sum += std::sqrt(std::max(0.0, s2[b] / c[b] - s[b] * s[b] / (c[b] * c[b]))) / (s[b] / c[b]);
    return std::pair{sum / bins, power};
  };
  const auto [flat, flat_power] = spread_and_power(floor(false));
  const auto [smooth, smooth_power] = spread_and_power(floor(true));
  std::printf("[glass_ball] ring spread 0.12-0.30 m: one intensity per triangle %.4f, smooth %.4f; power %.4f vs %.4f m^2 E0\n", flat,
              smooth, flat_power, smooth_power);
  EXPECT_GT(flat, 0.06);  // what the statistic catches
  EXPECT_LT(smooth, 0.035);
  EXPECT_NEAR(smooth_power / flat_power, 1.0, 0.005);
}

// The focal spot with curved glass refined (--glass-turn 5, the accurate
// preset's) and 1024^2 illumination textures: the power within r of the
// axis against the exact trace of a true sphere, in 3.75 mm pixels. Bound
// at r >= 2 cm: the glass target's 5 % plus 1 % for what the 48 x 24 UV sphere
// itself gives up against a true sphere (caustix-reference tracing the
// mesh, 32 M photons: -0.6 % at 2 cm, -2.4 % at 3 cm). Measured -4.9,
// -3.5, -3.0, -2.0, -1.6 %; unrefined, the same textures give -7.7 % at
// 2 cm (printed, not asserted).
TEST_F(Glass, RefinedBallLensHoldsItsFocalSpot) {
  const int n = 160;
  const double half = 0.3, pix = 2 * half / n;  // 3.75 mm pixels
  std::vector<Landing> exact;
  for (const auto& l : ball_lens(0.5, 0.75, 1.5, 20000)) {
    if (l.rho < half) exact.push_back(l);
  }
  for (double turn : {0.0, 5.0}) {
    bake::BakeOptions opt;
    opt.glass_refine.max_turn_deg = turn;
    const auto e = floor_irradiance(scene("glass_ball"), n, opt, 1024, half);
    std::vector<Landing> measured;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const double rho = std::hypot(-half + (j + 0.5) * pix, -half + (i + 0.5) * pix);
        measured.push_back({rho, e[static_cast<std::size_t>(i) * n + j] * pix * pix});  // all inside the shadow
      }
    }
    for (double r : {0.02, 0.03, 0.05, 0.1, 0.2}) {
      const double got = encircled(measured, r), want = encircled(exact, r);
      std::printf("[glass_ball, --glass-turn %g, 1024^2] encircled power within %.2f m: %.4f vs %.4f exact (%+.1f %%)\n",
                  turn, r, got, want, 100 * (got / want - 1));
      if (turn > 0) EXPECT_NEAR(got / want, 1.0, 0.06) << "within " << r << " m";
    }
  }
}

// Extremes of the IOR and total internal reflection, on a glass
// cube (0.5 m, its centre 0.75 m above the floor; faces of 16 x 16 cells:
// the table is per vertex, and box.obj's 8 corners have none inside a face,
// so all its light is traced from edges and corners and lost). Straight down,
// light enters the top face and leaves the bottom face at normal incidence:
// under the cube E/E0 = T^2, T = 1 - ((n-1)/(n+1))^2, for n = 1.5, 2.5 and
// 4 (0.9216, 0.6659, 0.4096). Tilted 45 degrees, the refracted light meets
// the side faces beyond the critical angle (n = 1.5: 62 against 41.8
// degrees) and is totally reflected down to the bottom face: finite, and
// the floor receives no more than the cube intercepts.
// One test per index (n = 1.5, 2.5, 4), so that the three run side by side.
class GlassCube : public Glass, public ::testing::WithParamInterface<double> {};

TEST_P(GlassCube, CubeAtExtremeIorsAndTotalInternalReflection) {
  const int n = 256;
  const double pix = 4.0 / n;
  const auto mesh = std::filesystem::temp_directory_path() / "caustix_subdivided_cube.obj";
  std::ofstream(mesh) << test::to_obj(test::subdivided_cube(16));
  const double ior = GetParam();
  nlohmann::json j = scene("glass_ball");
  j["objects"][1]["mesh"] = mesh.string();
  j["objects"][1]["material"]["ior"] = ior;
  const auto e = floor_irradiance(j, n);
  const double r = (ior - 1) / (ior + 1), t2 = (1 - r * r) * (1 - r * r);
  double under = 0;
  int count = 0;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < n; ++k) {
      const double x = -2 + (k + 0.5) * pix, z = -2 + (i + 0.5) * pix;
      if (std::max(std::fabs(x), std::fabs(z)) > 0.2) continue;  // 5 cm inside the cube's 0.25 m half side
      under += e[static_cast<std::size_t>(i) * n + k];
      ++count;
    }
  }
  std::printf("[cube, n = %.1f, straight down] E/E0 under it %.4f, T^2 = %.4f\n", ior, under / count, t2);
  EXPECT_NEAR(under / count, t2, 0.01 * t2) << "ior " << ior;

  const double c = std::sqrt(0.5);
  j["lights"][0]["direction"] = {c, -c, 0.0};
  const auto tilted = floor_irradiance(j, n);
  // Floor flux: direct light (E0 cos 45 outside the shadow) plus what came
  // through the glass (at most what the cube intercepts: its top and one
  // side face, 2 x 0.25 m^2 x cos 45).
  double total = 0;
  for (float v : tilted) total += v * pix * pix;
  const double intercepted = 2 * 0.25 * c;
  const double direct_all = 16 * c;
  std::printf("[cube, n = %.1f, 45 degrees] floor flux %.4f, direct without the cube %.4f\n", ior, total, direct_all);
  EXPECT_LE(total, direct_all + 1e-3) << "no light created";
  EXPECT_GE(total, direct_all - intercepted) << "no more lost than the cube intercepts";
}

INSTANTIATE_TEST_SUITE_P(Ior, GlassCube, ::testing::Values(1.5, 2.5, 4.0),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return "n" + std::to_string(static_cast<int>(info.param * 10));
                         });

TEST_F(Glass, IorOneIsTransparent) {
  nlohmann::json j = scene("glass_ball");
  j["objects"][1]["material"]["ior"] = 1.0;
  const int n = 256;
  // No caustic, no shadow: the identity path, Fresnel T = 1 at n = 1. Flux
  // is conserved; outside the ball's shadow nothing changes; inside, the
  // interpolation of exit points between grid directions moves
  // the triangles' landing corners, so the irradiance ripples about 1 by
  // an amount that falls with the table resolution (a ring of 4 pixels at
  // the silhouette, where the glass shadow map's filtered edge meets the
  // splatted light, is left out).
  std::vector<double> ripple;
  for (std::uint32_t res : {16u, 32u}) {
    bake::BakeOptions opt;
    opt.transport.resolution = res;
    const auto e = floor_irradiance(j, n, opt);
    double sum = 0, inner = 0, outer = 0;
    int n_inner = 0, n_outer = 0;
    const double pix = 4.0 / n;
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < n; ++k) {
        const double v = e[static_cast<std::size_t>(i) * n + k];
        const double rho = std::hypot(-2 + (k + 0.5) * pix, -2 + (i + 0.5) * pix);
        sum += v;
        if (rho < 0.5 - 4 * pix) {
          inner += std::fabs(v - 1);
          ++n_inner;
        } else if (rho > 0.5 + 4 * pix) {
          outer += std::fabs(v - 1);
          ++n_outer;
        }
      }
    }
    std::printf("[ior 1, R=%u] mean E/E0 %.5f; mean |E/E0 - 1| inside %.4f, outside %.6f\n", res, sum / e.size(), inner / n_inner,
                outer / n_outer);
    EXPECT_NEAR(sum / e.size(), 1.0, 0.002);
    EXPECT_LT(outer / n_outer, 1e-4);
    ripple.push_back(inner / n_inner);
  }
  EXPECT_LT(ripple[0], 0.15);
  EXPECT_LT(ripple[1], 0.6 * ripple[0]);
}

// A wedge prism as people model it (assets/meshes/prism.obj): 6 vertices,
// flat faces, no normals in the file. Cross-section in x-y: bottom y = 0.3
// from x = -0.5 to 0.5, back face x = -0.5 up to y = 0.8, the slope between;
// z from -0.5 to 0.5.
const std::string kWedgePrism = std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/prism.obj";

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path;
}

// Row profile of the floor (n x n over -2..2 m): the mean over rows with
// |z| < half_z.
std::vector<double> profile(const std::vector<float>& e, int n, double half_z) {
  std::vector<double> p(static_cast<std::size_t>(n), 0.0);
  int rows = 0;
  for (int i = 0; i < n; ++i) {
    if (std::fabs(-2 + (i + 0.5) * 4.0 / n) >= half_z) continue;
    ++rows;
    for (int k = 0; k < n; ++k) p[static_cast<std::size_t>(k)] += e[static_cast<std::size_t>(i) * n + k];
  }
  for (double& v : p) v /= rows;
  return p;
}

// Mean of the floor's irradiance over |x - cx| < h, |z| < h.
double mean_over(const std::vector<float>& e, int n, double cx, double h) {
  double sum = 0;
  int count = 0;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < n; ++k) {
      const double x = -2 + (k + 0.5) * 4.0 / n, z = -2 + (i + 0.5) * 4.0 / n;
      if (std::fabs(x - cx) >= h || std::fabs(z) >= h) continue;
      sum += e[static_cast<std::size_t>(i) * n + k];
      ++count;
    }
  }
  return sum / count;
}

TEST_F(Glass, LowPolyGlassCastsItsLight) {
  const int n = 400;
  const double pix = 4.0 / n;  // 1 cm
  nlohmann::json j = scene("glass_ball");

  // Prism, light straight down: refraction into the slope (normal
  // (1, 2, 0)/sqrt 5) and out of the bottom. Rays from x0 in [-0.425, 0.5]
  // leave through the bottom and land shifted by 0.3 d2.x / -d2.y in a band
  // of irradiance T1 T2 / (dx_floor / dx0); those nearer the back face
  // reflect totally there first. The band's right edge is the ray entering
  // at the slope's lower edge (x0 = 0.5), which leaves at once.
  j["objects"][1]["mesh"] = kWedgePrism;
  j["objects"][1].erase("transform");
  const double eta = 1 / 1.5, s5 = std::sqrt(5.0);
  const double n1[2] = {1 / s5, 2 / s5};
  const double cos1 = n1[1], cos1t = std::sqrt(1 - eta * eta * (1 - cos1 * cos1));
  const double d1[2] = {eta * 0 + (eta * cos1 - cos1t) * n1[0], -eta + (eta * cos1 - cos1t) * n1[1]};
  const double cos2 = -d1[1];
  const double shift = test::prism_floor_shift(1.5);
  const double band = fresnel_t(cos1, 1.5) * fresnel_t(cos2, 1 / 1.5) / (1 - 0.5 * d1[0] / -d1[1]);
  const double right_edge = 0.5 + shift;
  const auto e = floor_irradiance(j, n);
  const auto p = profile(e, n, 0.3);
  double level = 0;
  int count = 0;
  for (int k = 0; k < n; ++k) {
    const double x = -2 + (k + 0.5) * pix;
    if (x > -0.25 && x < right_edge - 0.05) {
      level += p[static_cast<std::size_t>(k)];
      ++count;
    }
  }
  level /= count;
  // Where the band falls to half its level, between pixel centres.
  double measured_edge = 0;
  for (int k = n / 2; k + 1 < n; ++k) {
    const double a = p[static_cast<std::size_t>(k)], b = p[static_cast<std::size_t>(k + 1)];
    if (a >= band / 2 && b < band / 2) {
      measured_edge = -2 + (k + 0.5 + (a - band / 2) / (a - b)) * pix;
      break;
    }
  }
  // The left edge: the ray entering at x0 = -0.425 m, where the light
  // that reaches the back face first starts to reflect totally there. It
  // leaves through the bottom's edge (x = -0.5, y = 0.3) and falls 0.3 m
  // as the right edge's ray does, landing left of the prism's shadow on the
  // floor's direct light (E0: the edge is where the band's light rises
  // through half its level over it). The triangles across that switch are
  // cut there (LTTW); dropped, the edge sat 5 cm right of it (docs/glass-tables.md).
  const double x_switch = -0.425, y_switch = 0.8 - 0.5 * (x_switch + 0.5);
  ASSERT_NEAR(x_switch + (y_switch - 0.3) * d1[0] / -d1[1], -0.5, 1e-3);  // it meets the bottom's edge
  const double want_left = -0.5 + shift;
  double measured_left = 0;
  for (int k = 0; k + 1 < n / 2; ++k) {
    const double a = p[static_cast<std::size_t>(k)] - 1.0, b = p[static_cast<std::size_t>(k + 1)] - 1.0;
    if (a < band / 2 && b >= band / 2) {
      measured_left = -2 + (k + 0.5 + (band / 2 - a) / (b - a)) * pix;
      break;
    }
  }
  std::printf("[prism, 6 vertices] band E/E0 %.4f (Snell + Fresnel %.4f); right edge %.4f m (Snell %.4f m), left edge %.4f m "
              "(Snell %.4f m)\n", level, band, measured_edge, right_edge, measured_left, want_left);
  EXPECT_NEAR(level, band, 0.015 * band);
  EXPECT_NEAR(measured_edge, right_edge, pix);
  EXPECT_NEAR(measured_left, want_left, pix);

  // Cube of 8 vertices and 12 triangles, 0.5 m, straight down: T^2 under it.
  auto cube = test::unit_cube();
  j["objects"][1]["mesh"] = write_temp("caustix_cube8.obj", test::to_obj(cube)).string();
  j["objects"][1]["transform"] = {{"translate", {-0.25, 0.5, -0.25}}, {"scale", 0.5}};
  const double t0 = fresnel_t(1.0, 1.5);
  const double under_cube = mean_over(floor_irradiance(j, n), n, 0.0, 0.2);
  std::printf("[cube, 8 vertices] E/E0 under it %.4f, T^2 = %.4f\n", under_cube, t0 * t0);
  EXPECT_NEAR(under_cube, t0 * t0, 0.01 * t0 * t0);

  // A pane 1 x 0.02 x 1 m of two triangles per face, tilted 30 degrees: a
  // parallel plate passes the light unbent, T(30 deg)^2 of it, over its
  // whole footprint (near its lower edge, light entering within 7 mm of the
  // edge leaves through the end face: the triangles torn between the two
  // exits smeared it over 0.3 m of floor, +2.6 %, until the runtime dropped
  // them).
  for (auto& pos : cube.positions) pos = {pos[0] - 0.5f, 0.02f * pos[1] - 0.01f, pos[2] - 0.5f};
  j["objects"][1]["mesh"] = write_temp("caustix_pane.obj", test::to_obj(cube)).string();
  j["objects"][1]["transform"] = {{"translate", {0, 0.6, 0}}, {"rotate_deg", {0, 0, 30}}};
  const double t30 = fresnel_t(std::cos(30 * kPi / 180), 1.5);
  const auto pane = floor_irradiance(j, n);
  const double upper = mean_over(pane, n, 0.2, 0.15), whole = mean_over(pane, n, 0.0, 0.4);
  std::printf("[pane, 12 triangles, 30 degrees] E/E0 upper half %.4f, whole footprint %.4f, T(30)^2 = %.4f\n", upper, whole,
              t30 * t30);
  EXPECT_NEAR(upper, t30 * t30, 0.01 * t30 * t30);
  EXPECT_NEAR(whole, t30 * t30, 0.01 * t30 * t30);
}

// A horizontal pane 1 x 0.02 x 1 m over the floor under a slanted sun: a
// parallel plate passes cos(theta) T(theta)^2 of E0 over its footprint,
// h tan(theta) downwind. Across the light's mean direction the floor spans
// metres of depth; the four virtual planes spread over it (§4.2) cut the
// space between pane and floor, and exit rays starting below a plane gave
// it nothing: 0.2 m up at 30 degrees the footprint read 0.517 for 0.796,
// at 60 degrees 0.314 for 0.415. A flat target is now cut exactly, along
// its normal.
TEST_F(Glass, SlantedLightThroughAPaneReachesTheFloor) {
  const int n = 400;
  nlohmann::json j = scene("glass_ball");
  auto pane = test::unit_cube();
  for (auto& pos : pane.positions) pos = {pos[0] - 0.5f, 0.02f * pos[1] - 0.01f, pos[2] - 0.5f};
  j["objects"][1]["mesh"] = write_temp("caustix_flat_pane.obj", test::to_obj(pane)).string();
  for (const auto& [height, degrees] : {std::pair{0.2, 30.0}, std::pair{0.6, 60.0}, std::pair{0.2, 75.0}}) {
    j["objects"][1]["transform"] = {{"translate", {0, height, 0}}};
    const double theta = degrees * kPi / 180;
    j["lights"][0]["direction"] = {std::sin(theta), -std::cos(theta), 0};
    const double t = fresnel_t(std::cos(theta), 1.5), expected = std::cos(theta) * t * t;
    const double footprint = mean_over(floor_irradiance(j, n), n, height * std::tan(theta), 0.4);
    std::printf("[pane %.1f m up, sun at %.0f degrees] E/E0 over the footprint %.4f, cos T^2 = %.4f\n", height, degrees, footprint,
                expected);
    EXPECT_NEAR(footprint, expected, 0.01 * expected);
  }
}

// A pane of two triangles per face (baked unsplit, --glass-edge 0), 0.6 m
// over the floor, straight under the sun, half in the shadow of an opaque
// board above it (x < 0): both triangles of its top face have corners in
// the shadow, so neither can be interpolated across, and the pane passed
// no light at all. Each lit corner now sends a third of its triangle's
// light as a parallel beam: with the shadow edge through the face's
// middle, 2 + 1 lit corners of the two triangles carry T^2 times the lit
// half's area. (Baked with the default splitting, the pane read 0.4472
// without corner beams, 0.4538 with them.)
TEST_F(Glass, HalfShadedPaneSendsTheLightOfItsLitHalf) {
  const int n = 256;
  const double half = 1.5, pix = 2 * half / n;
  nlohmann::json j = scene("glass_ball");
  auto pane = test::unit_cube();
  for (auto& pos : pane.positions) pos = {pos[0] - 0.5f, 0.02f * pos[1] - 0.01f, pos[2] - 0.5f};
  j["objects"][1]["mesh"] = write_temp("caustix_shaded_pane.obj", test::to_obj(pane)).string();
  j["objects"][1]["transform"] = {{"translate", {0, 0.6, 0}}};
  j["objects"].push_back({{"name", "board"}, {"mesh", j["objects"][0]["mesh"]}, {"role", "receiver"},
                          {"transform", {{"translate", {-0.75, 1.2, 0}}, {"scale", {1.5, 1, 2}}}}});
  bake::BakeOptions opt;
  opt.glass_refine.max_edge = 0;
  auto r = sample::Renderer::create(bake_and_load(j, opt));
  ASSERT_TRUE(r.ok()) << r.error().message;
  double transmitted = 0;
  for (auto method : {runtime::CausticsMethod::kLevelMap, runtime::CausticsMethod::kNone}) {
    sample::IrradianceRequest q = floor_request(n, half);
    q.caustics.method = method;
    auto img = (*r)->render_irradiance(q);
    ASSERT_TRUE(img.ok()) << img.error().message;
    double sum = 0;
    for (std::size_t i = 0; i < img->rgb.size(); i += 3) sum += img->rgb[i] * pix * pix;
    transmitted += method == runtime::CausticsMethod::kNone ? -sum : sum;
    if (method == runtime::CausticsMethod::kLevelMap) {
      // A pane concentrates nothing: no focus window, no cost.
      const auto lit = (*r)->engine().lighting(0, 0);
      ASSERT_TRUE(lit.ok());
      EXPECT_EQ(lit->block.glass_half.w, 0.0f);
    }
  }
  const double t = fresnel_t(1.0, 1.5), expected = t * t * 0.5;
  std::printf("[pane half in a board's shadow] light through it %.4f m^2 E0, T^2 x 0.5 m^2 = %.4f\n", transmitted, expected);
  EXPECT_NEAR(transmitted, expected, 0.02 * expected);
}

// Which receivers count as flat (cut along their normal, above).
TEST(PlaneNormal, FindsTheFlatAndOnlyTheFlat) {
  const double c = std::cos(0.3), s = std::sin(0.3);
  std::vector<Vec3d> tilted;  // a 3 x 3 grid in a plane tilted 0.3 rad about x, 10 km out
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) tilted.push_back({1e4 + i, 2 + k * s, -3 + k * c});
  }
  const auto n = plane_normal(tilted);
  ASSERT_TRUE(n.has_value());
  EXPECT_NEAR(std::fabs((*n)[1] * c - (*n)[2] * s), 1.0, 1e-9);
  std::vector<Vec3d> bent = tilted;
  bent[4][1] += 1e-3;  // the middle point 1 mm off the plane: not flat
  EXPECT_FALSE(plane_normal(bent).has_value());
  EXPECT_FALSE(plane_normal({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}).has_value());  // a line
  EXPECT_FALSE(plane_normal({{0, 0, 0}, {1, 0, 0}}).has_value());
}

TEST(GlassRefine, CreasesSplitAndFlatFacesRefinedClosed) {
  const TriangleMesh cube = test::unit_cube();  // 8 shared corners, every normal (0, 1, 0)
  bake::GlassRefineOptions opt;
  bake::GlassRefineReport rep;
  const TriangleMesh r = bake::refine_transparent_mesh(cube, opt, &rep);
  std::printf("[refine, cube] %u -> %u vertices, %u -> %u triangles, %u crease edges, %u rounds\n", rep.vertices_in,
              rep.vertices_out, rep.triangles_in, rep.triangles_out, rep.crease_edges, rep.rounds);
  EXPECT_EQ(rep.crease_edges, 12u);
  EXPECT_EQ(rep.crease_vertices, 16u);  // each corner: one copy per face
  const EdgeCensus c = census_edges(r);
  EXPECT_TRUE(c.closed());
  EXPECT_NEAR(c.signed_volume, 1.0, 1e-5);
  const double h = opt.max_edge * std::sqrt(3.0);
  EXPECT_NEAR(rep.max_edge_m, h, 1e-12);
  for (const auto& t : r.triangles) {
    std::array<double, 3> a{}, b{};
    for (int k = 0; k < 3; ++k) {
      a[k] = double{r.positions[t[1]][k]} - r.positions[t[0]][k];
      b[k] = double{r.positions[t[2]][k]} - r.positions[t[0]][k];
    }
    const std::array<double, 3> fn{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    const double len = std::sqrt(fn[0] * fn[0] + fn[1] * fn[1] + fn[2] * fn[2]);
    for (std::uint32_t v : t) {  // flat faces: every vertex normal is its face's
      const auto& nv = r.normals[v];
      EXPECT_GT((nv[0] * fn[0] + nv[1] * fn[1] + nv[2] * fn[2]) / len, 1 - 1e-6);
      const auto& pv = r.positions[v];  // on the cube's surface
      EXPECT_FLOAT_EQ(std::max({std::fabs(pv[0] - 0.5f), std::fabs(pv[1] - 0.5f), std::fabs(pv[2] - 0.5f)}), 0.5f);
    }
    for (int k = 0; k < 3; ++k) {
      double l2 = 0;
      for (int i = 0; i < 3; ++i) l2 += std::pow(double{r.positions[t[(k + 1) % 3]][i]} - r.positions[t[k]][i], 2);
      EXPECT_LE(std::sqrt(l2), h * (1 + 1e-6));
    }
  }
  // Deterministic.
  const TriangleMesh again = bake::refine_transparent_mesh(cube, opt, nullptr);
  EXPECT_EQ(again.positions, r.positions);
  EXPECT_EQ(again.normals, r.normals);
  EXPECT_EQ(again.triangles, r.triangles);
}

TEST(GlassRefine, SmoothMeshesAreLeftAlone) {
  // glass_ball's UV sphere: no crease, no flat triangle.
  auto sphere = bake::import_mesh(std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/sphere.obj");
  ASSERT_TRUE(sphere.ok());
  bake::GlassRefineReport rep;
  const TriangleMesh r = bake::refine_transparent_mesh(sphere->mesh, {}, &rep);
  EXPECT_FALSE(rep.changed());
  EXPECT_EQ(rep.flat_triangles, 0u);
  EXPECT_EQ(r.positions, sphere->mesh.positions);
  EXPECT_EQ(r.normals, sphere->mesh.normals);
  EXPECT_EQ(r.triangles, sphere->mesh.triangles);
  // The prism with splitting off: only its creases.
  auto prism = bake::import_mesh(kWedgePrism);
  ASSERT_TRUE(prism.ok());
  bake::GlassRefineOptions creases_only;
  creases_only.max_edge = 0;
  const TriangleMesh pr = bake::refine_transparent_mesh(prism->mesh, creases_only, &rep);
  EXPECT_EQ(rep.crease_edges, 9u);
  EXPECT_EQ(pr.positions.size(), 18u);  // 3 faces meet at each of the 6 corners
  EXPECT_EQ(pr.triangles.size(), 8u);
}

TEST(GlassRefine, CurvedGlassIsSplitUntilItsNormalsTurnLittle) {
  // glass_ball's UV sphere (edges turning up to 10.6 degrees at the poles,
  // 7.5 along the equator) with --glass-turn 5.
  auto sphere = bake::import_mesh(std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/sphere.obj");
  ASSERT_TRUE(sphere.ok());
  bake::GlassRefineOptions opt;
  opt.max_turn_deg = 5;
  bake::GlassRefineReport rep;
  const TriangleMesh r = bake::refine_transparent_mesh(sphere->mesh, opt, &rep);
  std::printf("[refine, sphere, 5 degrees] %u -> %u vertices, turn %.2f -> %.2f degrees, %u rounds\n", rep.vertices_in,
              rep.vertices_out, rep.max_turn_in, rep.max_turn_out, rep.rounds);
  EXPECT_GT(rep.max_turn_in, 5.0);
  EXPECT_LE(rep.max_turn_out, 5.0);
  EXPECT_GT(rep.curved_edges_split, 0u);
  const EdgeCensus c = census_edges(r);
  EXPECT_TRUE(c.closed());
  EXPECT_NEAR(c.signed_volume, census_edges(sphere->mesh).signed_volume, 1e-6);  // new vertices lie on old edges
  for (std::size_t v = 0; v < r.positions.size(); ++v) {
    const auto& p = r.positions[v];
    const auto& n = r.normals[v];
    const double pr = std::sqrt(double{p[0]} * p[0] + double{p[1]} * p[1] + double{p[2]} * p[2]);
    EXPECT_NEAR(std::sqrt(double{n[0]} * n[0] + double{n[1]} * n[1] + double{n[2]} * n[2]), 1.0, 1e-6);
    // Inside the unit sphere by at most the chord's sagitta (1 - cos 5.3 deg); the Phong normal is radial there.
    EXPECT_LE(pr, 1.0 + 1e-6);
    EXPECT_GE(pr, std::cos(5.3 * kPi / 180));
    EXPECT_GT((n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) / pr, std::cos(0.5 * kPi / 180));
  }
  // Off, or without a length bound (it keeps the rounds finite), nothing changes.
  opt.max_edge = 0;
  bake::refine_transparent_mesh(sphere->mesh, opt, &rep);
  EXPECT_FALSE(rep.changed());
}

TEST_F(Glass, RotatingGlassAndLightRotatesTheImage) {
  nlohmann::json a = scene("glass_teapot");
  a["objects"].erase(1);  // the block would break the symmetry of the floor
  nlohmann::json b = a;
  b["objects"][1]["transform"]["rotate_deg"] = {0, 120, 0};
  b["lights"][0]["direction"] = {0.2, -1.0, -0.35};  // (x, z) -> (z, -x): 90 degrees about y
  const int n = 256;
  const auto ea = floor_irradiance(a, n), eb = floor_irradiance(b, n);
  double diff = 0, sa = 0, sb = 0;
  for (int i = 0; i < n; ++i) {
    for (int jj = 0; jj < n; ++jj) {
      const double va = ea[static_cast<std::size_t>(i) * n + jj];
      const double vb = eb[static_cast<std::size_t>(n - 1 - jj) * n + i];
      diff += std::fabs(va - vb);
      sa += va;
      sb += vb;
    }
  }
  // Not vacuous: there is a caustic, and the unrotated images differ.
  double unrotated = 0;
  for (std::size_t k = 0; k < ea.size(); ++k) unrotated += std::fabs(ea[k] - eb[k]);
  EXPECT_GT(*std::max_element(ea.begin(), ea.end()), 2.0f);
  EXPECT_GT(unrotated / sa, 0.05);
  std::printf("[glass_teapot] rotated: relative L1 %.4f (unrotated %.4f), flux ratio %.5f\n", diff / sa, unrotated / sa, sb / sa);
  EXPECT_NEAR(sb / sa, 1.0, 0.002);
  EXPECT_LT(diff / sa, 0.03);
}

// Copies of one glass ball: baked once, one LTTB for the three
// (LTTR names the copies), drawn from one set of GPU tables, and the
// floor's light the same, texel for texel, as from three tables of their
// own (--no-share). Each copy, turned and scaled, still focuses as optics
// says for its own radius (the exact sphere of optics_oracle.h, 1 mm
// pixels): power within 5 cm of its axis within 5 % (BallLensFocusAgrees-
// WithOptics's bound beyond 1 cm; measured -4.7, -3.0, -3.4 %), and the
// turned copy within 3 % of the unturned one at 2 and 5 cm (measured +1.4,
// +1.8 %). At 2 cm the copies read -6.5 to -8.1 % against optics, printed
// and not asserted: the floor's one focus window has to span
// all three spots, 2.4 m apart, so it does not sharpen them.
TEST_F(Glass, CopiesShareOneTableAndFocusAsOptics) {
  nlohmann::json j = scene("glass_ball");
  const nlohmann::json ball = j["objects"][1];
  j["objects"].erase(1);
  struct Copy {
    const char* name;
    double x, r;
    std::array<double, 3> turn;
  };
  const Copy copies[] = {{"a", -1.2, 0.3, {0, 0, 0}}, {"b", 0.0, 0.3, {35, 60, 20}}, {"c", 1.2, 0.2, {-50, 10, 80}}};
  for (const Copy& c : copies) {
    nlohmann::json o = ball;
    o["name"] = c.name;
    o["transform"] = {{"translate", {c.x, 1.5 * c.r, 0}}, {"rotate_deg", c.turn}, {"scale", c.r}};  // focus f = 1.5 r on the floor
    j["objects"].push_back(o);
  }
  const std::string path = test::write_scene(j, "glass_copies");
  auto shared = bake::bake_scene(path, {});
  ASSERT_TRUE(shared.ok()) << shared.error().message;
  bake::BakeOptions own;
  own.share = false;
  auto separate = bake::bake_scene(path, own);
  ASSERT_TRUE(separate.ok()) << separate.error().message;
  auto a = runtime::load_scene(shared->cxb.data(), shared->cxb.size());
  auto b = runtime::load_scene(separate->cxb.data(), separate->cxb.size());
  ASSERT_TRUE(a.ok()) << a.error().message;
  ASSERT_TRUE(b.ok()) << b.error().message;
  EXPECT_EQ(a->transport_tables.size(), 1u);
  EXPECT_EQ(b->transport_tables.size(), 3u);
  EXPECT_EQ(a->desc.objects[2].tables_from, std::optional<std::uint32_t>{1});
  EXPECT_EQ(a->desc.objects[3].tables_from, std::optional<std::uint32_t>{1});
  std::printf("[glass copies] .cxb %zu bytes shared, %zu with a table each\n", shared->cxb.size(), separate->cxb.size());
  EXPECT_LT(shared->cxb.size() * 2, separate->cxb.size());

  const LightTransportTable& t = a->transport_tables[0];
  const std::uint64_t table_bytes = std::uint64_t{t.vertex_count} * t.resolution * t.resolution * 16;
  auto ra = sample::Renderer::create(std::move(*a));
  auto rb = sample::Renderer::create(std::move(*b));
  ASSERT_TRUE(ra.ok() && rb.ok());
  const int n = 128;
  const double pix = 0.001;
  std::vector<std::array<double, 2>> rel;  // each copy's power over optics', within 2 and 5 cm
  for (const Copy& c : copies) {
    sample::IrradianceRequest q = floor_request(n, n * pix / 2);
    q.x0 = static_cast<float>(c.x - n * pix / 2);
    q.x1 = static_cast<float>(c.x + n * pix / 2);
    auto ia = (*ra)->render_irradiance(q);
    auto ib = (*rb)->render_irradiance(q);
    ASSERT_TRUE(ia.ok() && ib.ok());
    EXPECT_EQ(ia->rgb, ib->rgb) << "copy " << c.name << ": the shared table lights it otherwise than its own";
    std::vector<double> got;
    for (std::size_t i = 0; i < ia->rgb.size(); i += 3) got.push_back(ia->rgb[i]);
    const auto want = test::landing_image(ball_lens(c.r, 1.5 * c.r, 1.5, 20000), n, -n * pix / 2, pix);
    rel.emplace_back();
    for (const double radius : {0.02, 0.05}) {
      const double g = test::power_within(got, n, -n * pix / 2, pix, radius), w = test::power_within(want, n, -n * pix / 2, pix, radius);
      rel.back()[radius == 0.05] = g / w;
      std::printf("[glass copies] %s (r %.1f m, turned %g/%g/%g deg): power within %.2f m %+.1f %% of optics\n", c.name, c.r, c.turn[0],
                  c.turn[1], c.turn[2], radius, 100 * (g / w - 1));
      if (radius == 0.05) EXPECT_NEAR(g / w, 1.0, 0.05) << "copy " << c.name << " within " << radius << " m";
    }
  }
  for (std::size_t k = 0; k < 2; ++k) EXPECT_NEAR(rel[1][k] / rel[0][k], 1.0, 0.03) << "the turned copy against the unturned one";
  // The GPU holds the one table once (and the same targets as the other).
  const std::uint64_t ga = (*ra)->engine().stats().memory.glass, gb = (*rb)->engine().stats().memory.glass;
  std::printf("[glass copies] glass GPU bytes %llu shared, %llu with a table each (a table %llu)\n", static_cast<unsigned long long>(ga),
              static_cast<unsigned long long>(gb), static_cast<unsigned long long>(table_bytes));
  EXPECT_GE(gb - ga, 2 * table_bytes);
}

TEST(LightTransport, LookupAgreesWithDirectTraces) {
  bake::BakeOptions opt;
  const runtime::RuntimeScene s = bake_and_load(scene("glass_ball"), opt);
  ASSERT_EQ(s.transport_tables.size(), 1u);
  const LightTransportTable& t = s.transport_tables[0];
  ASSERT_EQ(t.resolution, kDefaultTransportResolution);
  const Object& ball = s.desc.objects[t.object];
  const TriangleMesh& mesh = s.meshes[ball.mesh_index];
  const bake::TransportTracer tracer(ball.material, mesh, opt.transport.max_bounces);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  struct Worst {
    double dir = 0, pos = 0, t = 0;
  } worst[2];
  int compared = 0;
  for (int k = 0; k < 4000; ++k) {
    const auto v = static_cast<std::uint32_t>(rng() % t.vertex_count);
    const Dir3 nrm{mesh.normals[v][0], mesh.normals[v][1], mesh.normals[v][2]};
    Dir3 w{u(rng), u(rng), u(rng)};
    const double len = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (len > 1 || len < 1e-3) continue;
    for (double& c : w) c /= len;
    if (w[0] * nrm[0] + w[1] * nrm[1] + w[2] * nrm[2] < 0.3) continue;  // away from grazing (T -> 0 there)
    const TransportEntry exact = tracer.trace(v, w);
    if (exact.status != TransportStatus::kLeaves) continue;
    for (int mode = 0; mode < 2; ++mode) {
      const TransportEntry got = lookup(t, v, nrm, w, mode ? Interpolation::kBicubic : Interpolation::kBilinear);
      ASSERT_EQ(got.status, TransportStatus::kLeaves);
      const double c = exact.direction[0] * got.direction[0] + exact.direction[1] * got.direction[1] +
                       exact.direction[2] * got.direction[2];
      Worst& m = worst[mode];
      m.dir = std::max(m.dir, std::acos(std::min(1.0, c)) * 180 / kPi);
      m.pos = std::max(m.pos, std::hypot(exact.exit[0] - got.exit[0], exact.exit[1] - got.exit[1], exact.exit[2] - got.exit[2]));
      m.t = std::max(m.t, std::fabs(exact.transmittance - got.transmittance));
    }
    ++compared;
  }
  for (int mode = 0; mode < 2; ++mode) {
    std::printf("[ltt R=%u %s] %d look-ups: worst exit-direction error %.3f deg, exit point %.4f m (unit sphere), T %.4f\n",
                t.resolution, mode ? "bicubic" : "bilinear", compared, worst[mode].dir, worst[mode].pos, worst[mode].t);
  }
  ASSERT_GT(compared, 600);
  // docs/glass-tables.md: at the default R = 20 (12-bit fields, 14-bit Draco
  // normals) the sweep measured 0.49 deg bicubic and 1.0 deg bilinear over
  // 4000 look-ups on this mesh. The bounds leave room for the other sample
  // set, and require bicubic to beat bilinear clearly.
  EXPECT_LT(worst[1].dir, 0.65);
  EXPECT_LT(worst[1].dir, 0.75 * worst[0].dir);
  EXPECT_LT(worst[1].pos, 0.02);
  EXPECT_LT(worst[1].t, 0.03);
}

// Light is followed until it leaves the object for good. Two unit cubes in
// one mesh, the upper one dy above the lower: overlapping (dy = 0.5) they
// are one solid of glass, no interface where the shells cross; apart
// (dy = 1.2) the light leaves the upper one and enters the lower one. A
// ray through parallel faces leaves along the light, with T(theta) at each
// real interface, after 1.5 m or 2 m of glass at the refracted angle. The
// tracer used to stop at the inner shell (trapped) or at the first exit.
TEST(LightTransport, LightCrossesOverlappingShellsAndReEntersTheObject) {
  const Material glass{.transparent = true, .ior = 1.5f};
  const Dir3 to_light = [] {
    Dir3 w{0.12, 1.0, 0.07};
    const double len = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    for (double& c : w) c /= len;
    return w;
  }();
  const double cos_i = to_light[1], cos_t = std::sqrt(1 - (1 - cos_i * cos_i) / (1.5 * 1.5));
  for (const auto& [dy, interfaces, glass_length, events] : {std::tuple{0.5, 2, 1.5, 0}, std::tuple{1.2, 4, 2.0, 1}}) {
    TriangleMesh mesh = test::subdivided_cube(2);
    const TriangleMesh upper = test::subdivided_cube(2);
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (std::size_t v = 0; v < upper.positions.size(); ++v) {
      const auto& q = upper.positions[v];
      mesh.positions.push_back({q[0], q[1] + static_cast<float>(dy), q[2]});
      mesh.normals.push_back(upper.normals[v]);
    }
    for (const auto& t : upper.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    std::uint32_t top = 0;  // the centre of the upper cube's top face
    for (std::uint32_t v = base; v < mesh.positions.size(); ++v) {
      const auto& q = mesh.positions[v];
      if (q[0] == 0 && q[2] == 0 && q[1] > static_cast<float>(dy)) top = v;
    }
    ASSERT_NE(top, 0u);
    const bake::TransportTracer tracer(glass, mesh, 4);
    const TransportEntry e = tracer.trace(top, to_light);
    ASSERT_EQ(e.status, TransportStatus::kLeaves) << "dy " << dy;
    const double t = fresnel_t(cos_i, 1.5);
    std::printf("[two cubes, dy %.1f] exit y %.4f, T %.5f (T^%d %.5f), path %.4f (%.4f), events %d\n", dy, e.exit[1], e.transmittance,
                interfaces, std::pow(t, interfaces), e.path, glass_length / cos_t, e.bounces);
    EXPECT_NEAR(e.exit[1], -0.5, 1e-5);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(e.direction[static_cast<std::size_t>(k)], -to_light[static_cast<std::size_t>(k)], 1e-9);
    EXPECT_NEAR(e.transmittance, std::pow(t, interfaces), 1e-9);
    EXPECT_NEAR(e.path, glass_length / cos_t, 1e-5);
    EXPECT_EQ(e.bounces, events);
  }
  // A convex object cannot meet light that left it: two casts (towards the
  // light, then inside), none after the exit.
  const TriangleMesh cube = test::subdivided_cube(2);
  std::uint32_t top = 0;
  for (std::uint32_t v = 0; v < cube.positions.size(); ++v) {
    if (cube.positions[v] == std::array<float, 3>{0, 0.5f, 0}) top = v;
  }
  std::uint64_t casts = 0;
  const TransportEntry e = bake::TransportTracer(glass, cube, 4).trace(top, to_light, &casts);
  EXPECT_EQ(e.status, TransportStatus::kLeaves);
  EXPECT_EQ(casts, 2u);
}

TEST(LightTransport, AnOpenMeshBakesThinWalledNamingEdges) {
  nlohmann::json j = scene("glass_ball");
  j["objects"][1]["mesh"] = kScenes + "../meshes/teapot.obj";  // the Utah teapot has open rims
  auto baked = bake::bake_scene(test::write_scene(j, "glass_open"), {});
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  EXPECT_EQ(baked->scene.objects[1].role, Role::kThin);
  EXPECT_TRUE(baked->transport.empty());
  std::string said;
  for (const auto& w : baked->warnings) said += w + "\n";
  EXPECT_NE(said.find("teapot.obj: transparent object 'ball' is not a closed, consistently wound mesh: it has"), std::string::npos) << said;
  EXPECT_NE(said.find("boundary edge"), std::string::npos) << said;
  EXPECT_NE(said.find("baked thin-walled"), std::string::npos) << said;
}

// Light transport runs inside the object: a closed mesh that is wound
// inconsistently or has edges of three triangles is refused, saying which,
// before any tracing (a solid was meant); one with a hole too bounds no
// solid and bakes thin-walled, saying so; a solid wound inside out is
// turned outside out, saying so, into exactly the intact solid.
TEST(LightTransport, MiswoundAndNonManifoldSolidsAreRefused) {
  using test::CubeFlaw;
  const std::vector<std::pair<CubeFlaw, std::string>> cases{
      {CubeFlaw::kFlippedFace, "3 edge(s) whose two triangles are wound inconsistently"},
      {CubeFlaw::kDuplicateFace, "non-manifold edge(s)"},
      {CubeFlaw::kFin, "2 boundary edge(s) of holes, 1 non-manifold edge(s)"}};
  for (const auto& [flaw, says] : cases) {
    const auto mesh = std::filesystem::temp_directory_path() / ("caustix_flawed_cube_" + std::to_string(int(flaw)) + ".obj");
    std::ofstream(mesh) << test::to_obj(test::unit_cube(flaw));
    nlohmann::json j = scene("glass_ball");
    j["objects"][1]["mesh"] = mesh.string();
    bake::BakeOptions small;
    small.transport.resolution = 4;
    auto baked = bake::bake_scene(test::write_scene(j, "glass_flawed"), small);
    if (flaw == CubeFlaw::kFin) {
      ASSERT_TRUE(baked.ok()) << baked.error().message;
      EXPECT_EQ(baked->scene.objects[1].role, Role::kThin);
      std::string said;
      for (const auto& w : baked->warnings) said += w + "\n";
      EXPECT_NE(said.find(says), std::string::npos) << said;
      continue;
    }
    ASSERT_FALSE(baked.ok()) << says;
    EXPECT_EQ(baked.error().code, ErrorCode::kInput);
    EXPECT_NE(baked.error().message.find(mesh.string() + ": transparent object 'ball'"), std::string::npos) << baked.error().message;
    EXPECT_NE(baked.error().message.find(says), std::string::npos) << baked.error().message;
  }
  // The cube inside out bakes turned, the same bytes as the intact cube
  // (same path, so that only the mesh can differ).
  const auto mesh = std::filesystem::temp_directory_path() / "caustix_cube.obj";
  nlohmann::json j = scene("glass_ball");
  j["objects"][1]["mesh"] = mesh.string();
  bake::BakeOptions opt;
  opt.transport.resolution = 4;
  std::ofstream(mesh) << test::to_obj(test::unit_cube(CubeFlaw::kInsideOut));
  auto turned = bake::bake_scene(test::write_scene(j, "glass_cube"), opt);
  ASSERT_TRUE(turned.ok()) << turned.error().message;
  std::string said;
  for (const auto& w : turned->warnings) said += w + "\n";
  EXPECT_NE(said.find(mesh.string() + ": transparent object 'ball' is wound inside out (signed volume -1.0"), std::string::npos) << said;
  EXPECT_NE(said.find("baked turned outside out (its triangles reversed)"), std::string::npos) << said;
  EXPECT_EQ(turned->scene.objects[1].role, Role::kTransparent);
  std::ofstream(mesh) << test::to_obj(test::unit_cube());
  auto baked = bake::bake_scene(test::write_scene(j, "glass_cube"), opt);
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  EXPECT_TRUE(baked->cxb == turned->cxb);
}

// A table above kMaxTransportEntries (1 GiB) is refused before tracing:
// the solid teapot's 4.7k vertices x 128^2 directions = 76 M entries.
TEST(LightTransport, TablesAboveTheLimitAreRefusedUpFront) {
  bake::BakeOptions opt;
  opt.transport.resolution = 128;
  auto baked = bake::bake_scene(kScenes + "glass_teapot.json", opt);
  ASSERT_FALSE(baked.ok());
  EXPECT_EQ(baked.error().code, ErrorCode::kInput);
  EXPECT_NE(baked.error().message.find("above the limit of 67108864"), std::string::npos) << baked.error().message;
}

// Byte-identical files for 1 and 2 threads: glass_ball (convex: one cast
// per path inside) and glass_teapot (re-entries, overlapping shells), the
// tables' rays through Embree (its BVH built on one thread) and, for the
// ball, through CGAL.
TEST(LightTransport, TableIsIndependentOfThreadCount) {
  for (const char* name : {"glass_ball", "glass_teapot"}) {
    const std::string path = test::write_scene(scene(name), std::string("glass_threads_") + name);
    for (const bake::RayEngine rays : {bake::RayEngine::kEmbree, bake::RayEngine::kCgal}) {
      if (rays == bake::RayEngine::kCgal && std::string(name) == "glass_teapot") continue;
      bake::BakeOptions opt;
      opt.transport.rays = rays;
      if (std::string(name) == "glass_teapot") opt.transport.resolution = 8;  // the property, not the accuracy
      std::vector<std::uint8_t> first;
      for (int threads : {1, 2}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
        auto baked = bake::bake_scene(path, opt);
        ASSERT_TRUE(baked.ok()) << baked.error().message;
        if (first.empty()) first = baked->cxb;
        else EXPECT_EQ(first, baked->cxb) << name << (rays == bake::RayEngine::kCgal ? " through CGAL" : " through Embree");
      }
    }
  }
}

// The tables through Embree against those through CGAL's exact tree (issue
// 48), entry by entry, on the canonical ball (convex, smooth), teapot
// (re-entries, total internal reflection, overlapping shells) and prism
// (flat faces on a regular grid of vertices, creases): where both leave,
// exit points and directions within one stored step (12 bits: 16 / 65535
// of the exit box per axis; directions 0.12 degrees, two of the 0.059-degree
// bound), and the same status and class for all but a few entries, whose
// rays pass within float precision of an edge or a vertex and go their
// different ways there (measured 0, 0.24 and 1.8 per thousand). Apart are
// the entries whose direction lies on the vertex's horizon (cos 0: no light
// enters, T = 0), which CGAL finds blocked by the coplanar triangles of a
// flat face and Embree, whose ray runs parallel to them, does not (the
// prism: 12 794 of 254 784).
TEST(LightTransport, EmbreeTablesAgreeWithCgal) {
  struct Case {
    const char* scene;
    std::uint32_t resolution;
    double max_other;
  };
  for (const Case& c : {Case{"glass_ball", 12, 1e-4}, Case{"glass_teapot", 8, 5e-4}, Case{"prism", 8, 3e-3}}) {
    const nlohmann::json j = scene(c.scene);
    std::size_t glass = 0;
    while (j["objects"][glass]["role"] != "transparent") ++glass;
    bake::BakeOptions opt;
    opt.transport.resolution = c.resolution;
    opt.transport.wavelengths = 0;
    const runtime::RuntimeScene s = bake_and_load(j, opt);
    const Object& o = s.desc.objects[glass];
    const TriangleMesh& mesh = s.meshes[o.mesh_index];
    bake::TransportOptions to = opt.transport;
    to.rays = bake::RayEngine::kCgal;
    const LightTransportTable exact = bake::trace_transport_table(0, o.material, mesh, to, nullptr);
    to.rays = bake::RayEngine::kEmbree;
    const LightTransportTable fast = bake::trace_transport_table(0, o.material, mesh, to, nullptr);
    const std::uint32_t per_vertex = c.resolution * c.resolution;
    const std::size_t n = std::size_t{exact.vertex_count} * per_vertex;
    std::size_t other = 0, horizon = 0, both = 0, apart = 0;
    double worst_pos = 0, worst_dir = 0;
    const double step = 16.0 / 65535.0;
    for (std::size_t i = 0; i < n; ++i) {
      const TransportEntry a = exact.load(i), b = fast.load(i);
      if (a.status != b.status || a.bounces != b.bounces) {
        const auto& nf = mesh.normals[i / per_vertex];
        const Dir3 nv{nf[0], nf[1], nf[2]};
        const auto rc = static_cast<std::uint32_t>(i % per_vertex);
        const Dir3 w = grid_direction(nv, c.resolution, rc / c.resolution, rc % c.resolution);
        (w[0] * nv[0] + w[1] * nv[1] + w[2] * nv[2] <= 0 ? horizon : other) += 1;
        continue;
      }
      if (a.status != TransportStatus::kLeaves) continue;
      ++both;
      double pos = 0;
      for (std::size_t k = 0; k < 3; ++k) {
        const double range = double{exact.exit_max[k]} - exact.exit_min[k];
        if (range > 0) pos = std::max(pos, std::fabs(a.exit[k] - b.exit[k]) / (range * step));
      }
      const double cosine = a.direction[0] * b.direction[0] + a.direction[1] * b.direction[1] + a.direction[2] * b.direction[2];
      const double dir = std::acos(std::min(1.0, cosine)) * 180 / kPi;
      if (pos > 1.0 || dir > 0.12) {
        ++apart;
        continue;
      }
      worst_pos = std::max(worst_pos, pos);
      worst_dir = std::max(worst_dir, dir);
    }
    std::printf("[embree vs cgal] %s at R %u, %zu entries: %zu of another status or class (and %zu on the horizon); where both "
                "leave (%zu), %zu further apart than a stored step, the rest within %.2f steps and %.4f deg\n",
                c.scene, c.resolution, n, other, horizon, both, apart, worst_pos, worst_dir);
    EXPECT_LE(static_cast<double>(other + apart), c.max_other * static_cast<double>(n)) << c.scene;
  }
}

// Where a look-up's cell holds two path classes, the class of its heaviest
// corner is extrapolated linearly from that class's entries up to the
// query instead of averaged over its corners (linear_fit_weights()). The
// prism (flat faces: a look-up in a cell of one class is near exact) with
// the light straight down, every slope vertex against its exact trace,
// landing on the floor 0.3 m below the bottom. Light entering at x0 <
// -0.425 m reflects totally before it leaves, so the vertices near there
// look up cells that hold both classes. Before: mean landing error 1.6 mm,
// 36 vertices over 1 cm, at most 3.1 cm (x0 = -0.4375: -0.3811 m for
// -0.4122 m). Now 0.4 mm, 3 over 1 cm, at most 2.2 cm (vertices next to
// the end faces, where the edge refinement puts them within 3 mm of the
// switch). The class: with the switches the baker stores (LTTW), the
// side of the switch the light's direction is on; 2 vertices within 3 mm
// of it are on the wrong side (4 with the heaviest corner's class).
TEST(LightTransport, MixedCellsExtrapolateTheirPathClass) {
  nlohmann::json j = scene("prism");
  j["objects"][1]["material"].erase("dispersion");
  bake::BakeOptions opt;
  opt.transport.wavelengths = 0;
  const runtime::RuntimeScene s = bake_and_load(j, opt);
  const LightTransportTable& t = s.transport_tables[0];
  const Object& o = s.desc.objects[t.object];
  const TriangleMesh& mesh = s.meshes[o.mesh_index];
  const bake::TransportTracer tracer(o.material, mesh, opt.transport.max_bounces);
  const Dir3 down{0, 1, 0};  // towards the light
  const auto landing = [](const TransportEntry& e) { return e.exit[0] - e.direction[0] * e.exit[1] / e.direction[1]; };
  int slope = 0, wrong = 0, reflected = 0, off = 0;
  double worst = 0, sum = 0;
  for (std::uint32_t v = 0; v < t.vertex_count; ++v) {
    const Dir3 n{mesh.normals[v][0], mesh.normals[v][1], mesh.normals[v][2]};
    if (std::fabs(n[0] - 1 / std::sqrt(5.0)) > 1e-3 || std::fabs(n[1] - 2 / std::sqrt(5.0)) > 1e-3) continue;
    // Not the slope's end edges, whose light runs within the end faces'
    // planes (the exact trace and the table's go their different ways there).
    if (std::fabs(mesh.positions[v][2]) > 0.49) continue;
    const TransportEntry exact = tracer.trace(v, down);
    const TransportEntry got = lookup(t, v, n, down);
    if (exact.status != TransportStatus::kLeaves) continue;  // a vertex on the slope's upper edge
    ASSERT_EQ(got.status, TransportStatus::kLeaves);
    ++slope;
    reflected += exact.bounces > 0 ? 1 : 0;
    if (got.bounces != exact.bounces) {
      ++wrong;
      continue;
    }
    const double err = std::fabs(landing(got) - landing(exact));
    off += err > 0.01 ? 1 : 0;
    sum += err;
    worst = std::max(worst, std::fabs(landing(got) - landing(exact)));
  }
  std::printf("[prism, light straight down] %d slope vertices (%d reflected totally): %d of another class; landing error "
              "mean %.5f m, at most %.4f m, %d over 1 cm\n", slope, reflected, wrong, sum / (slope - wrong), worst, off);
  EXPECT_GT(reflected, 200);
  EXPECT_LE(wrong, 2);
  EXPECT_LT(worst, 0.025);
  EXPECT_LE(off, 3);
}

}  // namespace
}  // namespace caustix
