// Water caustics at run time (Tipprasert 2006 §4.3-4.7, §5.2.1), with physics as
// the oracle: flat water transmits T(theta) cos(theta) e^(-K d); a sine
// wave conserves energy and puts its fold lines where a 1-D ray trace does;
// smart slicing, uniform slicing and the volumetric baseline agree (eq. 2-9);
// lights add up; nothing is NaN.

#include <gtest/gtest.h>

#include "bake_fixture.h"
#include "gl_fixture.h"
#include "optics_oracle.h"
#include "scene_fixture.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <tuple>

#include "caustix/bake/bake.h"
#include "caustix/bake/presets.h"
#include "caustix/formats/spectrum.h"
#include "caustix/metrics/image_metrics.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/sample/renderer.h"

namespace caustix {
namespace {

using runtime::CausticsMethod;
using runtime::CausticsOptions;
using sample::IrradianceRequest;

using test::fresnel_t;
using test::kPi;
using test::kScenes;
nlohmann::json scene(const std::string& name) { return test::canonical_scene(name); }

// High-frequency content of img - base: mean |d - box3(d)| over
// mean base, on the green channel.
double high_frequency(const metrics::Image& img, const metrics::Image& base) {
  const int w = img.width, h = img.height;
  auto d = [&](int x, int y) {
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * w + x) + 1;
    return double{img.rgb[i]} - base.rgb[i];
  };
  double hf = 0, sum = 0;
  for (int y = 1; y + 1 < h; ++y) {
    for (int x = 1; x + 1 < w; ++x) {
      double box = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) box += d(x + dx, y + dy) / 9.0;
      }
      hf += std::abs(d(x, y) - box);
      sum += base.rgb[3 * (static_cast<std::size_t>(y) * w + x) + 1];
    }
  }
  return hf / sum;
}

class Caustics : public test::GlTest {
 protected:
  std::unique_ptr<sample::Renderer> renderer(const nlohmann::json& j, const bake::BakeOptions& opt = {}) {
    return test::bake_and_create(test::write_scene(j, "caustics_test"), opt);
  }

  static metrics::Image irradiance(sample::Renderer& r, IrradianceRequest q) {
    auto img = r.render_irradiance(q);
    EXPECT_TRUE(img.ok()) << img.error().message;
    for (float v : img->rgb) EXPECT_TRUE(std::isfinite(v)) << "non-finite irradiance";
    return metrics::Image{img->width, img->height, img->rgb};
  }

  static metrics::Image beauty(sample::Renderer& r, const CausticsOptions& co, int w, int h, float time) {
    sample::FrameParams f{r.default_camera(), time, w, h, co, {}, {}, {}, 1};
    EXPECT_TRUE(r.render(f).ok());
    const auto rgba = r.read_hdr();
    metrics::Image img{w, h, {}};
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_TRUE(std::isfinite(rgba[i + k]));
        img.rgb.push_back(rgba[i + k]);
      }
    }
    return img;
  }

};

TEST_F(Caustics, FlatPoolTransmitsFresnelTimesCosine) {
  auto r = renderer(scene("flat_pool"));
  const double expected = fresnel_t(std::cos(30 * kPi / 180), 1.33) * std::cos(30 * kPi / 180);
  for (auto m : {CausticsMethod::kLevelMap, CausticsMethod::kUniform, CausticsMethod::kVolumetric, CausticsMethod::kNone}) {
    IrradianceRequest q{"floor", -2, -2, 2, 2, 64, 64, 0.0f, {}};
    q.caustics.method = m;
    const auto img = irradiance(*r, q);
    double worst = 0;
    for (std::size_t i = 0; i < img.rgb.size(); ++i) worst = std::max(worst, std::fabs(img.rgb[i] / expected - 1));
    EXPECT_LT(worst, 0.01) << runtime::to_string(m) << ": worst relative error " << worst;
  }
}

