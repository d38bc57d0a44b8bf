// Dispersive glass through light-transport tables (
// docs/dispersion.md), physics as the oracle: the monochromatic images of a
// dispersive ball lens at the F, d and C lines against the exact trace of
// a sphere of that index; the interpolation between tables against a
// table baked at the wavelength itself; the RGB image as the bins'
// monochromatic images times their weights, each channel keeping its
// energy; one wavelength bit-identical to the ball without dispersion.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "caustix/bake/bake.h"
#include "caustix/formats/spectrum.h"
#include "caustix/sample/renderer.h"
#include "bake_fixture.h"
#include "gl_fixture.h"
#include "optics_oracle.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

struct Floor {
  std::vector<float> rgb;  // irradiance / E0, row-major, three channels
  std::vector<float> e;    // red
  std::uint32_t wavelengths = 0;
};

class GlassDispersion : public test::GlTest {
 protected:
  static std::unique_ptr<sample::Renderer> create(const std::string& name, std::uint32_t table_wavelengths) {
    bake::BakeOptions opt;
    opt.transport.wavelengths = table_wavelengths;
    return test::bake_and_create(test::write_scene(test::canonical_scene(name), "glass_dispersion_test"), opt);
  }
  // The floor's irradiance over |x|, |z| < half, n x n, glass by its tables.
  static Floor render(sample::Renderer& r, int n, double half, const runtime::CausticsOptions& o) {
    sample::IrradianceRequest q;
    q.receiver = "floor";
    q.x0 = q.z0 = static_cast<float>(-half);
    q.x1 = q.z1 = static_cast<float>(half);
    q.width = q.height = n;
    q.caustics = o;
    auto img = r.render_irradiance(q);
    EXPECT_TRUE(img.ok()) << img.error().message;
    Floor f;
    if (!img.ok()) return f;
    f.rgb = img->rgb;
    for (std::size_t i = 0; i < f.rgb.size(); i += 3) {
      EXPECT_TRUE(std::isfinite(f.rgb[i]) && std::isfinite(f.rgb[i + 1]) && std::isfinite(f.rgb[i + 2]));
      f.e.push_back(f.rgb[i]);
    }
    f.wavelengths = r.engine().stats().glass_wavelengths;
    return f;
  }
  static runtime::CausticsOptions at(float nm) {
    runtime::CausticsOptions o;
    o.wavelength_nm = nm;
    return o;
  }
};

double relative_l1(const std::vector<float>& a, const std::vector<float>& b) {
  double d = 0, s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d += std::fabs(a[i] - b[i]);
    s += std::fabs(b[i]);
  }
  return d / s;
}

// dispersive_ball (n_d 1.5, V_d 20), tables at the defaults (380 and
// 780 nm besides n_d), illumination textures of 1024^2 (3.9 mm texels over
// the floor): at each line the transmitted flux within 5 % of the exact
// sphere's at n(lambda), its R50 within 10 % and the encircled power within
// 10 % (the target) at 2-20 cm. Before the focus windows
// the default 512^2 texels (the 2 cm circle 2.5 texels wide) put the C
// line's sharper focus at -10.7 % there; the focus itself is judged in
// finer pixels below. The F line's image misses the C line's exact pattern
// by more than that, and back.
TEST_F(GlassDispersion, BallLensPerWavelengthFromTables) {
  const int n = 512;
  const double half = 2.0, pix = 2 * half / n;
  auto r = create("dispersive_ball", kDefaultTransportWavelengths);
  ASSERT_TRUE(r);
  const float dispersion = r->scene().objects[1].material.dispersion;
  std::vector<test::BallLensFloor> got;
  for (const float nm : {kWavelengthF, kWavelengthD, kWavelengthC}) {
    const double ior = index_at(1.5f, dispersion, nm);
    runtime::CausticsOptions o = at(nm);
    o.glass_map_size = 1024;
    const Floor f = render(*r, n, half, o);
    EXPECT_EQ(f.wavelengths, 1u);
    const test::BallLensFloor b = test::ball_lens_floor(f.e, n, half, ior);
    std::printf("[dispersive_ball, tables] %.2f nm, n %.5f: transmitted %.4f / exact %.4f; R50 %.4f / %.4f m\n", nm, ior,
                b.transmitted, b.expected, b.m50, b.r50);
    EXPECT_NEAR(b.transmitted / b.expected, 1.0, 0.05) << nm << " nm";
    EXPECT_NEAR(b.m50, b.r50, std::max(2 * pix, 0.1 * b.r50)) << nm << " nm";
    for (double radius : {0.02, 0.03, 0.05, 0.1, 0.2}) {
      const double ratio = test::encircled(b.measured, radius) / test::encircled(b.exact, radius);
      std::printf("[dispersive_ball, tables] %.2f nm: encircled power within %.2f m %+.1f %%\n", nm, radius, 100 * (ratio - 1));
      EXPECT_NEAR(ratio, 1.0, 0.10) << nm << " nm, " << radius << " m";
    }
    got.push_back(b);
  }
  EXPECT_TRUE(test::lines_apart(got, "[dispersive_ball, tables]"));
}

