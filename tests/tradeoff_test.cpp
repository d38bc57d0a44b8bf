// The speed/accuracy trade against the independent reference:
// the level map's error falls, within the reference's noise, as planes and
// map sizes grow; the presets are ordered, fast doing the least work and
// accurate having the smallest error.
//
// Work, not time, stands for speed here (times belong in the benchmarks,
// docs/tradeoff.md): the caustic primitives drawn and the GPU memory of the
// caustics pass, both deterministic, and what a frame's cost on llvmpipe is
// linear in (docs/caustics.md).

#include <gtest/gtest.h>

#include <cstdio>

#include "caustix/bake/bake.h"
#include "caustix/bake/presets.h"
#include "caustix/metrics/image_metrics.h"
#include "caustix/sample/renderer.h"
#include "bake_fixture.h"
#include "gl_fixture.h"
#include "reference.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

struct Outcome {
  double rel_l1 = 0;
  std::uint64_t primitives = 0, gpu_bytes = 0;
};

class Tradeoff : public test::GlTest {
 public:
  // A reference image of `scene` (16 batches: its noise estimate is the
  // batches' standard error).
  static reference::Image reference_image(const std::string& scene, const std::string& receiver,
                                          std::array<double, 4> region, int w, int h, std::uint64_t photons) {
    reference::Request q{test::kScenes + scene + ".json", receiver, region[0], region[1], region[2], region[3],
                         w, h, 0.0, photons, 16, 11};
    auto img = reference::trace(q);
    EXPECT_TRUE(img.ok()) << img.error().message;
    return img.ok() ? std::move(*img) : reference::Image{};
  }

  // Bake with `opt`, render the reference's view with `caustics` (or the
  // file's recorded defaults), compare.
  static Outcome run(const std::string& scene, const bake::BakeOptions& opt,
                     std::optional<runtime::CausticsOptions> caustics, const reference::Image& ref,
                     const std::string& receiver, std::array<double, 4> region) {
    auto loaded = test::bake_and_load(test::kScenes + scene + ".json", opt);
    if (!loaded) return {};
    auto r = sample::Renderer::create(*loaded);
    EXPECT_TRUE(r.ok()) << r.error().message;
    if (!r.ok()) return {};
    sample::IrradianceRequest q;
    q.receiver = receiver;
    q.x0 = static_cast<float>(region[0]);
    q.z0 = static_cast<float>(region[1]);
    q.x1 = static_cast<float>(region[2]);
    q.z1 = static_cast<float>(region[3]);
    q.width = ref.width;
    q.height = ref.height;
    q.caustics = caustics.value_or(runtime::default_caustics_options(loaded->desc));
    auto img = (*r)->render_irradiance(q);
    EXPECT_TRUE(img.ok()) << img.error().message;
    if (!img.ok()) return {};
    const runtime::CausticsStats cs = (*r)->caustics_stats(true);
    const metrics::Image a{img->width, img->height, img->rgb}, b{ref.width, ref.height, ref.rgb};
    return {metrics::relative_l1(a, b), cs.volumes_drawn, cs.gpu_bytes};
  }
};

// The references, traced once for the suite. wavy_pool's floor along a 4 m
// strip (1.6 cm pixels, as docs/tradeoff.md; 8 M photons: 8 % noise per
// pixel); the teapot from above (5 cm pixels; 4 M photons: 4 %).
constexpr std::array<double, 4> kStrip{0, -0.03125, 4, 0.03125};
constexpr std::array<double, 4> kTeapot{-1.25, -0.8, 1.35, 0.8};
const reference::Image& strip_reference() {
  static const reference::Image ref = Tradeoff::reference_image("wavy_pool", "floor", kStrip, 256, 4, 8'000'000);
  return ref;
}
const reference::Image& teapot_reference() {
  static const reference::Image ref = Tradeoff::reference_image("thesis_teapot", "teapot", kTeapot, 52, 32, 4'000'000);
  return ref;
}

// Comparing two images with the same noisy reference: where the reference's
// noise dominates, the L1 changes only to second order with the image, so
// settings whose L1s differ by less than a quarter of the noise are not
// told apart (measured: equal settings' L1s scatter by 0.1-0.15 of it).
double tell(const reference::Image& ref) { return 0.25 * ref.relative_noise; }