// Photon splatting (Mihalik 2008 ch. 8): each photon carries E0 cos T of its
// water patch, so the mean is the flat-water value; the spread per pixel is
// the photon grid against the caustics texels (filtered splats), and
// shrinks with more photons.
TEST_F(Caustics, SplatFlatPoolMeanAndSpread) {
  auto r = renderer(scene("flat_pool"));
  const double expected = fresnel_t(std::cos(30 * kPi / 180), 1.33) * std::cos(30 * kPi / 180);
  // Measured 1.1 % and 0.11 % with the smooth filter (the tent's were
  // about 4 % and 0.3 %).
  for (auto [photons, spread] : {std::pair{1024u, 0.02}, std::pair{2048u, 0.003}}) {
    IrradianceRequest q{"floor", -2, -2, 2, 2, 64, 64, 0.0f, {}};
    q.caustics.method = CausticsMethod::kSplat;
    q.caustics.photons = photons;
    const auto img = irradiance(*r, q);
    double sum = 0, worst = 0;
    for (float v : img.rgb) {
      sum += v;
      worst = std::max(worst, std::fabs(v / expected - 1));
    }
    std::printf("[splat] %u photons: mean %.5f of the exact value, worst pixel %.4f off\n", photons, sum / img.rgb.size() / expected, worst);
    EXPECT_NEAR(sum / img.rgb.size() / expected, 1.0, 0.005) << photons << " photons";
    EXPECT_LT(worst, spread) << photons << " photons";
  }
}

TEST_F(Caustics, AbsorptionScalesByExpMinusKd) {
  auto j = scene("flat_pool");
  j["water"]["absorption"] = {0.1, 0.3, 0.6};
  auto r = renderer(j);
  const double th = 30 * kPi / 180, cos_t = std::sqrt(1 - std::pow(std::sin(th) / 1.33, 2));
  const double d = 2.0 / cos_t;  // path length in water to the floor along the refracted ray
  const double base = fresnel_t(std::cos(th), 1.33) * std::cos(th);
  const auto img = irradiance(*r, IrradianceRequest{"floor", -1, -1, 1, 1, 16, 16, 0.0f, {}});
  const double k[3] = {0.1, 0.3, 0.6};
  for (std::size_t i = 0; i < img.rgb.size(); ++i) {
    EXPECT_NEAR(img.rgb[i] / (base * std::exp(-k[i % 3] * d)), 1.0, 0.01) << "channel " << i % 3;
  }
}

// 1-D ray trace of y = 2 + 0.1 sin(2 pi x), light straight down, floor y = 0,
// water of index n: where the map x0 -> X is folded (dX/dx0 = 0) within one
// wavelength.
std::vector<double> fold_lines(double n = 1.33) {
  auto land = [n](double x0) {
    const double slope = 0.1 * 2 * kPi * std::cos(2 * kPi * x0);
    const double nlen = std::sqrt(slope * slope + 1), nx = -slope / nlen, ny = 1 / nlen;
    const double eta = 1 / n, cos_i = ny, k = 1 - eta * eta * (1 - cos_i * cos_i);
    const double tx = (eta * cos_i - std::sqrt(k)) * nx, ty = -eta + (eta * cos_i - std::sqrt(k)) * ny;
    const double h = 2 + 0.1 * std::sin(2 * kPi * x0);
    return x0 + tx * h / -ty;
  };
  std::vector<double> folds;
  const int steps = 200000;
  double prev = land(1.0 / steps) - land(0.0);
  for (int i = 1; i < steps; ++i) {
    const double x0 = double(i) / steps;
    const double d = land(x0 + 1.0 / steps) - land(x0);
    if ((d > 0) != (prev > 0)) {
      double x = land(x0);
      x -= std::floor(x);
      folds.push_back(x);
    }
    prev = d;
  }
  std::sort(folds.begin(), folds.end());
  return folds;
}

// wavy_pool's floor along x in [0, 4] m (4 periods of the wave), 512
// texels of 7.8 mm over a strip 0.1 m wide: the mean of its 4 rows, per
// channel.
constexpr int kProfileTexels = 512;
constexpr double kProfileTexel = 4.0 / kProfileTexels;
std::array<std::vector<double>, 3> floor_profile(const metrics::Image& img) {
  std::array<std::vector<double>, 3> profile;
  for (auto& p : profile) p.assign(kProfileTexels, 0.0);
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < kProfileTexels; ++col) {
      for (int c = 0; c < 3; ++c) profile[c][col] += img.rgb[3 * (std::size_t(row) * kProfileTexels + col) + c] / 4.0;
    }
  }
  return profile;
}