// The rainbow at the focus: at the default preset (512^2
// textures, the focus window), each line's power within 1 cm of the axis
// against the exact sphere at n(lambda), rasterised into the same 0.5 mm
// pixels (optics_oracle.h), within 10 %, and the F/C ratio of those powers
// within 3 % of optics' (0.636 in these pixels: the F line focuses above
// the floor and spreads wider). The issue, before the window, read -22 %
// to -27 % for the lines. Both ways of drawing a dispersive glass's window
// (CausticsOptions::glass_focus_spectral_coarse; docs/glass-focus.md, "A window
// per wavelength"): at half its texels, interpolated (the default;
// measured -1.4, -4.7, -3.5 % and +2.2 %), and at its own (accurate;
// -0.8, -3.1, -2.1 % and +1.4 %). The two must differ (the coarse window
// was drawn) and hold the same light within the image (0.5 %).
TEST_F(GlassDispersion, BallLensFocusPerLineAgreesWithOptics) {
  const int n = 204;
  const double half = 0.051, pix = 2 * half / n;
  auto r = create("dispersive_ball", kDefaultTransportWavelengths);
  ASSERT_TRUE(r);
  const float dispersion = r->scene().objects[1].material.dispersion;
  const float lines[3] = {kWavelengthF, kWavelengthD, kWavelengthC};
  std::vector<float> d_line[2];
  for (const bool coarse : {true, false}) {
    const char* label = coarse ? "coarse window" : "full window";
    double got[3] = {0, 0, 0}, want[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const double ior = index_at(1.5f, dispersion, lines[k]);
      runtime::CausticsOptions o = at(lines[k]);
      o.glass_focus_spectral_coarse = coarse;
      const Floor f = render(*r, n, half, o);
      if (k == 1) d_line[coarse ? 0 : 1] = f.e;
      const std::vector<double> e(f.e.begin(), f.e.end());
      got[k] = test::power_within(e, n, -half, pix, 0.01);
      want[k] = test::power_within(test::landing_image(test::ball_lens(0.5, 0.75, ior, 20000), n, -half, pix), n, -half, pix, 0.01);
      std::printf("[dispersive_ball, focus, %s] %.2f nm, n %.5f: power within 1 cm %.5f vs %.5f optics (%+.1f %%)\n", label, lines[k],
                  ior, got[k], want[k], 100 * (got[k] / want[k] - 1));
      EXPECT_NEAR(got[k] / want[k], 1.0, 0.10) << lines[k] << " nm, " << label;
    }
    const double ratio = got[0] / got[2], exact = want[0] / want[2];
    std::printf("[dispersive_ball, focus, %s] F/C within 1 cm %.4f vs %.4f optics (%+.1f %%)\n", label, ratio, exact,
                100 * (ratio / exact - 1));
    EXPECT_NEAR(ratio / exact, 1.0, 0.03) << label;
  }
  double flux[2] = {0, 0};
  for (int k = 0; k < 2; ++k) flux[k] = std::accumulate(d_line[k].begin(), d_line[k].end(), 0.0);
  const double apart = relative_l1(d_line[0], d_line[1]);
  std::printf("[dispersive_ball, focus] d line, coarse against full window: relative L1 %.4f, flux %.5f\n", apart, flux[0] / flux[1]);
  EXPECT_GT(apart, 0.005) << "the coarse window was not drawn";
  EXPECT_NEAR(flux[0] / flux[1], 1.0, 0.005);
}