// On the teapot, whose error the water grid dominates (docs/tradeoff.md:
// 0.098 at half the grid, 0.0315 at the scene's, 0.0192 at twice).
// Cost: the teapot's reference trace and the three presets baked and
// rendered, the accurate one with its finest maps.
TEST_F(Tradeoff, PresetsAreOrderedInWorkAndError) {
  const reference::Image& ref = teapot_reference();
  ASSERT_FALSE(ref.rgb.empty());
  std::vector<Outcome> out;
  for (const bake::Preset& p : bake::presets()) {
    out.push_back(run("thesis_teapot", p.options, std::nullopt, ref, "teapot", kTeapot));  // the file's RNDR defaults
    std::printf("preset %-8s rel L1 %.4f, %llu primitives, %.1f MB (reference noise %.4f)\n", p.name,
                out.back().rel_l1, static_cast<unsigned long long>(out.back().primitives),
                static_cast<double>(out.back().gpu_bytes) / 1e6, ref.relative_noise);
  }
  ASSERT_EQ(out.size(), 3u);
  const Outcome &fast = out[0], &balanced = out[1], &accurate = out[2];
  EXPECT_LT(fast.primitives, balanced.primitives);
  EXPECT_LT(balanced.primitives, accurate.primitives);
  EXPECT_LT(fast.gpu_bytes, balanced.gpu_bytes);
  EXPECT_LT(balanced.gpu_bytes, accurate.gpu_bytes);
  EXPECT_LT(accurate.rel_l1, fast.rel_l1 - tell(ref));
  EXPECT_LT(balanced.rel_l1, fast.rel_l1 - tell(ref));
  EXPECT_LE(accurate.rel_l1, balanced.rel_l1 + tell(ref));
}

// Errors along one knob: never growing by more than the reference can tell;
// returns them in order.
template <class ErrorAt>
std::vector<double> sweep(const char* knob, const std::vector<std::uint32_t>& values, const reference::Image& r,
                          ErrorAt&& error_at) {
  std::vector<double> errors;
  for (std::uint32_t v : values) {
    errors.push_back(error_at(v));
    std::printf("%s %u: rel L1 %.4f (reference noise %.4f)\n", knob, v, errors.back(), r.relative_noise);
    if (errors.size() > 1) EXPECT_LE(errors.back(), errors[errors.size() - 2] + tell(r)) << knob << " " << v;
  }
  return errors;
}

// Cost (one of the slowest tests): the teapot's reference trace (ctest runs
// each test in a process of its own, so it is traced again here) and five
// bakes and renders, the ends of each knob's sweep and the position map's
// knee; the full sweeps are caustix-bench tradeoff's.
TEST_F(Tradeoff, LevelMapErrorFallsAsPlanesAndMapSizesGrow) {
  // Planes and the position map: the teapot, whose depth range the planes
  // must span (wavy_pool's flat floor needs one plane).
  const reference::Image& ref = teapot_reference();
  ASSERT_FALSE(ref.rgb.empty());
  auto teapot_with = [&](auto&& set) {
    return [&, set](std::uint32_t v) {
      bake::BakeOptions opt;
      set(opt, v);
      return run("thesis_teapot", opt, runtime::CausticsOptions{}, ref, "teapot", kTeapot).rel_l1;
    };
  };
  // The sweeps' ends and, for the position map, its knee; every value in
  // between is in `caustix-bench tradeoff` (docs/tradeoff.md).
  // Planes: at these pixel sizes the teapot's error is the same from 2 to
  // 32 planes within the noise (docs/tradeoff.md): it must not grow.
  sweep("planes", {2, 32}, ref, teapot_with([](bake::BakeOptions& o, std::uint32_t v) { o.level_maps.slicing.planes = v; }));
  // The position map: a coarse one misplaces the surface (measured 0.24 at
  // 4^2, 0.055 at 32^2, 0.037 at 512^2; noise 0.026).
  const auto pm = sweep("position map", {4, 32, 512}, ref,
                        teapot_with([](bake::BakeOptions& o, std::uint32_t v) { o.level_maps.map_size = v; }));
  EXPECT_LT(pm.back(), pm.front() - ref.relative_noise);
}

// The runtime's own knob, the caustics map's size, in a test of its own:
// it needs only the wavy_pool strip's reference, not the teapot's.
TEST_F(Tradeoff, CausticsMapErrorFallsAsItsSizeGrows) {
  // The caustics map: wavy_pool's fold lines (its floor spans 16 m, so the
  // map's texel is 16 m / S; measured 0.24 at 128^2, 0.079 at 512^2;
  // noise 0.037).
  const reference::Image& strip = strip_reference();
  const auto cm = sweep("caustics map", {128, 512}, strip, [&](std::uint32_t s) {
    runtime::CausticsOptions co;
    co.map_size = s;
    return run("wavy_pool", {}, co, strip, "floor", kStrip).rel_l1;
  });
  EXPECT_LT(cm.back(), cm.front() - strip.relative_noise);
}

}  // namespace
}  // namespace caustix