// The caustics map spans the strip's window (4 m by 0.1 m plus a margin)
// in a square of texels: 1024^2 puts 4 mm in a texel along x, half a
// profile texel; 2048^2 found the same fold positions (to 0.01 texel) and
// means (to 1e-5) at four times the fill.
IrradianceRequest floor_strip() {
  IrradianceRequest q{"floor", 0, -0.05f, 4, 0.05f, kProfileTexels, 4, 0.0f, {}};
  q.caustics.map_size = 1024;
  return q;
}

double mean_of(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m += x / static_cast<double>(v.size());
  return m;
}

// In each of the 4 periods, the positions (within the period) of the two
// brightest local maxima, sorted.
std::vector<std::array<double, 2>> brightest_pairs(const std::vector<double>& profile) {
  std::vector<std::array<double, 2>> out;
  for (int wave = 0; wave < 4; ++wave) {
    std::vector<std::pair<double, double>> peaks;  // value, x
    for (int c = wave * 128 + 1; c < wave * 128 + 127; ++c) {
      if (profile[c] > profile[c - 1] && profile[c] >= profile[c + 1]) peaks.push_back({profile[c], (c + 0.5) * kProfileTexel});
    }
    std::sort(peaks.rbegin(), peaks.rend());
    if (peaks.size() < 2) return {};
    std::array<double, 2> xs{peaks[0].second - wave, peaks[1].second - wave};
    std::sort(xs.begin(), xs.end());
    out.push_back(xs);
  }
  return out;
}

TEST_F(Caustics, WavyPoolConservesEnergyAndFoldsWhereRaysCross) {
  auto r = renderer(scene("wavy_pool"));
  const auto profile = floor_profile(irradiance(*r, floor_strip()))[0];
  const double mean = mean_of(profile);
  const double flat = fresnel_t(1.0, 1.33);
  EXPECT_NEAR(mean / flat, 1.0, 0.02) << "mean E/E0 over 4 wavelengths " << mean << ", flat water " << flat;

  const auto folds = fold_lines();
  ASSERT_EQ(folds.size(), 2u);
  EXPECT_NEAR(folds[0], 0.146, 0.002);
  EXPECT_NEAR(folds[1], 0.354, 0.002);
  // In each wavelength the two brightest local maxima sit on the folds.
  const auto pairs = brightest_pairs(profile);
  ASSERT_EQ(pairs.size(), 4u);
  for (int wave = 0; wave < 4; ++wave) {
    EXPECT_NEAR(pairs[wave][0], folds[0], 2 * kProfileTexel) << "wave " << wave;
    EXPECT_NEAR(pairs[wave][1], folds[1], 2 * kProfileTexel) << "wave " << wave;
  }
}