// The interpolation between tables (glass_rays_blend.comp) against a table
// baked at the wavelength itself: tables at 380, 480, 580, 680 and 780 nm
// (--ltt-wavelengths 5) make 480 nm exact; the defaults interpolate it
// between the 380 nm and n_d tables. At a wavelength both files hold
// (380 nm) the images are bit-identical.
TEST_F(GlassDispersion, InterpolatedTablesAgreeWithATableBakedAtTheWavelength) {
  const int n = 256;
  const double half = 0.5;
  auto two = create("dispersive_ball", 2), five = create("dispersive_ball", 5);
  ASSERT_TRUE(two && five);
  EXPECT_EQ(two->scene().objects[1].material.spectral_tables, 2u);
  EXPECT_EQ(five->scene().objects[1].material.spectral_tables, 5u);
  const Floor a = render(*two, n, half, at(380)), b = render(*five, n, half, at(380));
  EXPECT_EQ(a.rgb, b.rgb);
  const Floor interpolated = render(*two, n, half, at(480)), exact = render(*five, n, half, at(480));
  const Floor nd = render(*two, n, half, runtime::CausticsOptions{});
  const double err = relative_l1(interpolated.e, exact.e), apart = relative_l1(nd.e, exact.e);
  std::printf("[dispersive_ball, tables] 480 nm interpolated between 380 nm and n_d vs baked at 480 nm: relative L1 %.4f "
              "(the d line's image against it: %.4f)\n", err, apart);
  EXPECT_LT(err, 0.25 * apart);
}

