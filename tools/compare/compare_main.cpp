// caustix-compare: error metrics between two images of the same size,
// typically irradiance images (caustix-render --irradiance, the reference).
// A is compared against B (the reference). Exit codes: 0 ok, 2 usage,
// 3 an image cannot be read, 4 the images do not match in size.

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>

#include "caustix/common/cli.h"
#include "caustix/metrics/error_split.h"
#include "caustix/metrics/image_metrics.h"
#include "caustix/sample/image_output.h"

namespace {

using namespace caustix;

Result<std::pair<metrics::Image, std::optional<std::array<double, 4>>>> load(const std::string& path) {
  auto img = sample::read_rgb_image(path);
  if (!img) return img.error();
  return std::pair{metrics::Image{img->width, img->height, std::move(img->rgb)}, img->region()};
}

}  // namespace

int main(int argc, char** argv) {
  std::string a_path, b_path, aux_path, map_path;
  bool as_json = false;
  CLI::App app{"caustix-compare: error metrics of image A against reference B"};
  app.footer(
      "Metrics: eq29 = Tipprasert 2006 eq. 2-9, the mean CIE L*u*v* difference (white Y = 1, i.e. E/E0 = 1);\n"
      "rel_l1 = sum|A-B|/sum|B| and rms of luminance; flux_ratio = sum A / sum B; peak = distance between\n"
      "the brightest pixels (pixels, and metres when the images carry caustix:region).\n"
      "--split: the error split by cause, each pixel in one class (silhouette, self-shadow, terminator,\n"
      "cast-shadow, fold, slope bins of |n_y|; metrics/include/caustix/metrics/error_split.h): per class\n"
      "pixels, rel_l1 and bias within it, and its share of the image's whole L1 error.\n"
      "Exit codes: 0 ok, 2 usage, 3 an image cannot be read, 4 the images differ in size.");
  app.add_option("a", a_path, "image to judge")->required();
  app.add_option("b", b_path, "reference image")->required();
  app.add_flag("--json", as_json, "machine-readable output");
  auto* split_option = app.add_option("--split", aux_path, "A's auxiliary image (caustix-render --aux): split the error by cause");
  app.add_option("--error-map", map_path, "with --split: write an EXR of A - B (R), |A - B| (G) and the class index (B)")
      ->needs(split_option);
  if (auto rc = cli::parse(app, "caustix-compare", argc, argv)) return *rc;
  auto a = load(a_path);
  if (!a) return cli::fail("caustix-compare", a.error());
  auto b = load(b_path);
  if (!b) return cli::fail("caustix-compare", b.error());
  // Whether x and y differ in size (said on stderr).
  auto differ = [](const std::string& x_path, const metrics::Image& x, const std::string& y_path, const metrics::Image& y) {
    if (x.width == y.width && x.height == y.height) return false;
    std::fprintf(stderr, "caustix-compare: error: %s is %dx%d but %s is %dx%d\n", x_path.c_str(), x.width, x.height,
                 y_path.c_str(), y.width, y.height);
    return true;
  };
  if (differ(a_path, a->first, b_path, b->first)) return kExitContainer;
  std::optional<metrics::ErrorSplit> split;
  if (!aux_path.empty()) {
    auto aux = load(aux_path);
    if (!aux) return cli::fail("caustix-compare", aux.error());
    if (differ(aux_path, aux->first, a_path, a->first)) return kExitContainer;
    split = metrics::split_error(a->first, b->first, aux->first);
    if (!map_path.empty()) {
      const std::size_t n = split->class_of.size();
      std::vector<float> map(3 * n);
      for (std::size_t i = 0; i < n; ++i) {
        const double d = metrics::luminance(a->first, i) - metrics::luminance(b->first, i);
        map[3 * i] = static_cast<float>(d);
        map[3 * i + 1] = static_cast<float>(std::fabs(d));
        map[3 * i + 2] = split->class_of[i];
      }
      if (Status st = sample::write_float_image(map_path, a->first.width, a->first.height, 3, map); !st) {
        return cli::fail("caustix-compare", st.error());
      }
    }
  }
  const metrics::Comparison c = metrics::compare(a->first, b->first, b->second);
  if (as_json) {
    nlohmann::ordered_json j{{"a", a_path}, {"b", b_path}, {"eq29", c.eq29}, {"rel_l1", c.rel_l1}, {"rms", c.rms},
                             {"flux_ratio", c.flux_ratio}, {"peak_error_px", c.peak_error_px}};
    if (c.peak_error_m) j["peak_error_m"] = *c.peak_error_m;
    j["peak_ratio"] = c.peak_ratio;
    if (c.focus_1cm) j["focus_1cm"] = *c.focus_1cm;
    if (c.focus_2cm) j["focus_2cm"] = *c.focus_2cm;
    if (split) {
      for (const auto& e : split->classes) {
        j["split"].push_back({{"class", e.name}, {"pixels", e.pixels}, {"rel_l1", e.rel_l1()}, {"bias", e.bias()},
                              {"share", split->share(e)}});
      }
    }
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("eq. 2-9 (mean CIE Luv difference): %.6g\nrelative L1: %.6g\nRMS: %.6g\nflux ratio: %.6g\n", c.eq29,
                c.rel_l1, c.rms, c.flux_ratio);
    std::printf("peak position error: %.3g px", c.peak_error_px);
    if (c.peak_error_m) std::printf(" (%.4g m)", *c.peak_error_m);
    std::printf("\nbrightest pixel, A over B: %.6g\n", c.peak_ratio);
    if (c.focus_1cm) std::printf("power within 1 cm of B's brightest pixel, A over B: %.6g\n", *c.focus_1cm);
    if (c.focus_2cm) std::printf("power within 2 cm of B's brightest pixel, A over B: %.6g\n", *c.focus_2cm);
    if (split) {
      std::printf("\n%-13s %8s %9s %9s %9s\n", "class", "pixels", "rel_l1", "bias", "share");
      for (const auto& e : split->classes) {
        if (e.pixels == 0) continue;
        std::printf("%-13s %8zu %9.4f %+9.4f %9.4f\n", e.name.c_str(), e.pixels, e.rel_l1(), e.bias(), split->share(e));
      }
    }
  }
  return kExitOk;
}