// Dispersion in the level-map water family. wavy_pool's water
// with dispersion 3 (V_d 6.7), RGB from 4 bins (430, 530, 630, 730 nm;
// n 1.3951 .. 1.3036):
// - each bin's monochromatic image puts its fold lines where the 1-D trace
//   with that wavelength's index does (tolerance 2 texels as above); the
//   folds of 430 and 730 nm lie 5.2 cm, 6.7 texels, apart, and each image
//   is farther than 2 texels from the other's;
// - the RGB image is the spectral integral: each channel is the sum of the
//   bins' monochromatic images times the bins' weights (to float rounding:
//   the floor faces V, so the mean direction the include takes is exact),
//   and each channel's mean is the bins' Fresnel transmittances so
//   weighted (energy per channel, 2 % as above);
// - one wavelength traced is bit-identical to water without dispersion.
// Cost: the pool rendered once per wavelength bin, once in RGB and once
// without dispersion, each with 1024^2 caustics maps (floor_strip).
TEST_F(Caustics, DispersiveWaterFoldsPerWavelengthAndAddsUpInRgb) {
  constexpr float kDispersion = 3.0f;
  constexpr std::uint32_t kBins = 4;
  auto j = scene("wavy_pool");
  j["water"]["dispersion"] = kDispersion;
  auto r = renderer(j);
  const float n_d = j["water"].value("ior", 1.33f);
  const auto bins = wavelength_samples(kBins);
  std::array<std::vector<double>, 3> sum;
  for (auto& s : sum) s.assign(kProfileTexels, 0.0);
  std::array<double, 3> expected_mean{};
  std::vector<std::vector<std::array<double, 2>>> pairs;
  for (const WavelengthSample& w : bins) {
    IrradianceRequest q = floor_strip();
    q.caustics.wavelength_nm = w.nm;
    const auto p = floor_profile(irradiance(*r, q))[0];
    const double n = index_at(n_d, kDispersion, w.nm);
    const auto folds = fold_lines(n);
    ASSERT_EQ(folds.size(), 2u);
    pairs.push_back(brightest_pairs(p));
    ASSERT_EQ(pairs.back().size(), 4u) << w.nm << " nm";
    for (int wave = 0; wave < 4; ++wave) {
      for (int f = 0; f < 2; ++f) EXPECT_NEAR(pairs.back()[wave][f], folds[f], 2 * kProfileTexel) << w.nm << " nm, n " << n << ", wave " << wave;
    }
    for (int c = 0; c < 3; ++c) {
      for (int i = 0; i < kProfileTexels; ++i) sum[c][i] += w.rgb[c] * p[i];
      expected_mean[c] += w.rgb[c] * fresnel_t(1.0, n);
    }
  }
  const auto blue = fold_lines(index_at(n_d, kDispersion, bins.front().nm)), red = fold_lines(index_at(n_d, kDispersion, bins.back().nm));
  for (int wave = 0; wave < 4; ++wave) {
    for (int f = 0; f < 2; ++f) {
      EXPECT_GT(std::fabs(pairs.front()[wave][f] - red[f]), 2 * kProfileTexel) << "430 nm image against 730 nm's folds, wave " << wave;
      EXPECT_GT(std::fabs(pairs.back()[wave][f] - blue[f]), 2 * kProfileTexel) << "730 nm image against 430 nm's folds, wave " << wave;
    }
  }

  IrradianceRequest q = floor_strip();
  q.caustics.wavelengths = kBins;
  const auto rgb = floor_profile(irradiance(*r, q));
  for (int c = 0; c < 3; ++c) {
    const double scale = mean_of(rgb[c]);
    double worst = 0;
    for (int i = 0; i < kProfileTexels; ++i) worst = std::max(worst, std::fabs(rgb[c][i] - sum[c][i]) / scale);
    EXPECT_LT(worst, 1e-4) << "channel " << c << ": RGB against the weighted monochromatic images";
    EXPECT_NEAR(scale / expected_mean[c], 1.0, 0.02) << "channel " << c;
  }

  IrradianceRequest one = floor_strip();
  one.caustics.wavelengths = 1;
  auto plain = renderer(scene("wavy_pool"));
  EXPECT_EQ(irradiance(*r, one).rgb, irradiance(*plain, one).rgb) << "one wavelength against water without dispersion";
}