// RGB from 4 bins equals the bins' monochromatic images times the bins'
// weights (to float rounding: the same passes, summed by blending; a
// buffer one wavelength overwrote before the last had read it would show
// as whole triangles off); each channel's floor flux over the ball's
// without dispersion is what the exact sphere at each bin's index puts
// within the image, to 0.1 % (the index moves Fresnel and the rim's
// spread: blue -0.2 %); the fringes are coloured; one wavelength is
// bit-identical to glass_ball, which traces one whatever the count.
TEST_F(GlassDispersion, RgbIsTheWeightedSumOfTheBinsAndOneWavelengthIsTheDLine) {
  const int n = 256;
  const double half = 1.0;
  auto r = create("dispersive_ball", kDefaultTransportWavelengths);
  auto plain = create("glass_ball", kDefaultTransportWavelengths);
  ASSERT_TRUE(r && plain);
  runtime::CausticsOptions o;
  o.wavelengths = 4;
  const Floor rgb = render(*r, n, half, o);
  EXPECT_EQ(rgb.wavelengths, 4u);
  std::vector<double> sum(rgb.rgb.size(), 0.0);
  for (const WavelengthSample& w : wavelength_samples(4)) {
    const Floor mono = render(*r, n, half, at(w.nm));
    for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += w.rgb[i % 3] * mono.rgb[i];
  }
  double worst = 0, peak = 0, diff = 0, total = 0;
  for (std::size_t i = 0; i < sum.size(); ++i) {
    worst = std::max(worst, std::fabs(sum[i] - rgb.rgb[i]));
    peak = std::max(peak, std::fabs(sum[i]));
    diff += std::fabs(sum[i] - rgb.rgb[i]);
    total += std::fabs(sum[i]);
  }
  std::printf("[dispersive_ball, tables] RGB of 4 bins vs their weighted monochromatic images: relative L1 %.3g, largest "
              "difference %.3g of the peak\n", diff / total, worst / peak);
  // Float rounding of sums up to the focus's E/E0 ~ 400 in another order.
  EXPECT_LT(diff / total, 1e-5);
  EXPECT_LT(worst, 1e-5 * peak);

  o.wavelengths = 8;
  const Floor rgb8 = render(*r, n, half, o), ball = render(*plain, n, half, o);
  EXPECT_EQ(rgb8.wavelengths, 8u);
  EXPECT_EQ(ball.wavelengths, 1u);
  double s[3] = {0, 0, 0}, sp[3] = {0, 0, 0}, fringe = 0;
  for (std::size_t i = 0; i < rgb8.rgb.size(); i += 3) {
    for (int c = 0; c < 3; ++c) {
      s[c] += rgb8.rgb[i + c];
      sp[c] += ball.rgb[i + c];
    }
    const double red = rgb8.rgb[i], blue = rgb8.rgb[i + 2];
    if (red + blue > 0.5) fringe = std::max(fringe, std::fabs(blue - red) / (red + blue));
  }
  // What physics expects of each channel against the ball without
  // dispersion: the direct light is the same; the light through the ball
  // that lands within the image (each exact landing ring's part inside the
  // square) changes with n(lambda) (Fresnel, and how far the rim's light
  // spreads), weighted by the bins.
  const auto landed = [&](double ior) {
    double sum = 0;
    for (const auto& l : test::ball_lens(0.5, 0.75, ior, 20000)) {
      const double inside = l.rho <= half ? 1.0 : l.rho >= half * std::sqrt(2.0) ? 0.0 : 1.0 - 4.0 / test::kPi * std::acos(half / l.rho);
      sum += l.weight * inside;
    }
    return sum;
  };
  const double pix2 = (2 * half / n) * (2 * half / n);
  const double nd_landed = landed(1.5), direct = sp[1] * pix2 - nd_landed;
  double want[3] = {0, 0, 0};
  for (const WavelengthSample& w : wavelength_samples(8)) {
    const double l = landed(index_at(1.5f, r->scene().objects[1].material.dispersion, w.nm));
    for (int c = 0; c < 3; ++c) want[c] += w.rgb[static_cast<std::size_t>(c)] * (direct + l);
  }
  for (int c = 0; c < 3; ++c) {
    const double expected = want[c] / (direct + nd_landed);
    std::printf("[dispersive_ball, tables, 8 wavelengths] channel %d: floor flux %.5f vs %.5f without dispersion (%.5f, physics %.5f)\n",
                c, s[c], sp[c], s[c] / sp[c], expected);
    EXPECT_NEAR(s[c] / sp[c], expected, 0.001) << "channel " << c;
  }
  std::printf("[dispersive_ball, tables, 8 wavelengths] largest |B - R| / (R + B) %.3f\n", fringe);
  EXPECT_GT(fringe, 0.1);
  o.wavelengths = 1;
  EXPECT_EQ(render(*r, n, half, o).rgb, ball.rgb);
}

// Tables at n_d only (--ltt-wavelengths 0): the bake warns, RGB traces the
// d line, and a monochromatic image is refused naming the object.
TEST_F(GlassDispersion, TablesAtNdOnlyRefuseAMonochromaticImage) {
  auto r = create("dispersive_ball", 0);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->scene().objects[1].material.spectral_tables, 0u);
  sample::IrradianceRequest q;
  q.receiver = "floor";
  q.width = q.height = 16;
  q.caustics.wavelength_nm = 500;
  auto img = r->render_irradiance(q);
  ASSERT_FALSE(img.ok());
  EXPECT_EQ(img.error().code, ErrorCode::kUsage);
  EXPECT_NE(img.error().message.find("'ball'"), std::string::npos) << img.error().message;
  q.caustics.wavelength_nm.reset();
  ASSERT_TRUE(r->render_irradiance(q).ok());
  EXPECT_EQ(r->engine().stats().glass_wavelengths, 1u);
}

}  // namespace
}  // namespace caustix