// Moire in caustic lines: eq. 4-18 gives each water triangle
// one irradiance, so the caustics are a mosaic of the water grid (3 cm
// cells in thesis_sphere) that beats against the pixels. A patch of
// thesis_sphere's floor (1 m^2, no shadow), 256^2 pixels, caustics map
// 1024^2, against the same scene with a water grid 4x finer: the
// high-frequency content of the difference, mean |d - box3(d)| / mean E
// (the mosaic's edges), falls with the corners interpolated (water_smooth;
// measured 0.066 -> 0.054), the relative L1 falls by more than 15 %
// (measured 11.9 % -> 8.8 %), and the power stays within 0.5 %.
TEST_F(Caustics, SmoothCausticsRemoveTheWaterGridsMosaic) {
  auto coarse = renderer(scene("thesis_sphere"));
  nlohmann::json fine_scene = scene("thesis_sphere");
  fine_scene["water"]["grid"]["cells"] = {512, 512};
  auto fine = renderer(fine_scene);
  ASSERT_TRUE(coarse && fine);
  IrradianceRequest q{"floor", 0.9f, 0.9f, 1.9f, 1.9f, 256, 256, 0.7f, {}};
  q.pixel_samples = 2;
  q.caustics = runtime::default_caustics_options(coarse->scene());
  q.caustics.map_size = 1024;
  auto power = [](const metrics::Image& img) {
    double p = 0;
    for (std::size_t i = 1; i < img.rgb.size(); i += 3) p += img.rgb[i];
    return p;
  };
  q.caustics.water_smooth = false;
  const auto flat_img = irradiance(*coarse, q);
  q.caustics.water_smooth = true;
  const auto smooth_img = irradiance(*coarse, q);
  q.caustics.water_smooth = false;
  const auto truth = irradiance(*fine, q);
  const double p_flat = power(flat_img), p_smooth = power(smooth_img);
  const double hf_flat = high_frequency(flat_img, truth), hf_smooth = high_frequency(smooth_img, truth);
  const double l1_flat = metrics::relative_l1(flat_img, truth), l1_smooth = metrics::relative_l1(smooth_img, truth);
  std::cout << "mosaic: high frequency of the difference from the finer grid " << hf_flat << " -> " << hf_smooth << ", power "
            << p_flat << " -> " << p_smooth << ", L1 against the finer grid " << l1_flat << " -> " << l1_smooth << "\n";
  ::testing::Test::RecordProperty("hf_flat", std::to_string(hf_flat));
  ::testing::Test::RecordProperty("hf_smooth", std::to_string(hf_smooth));
  ::testing::Test::RecordProperty("l1_flat", std::to_string(l1_flat));
  ::testing::Test::RecordProperty("l1_smooth", std::to_string(l1_smooth));
  EXPECT_LT(hf_smooth, 0.9 * hf_flat);
  EXPECT_NEAR(p_smooth / p_flat, 1.0, 0.005);
  EXPECT_LT(l1_smooth, 0.85 * l1_flat);
}

// Every preset's caustics under waves without the water grid's seams
//: with few planes (fast: 4, and a water grid half as fine)
// each beam travels up to a window's half-width from its plane to the
// floor. Moved rigidly along its mean direction, neighbouring beams opened
// gaps and overlaps one texel wide along the water triangles' edges (a
// dark mesh). Following each vertex's own ray they tile at every depth. The
// statistic is the moire test's above: the high-frequency content of the difference
// from the same bake drawn with 64 planes (windows so thin that nothing
// travels), on a lit patch of the floor of thesis_teapot and thesis_sphere.
// (Not wavy_pool: its flat floor lies on a plane, so nothing travels and
// the difference is 0 with rigid beams too; it could not fail.)
// On thesis_teapot / thesis_sphere, rigid beams measured fast 0.0124 /
// 0.0149, balanced 0.0072 / 0.0080, accurate 0.0043 / 0.0045; following
// the vertices 0.0049 / 0.0087, 0.0048 / 0.0059, 0.0030 / 0.0034 (what is
// left lies on the fold lines, whose beams cross inside the windows, and
// is no mesh). Each preset's bound lies below both of its rigid values.
// One test per preset (fast, balanced, accurate) and scene, so that they
// run side by side: each bakes one scene and draws two 192^2 images.
struct SeamPatch {
  const char* scene;
  float x0, z0, x1, z1;
};
constexpr SeamPatch kSeamPatches[] = {{"thesis_teapot", -1.6f, 0.6f, -0.6f, 1.6f}, {"thesis_sphere", 0.7f, -1.7f, 1.7f, -0.7f}};
class CausticsPerPreset : public Caustics, public ::testing::WithParamInterface<std::tuple<std::size_t, std::size_t>> {};

// Cost: the preset's planes and 64 at 192^2 with two samples a pixel; the
// bounds were measured at this size, so the images stay as they are.
TEST_P(CausticsPerPreset, EveryPresetsCausticsUnderWavesHaveNoSeams) {
  const std::map<std::string, double> bound{{"fast", 0.011}, {"balanced", 0.0066}, {"accurate", 0.0039}};
  const auto [preset_index, patch_index] = GetParam();
  ASSERT_LT(preset_index, bake::presets().size());
  const bake::Preset& preset = bake::presets()[preset_index];
  const SeamPatch& patch = kSeamPatches[patch_index];
  auto r = renderer(scene(patch.scene), preset.options);
  ASSERT_TRUE(r);
  IrradianceRequest q{"floor", patch.x0, patch.z0, patch.x1, patch.z1, 192, 192, 1.0f, {}};
  q.pixel_samples = 2;
  q.caustics = runtime::default_caustics_options(r->scene());
  const auto img = irradiance(*r, q);
  const std::uint32_t planes = q.caustics.planes.value_or(0);
  q.caustics.planes = 64;
  const auto thin = irradiance(*r, q);
  const double hf = high_frequency(img, thin);
  std::printf("%s, %s (%s planes): high frequency of the difference from 64 planes %.4f, L1 %.4f\n", patch.scene, preset.name,
              planes ? std::to_string(planes).c_str() : "the baked", hf, metrics::relative_l1(img, thin));
  EXPECT_LT(hf, bound.at(preset.name));
}

INSTANTIATE_TEST_SUITE_P(Presets, CausticsPerPreset,
                         ::testing::Combine(::testing::Range<std::size_t>(0, 3),
                                            ::testing::Range<std::size_t>(0, std::size(kSeamPatches))),
                         [](const ::testing::TestParamInfo<std::tuple<std::size_t, std::size_t>>& info) {
                           return std::string(bake::presets()[std::get<0>(info.param)].name) + "_" +
                                  kSeamPatches[std::get<1>(info.param)].scene;
                         });

TEST_F(Caustics, SeveralLightsAddUp) {
  auto both = scene("flat_pool");
  both["water"]["waves"] = {{{"amplitude", 0.05}, {"wavelength", 0.9}, {"direction", {1, 0.4}}}};
  both["lights"].push_back({{"type", "directional"}, {"direction", {0.0, -0.9, 0.4}}, {"irradiance", 0.7}});
  auto first = both, second = both;
  first["lights"].erase(1);
  second["lights"].erase(0);
  const IrradianceRequest q{"floor", -1.5, -1.5, 1.5, 1.5, 96, 96, 0.0f, {}};
  const auto a = irradiance(*renderer(first), q);
  auto b = irradiance(*renderer(second), q);
  const auto ab = irradiance(*renderer(both), q);
  // Normalisation: each image divides by its first directional light's E0.
  for (float& v : b.rgb) v *= 0.7f;
  double worst = 0, peak = 0;
  for (std::size_t i = 0; i < ab.rgb.size(); ++i) {
    worst = std::max(worst, double(std::fabs(ab.rgb[i] - (a.rgb[i] + b.rgb[i]))));
    peak = std::max(peak, double(ab.rgb[i]));
  }
  EXPECT_LT(worst, 1e-4 * peak) << "sum of single-light images differs by " << worst;
}

TEST_F(Caustics, MethodsAgreeAndSmartDrawsFewerPlanes) {
  auto r = renderer(scene("thesis_sphere"));
  CausticsOptions co;
  co.map_size = 256;
  co.planes = 16;
  std::map<CausticsMethod, metrics::Image> images;
  std::map<CausticsMethod, std::uint64_t> planes;
  for (auto m : {CausticsMethod::kLevelMap, CausticsMethod::kUniform, CausticsMethod::kVolumetric}) {
    co.method = m;
    images[m] = beauty(*r, co, 160, 120, 0.7f);
    planes[m] = r->caustics_stats(true).planes_drawn;
  }
  const double smart_vs_uniform = metrics::average_luv_difference(images[CausticsMethod::kLevelMap], images[CausticsMethod::kUniform]);
  const double level_vs_volumetric = metrics::average_luv_difference(images[CausticsMethod::kUniform], images[CausticsMethod::kVolumetric]);
  EXPECT_LT(smart_vs_uniform, 0.5);
  EXPECT_LT(level_vs_volumetric, 0.5);
  EXPECT_LT(planes[CausticsMethod::kLevelMap], planes[CausticsMethod::kUniform]);
  ::testing::Test::RecordProperty("eq_2_9_smart_vs_uniform", std::to_string(smart_vs_uniform));
  ::testing::Test::RecordProperty("eq_2_9_levelmap_vs_volumetric", std::to_string(level_vs_volumetric));
  // Caustics are present: the level map differs from flat-water lighting.
  co.method = CausticsMethod::kNone;
  const auto none = beauty(*r, co, 160, 120, 0.7f);
  EXPECT_GT(metrics::average_luv_difference(images[CausticsMethod::kLevelMap], none), 1.0);
}

TEST_F(Caustics, CullingChangesNothing) {
  auto r = renderer(scene("thesis_sphere"));
  CausticsOptions co;
  co.map_size = 256;
  co.planes = 12;
  const auto culled = beauty(*r, co, 128, 96, 1.3f);
  const auto stats_culled = r->caustics_stats(true);
  co.cull = false;
  const auto all = beauty(*r, co, 128, 96, 1.3f);
  const auto stats_all = r->caustics_stats(true);
  EXPECT_LT(metrics::average_luv_difference(culled, all), 0.01);
  EXPECT_LT(stats_culled.volumes_drawn, stats_all.volumes_drawn / 4) << "culling should drop most pairs";
}

}  // namespace
}  // namespace caustix

namespace caustix {
namespace {

TEST_F(Caustics, MovingTheLightReDerivesTheLevelMapOnTheGpu) {
  auto r = renderer(scene("flat_pool"));
  for (double deg : {45.0, 10.0, 60.0, 0.0}) {  // 0: the flat floor's frame a few micrometres tall
    Light sun = r->scene().lights[0];
    sun.direction = {static_cast<float>(std::sin(deg * kPi / 180)), static_cast<float>(-std::cos(deg * kPi / 180)), 0.0f};
    ASSERT_TRUE(r->set_light(0, sun).ok());
    const double expected = fresnel_t(std::cos(deg * kPi / 180), 1.33) * std::cos(deg * kPi / 180);
    const auto img = irradiance(*r, IrradianceRequest{"floor", -1.5, -1.5, 1.5, 1.5, 48, 48, 0.0f, {}});
    double worst = 0;
    for (float v : img.rgb) worst = std::max(worst, std::fabs(v / expected - 1));
    EXPECT_LT(worst, 0.01) << deg << " degrees: worst relative error " << worst;
  }
}

}  // namespace
}  // namespace caustix

namespace caustix {
namespace {

TEST_F(Caustics, MovingAnObjectReDerivesItsLevelMap) {
  // A floor tilted by 20 degrees about z (a ramp) under flat water, light
  // straight down: E/E0 = T(0) cos(20 deg) on it. Then moved flat.
  auto j = scene("flat_pool");
  j["lights"][0]["direction"] = {0, -1, 0};
  j["objects"][0]["transform"] = {{"rotate_deg", {0, 0, 20}}, {"scale", {8, 1, 8}}};
  auto r = renderer(j);
  const double t0 = fresnel_t(1.0, 1.33);
  auto check = [&](double expected, const char* what) {
    const auto img = irradiance(*r, IrradianceRequest{"floor", -1, -1, 1, 1, 32, 32, 0.0f, {}});
    double worst = 0;
    for (float v : img.rgb) worst = std::max(worst, std::fabs(v / expected - 1));
    EXPECT_LT(worst, 0.01) << what << ": worst relative error " << worst;
  };
  check(t0 * std::cos(20 * kPi / 180), "ramp");
  Mat4f flat{8, 0, 0, 0, 0, 1, 0, 0, 0, 0, 8, 0, 0, 0.3f, 0, 1};
  ASSERT_TRUE(r->set_object_transform(0, flat).ok());
  check(t0, "flat after moving");
  EXPECT_FALSE(r->set_object_transform(0, Mat4f{}).ok()) << "a singular transform is refused";
}

}  // namespace
}  // namespace caustix
