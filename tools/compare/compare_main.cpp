// caustix-compare: error metrics between two images of the same size,
// typically irradiance images (caustix-render --irradiance, the reference).
// A is compared against B (the reference). Exit codes: 0 ok, 2 usage,
// 3 an image cannot be read, 4 the images do not match in size.

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>

#include "caustix/common/cli.h"
#include "caustix/metrics/image_metrics.h"

namespace {

using namespace caustix;

struct Loaded {
  metrics::Image image;
  std::optional<std::array<double, 4>> region;  // x0, z0, x1, z1 (caustix:region)
};

Result<Loaded> load(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return make_error(ErrorCode::kInput, path + ": cannot read: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.width > 65536 || spec.height > 65536) {
    return make_error(ErrorCode::kInput, path + ": unsupported image size");
  }
  Loaded out;
  out.image.width = spec.width;
  out.image.height = spec.height;
  std::vector<float> px(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) *
                        static_cast<std::size_t>(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data())) {
    return make_error(ErrorCode::kInput, path + ": read failed: " + in->geterror());
  }
  const std::string region = spec.get_string_attribute("caustix:region");
  std::array<double, 4> r{};
  if (!region.empty() && std::sscanf(region.c_str(), "%lf,%lf,%lf,%lf", &r[0], &r[1], &r[2], &r[3]) == 4) out.region = r;
  // Grey images stand for equal RGB; extra channels (alpha) are ignored.
  const auto c = static_cast<std::size_t>(spec.nchannels);
  out.image.rgb.reserve(px.size() / c * 3);
  for (std::size_t i = 0; i < px.size(); i += c) {
    for (std::size_t k = 0; k < 3; ++k) out.image.rgb.push_back(px[i + std::min(k, c - 1)]);
  }
  return out;
}

// Position of the brightest pixel (luminance), in pixels (column, row).
std::array<double, 2> peak(const metrics::Image& im) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < im.rgb.size() / 3; ++i) {
    if (metrics::luminance(im, i) > metrics::luminance(im, best)) best = i;
  }
  return {static_cast<double>(best % static_cast<std::size_t>(im.width)) + 0.5,
          static_cast<double>(best / static_cast<std::size_t>(im.width)) + 0.5};
}

}  // namespace

int main(int argc, char** argv) {
  std::string a_path, b_path;
  bool as_json = false;
  CLI::App app{"caustix-compare: error metrics of image A against reference B"};
  app.footer(
      "Metrics: eq29 = seed 000 eq. 2-9, the mean CIE L*u*v* difference (white Y = 1, i.e. E/E0 = 1);\n"
      "rel_l1 = sum|A-B|/sum|B| and rms of luminance; flux_ratio = sum A / sum B; peak = distance between\n"
      "the brightest pixels (pixels, and metres when the images carry caustix:region).\n"
      "Exit codes: 0 ok, 2 usage, 3 an image cannot be read, 4 the images differ in size.");
  app.add_option("a", a_path, "image to judge")->required();
  app.add_option("b", b_path, "reference image")->required();
  app.add_flag("--json", as_json, "machine-readable output");
  if (auto rc = cli::parse(app, "caustix-compare", argc, argv)) return *rc;
  auto a = load(a_path);
  if (!a) return cli::fail("caustix-compare", a.error());
  auto b = load(b_path);
  if (!b) return cli::fail("caustix-compare", b.error());
  if (a->image.width != b->image.width || a->image.height != b->image.height) {
    std::fprintf(stderr, "caustix-compare: error: %s is %dx%d but %s is %dx%d\n", a_path.c_str(), a->image.width,
                 a->image.height, b_path.c_str(), b->image.width, b->image.height);
    return kExitContainer;
  }
  const double eq29 = metrics::average_luv_difference(a->image, b->image);
  const double l1 = metrics::relative_l1(a->image, b->image);
  const double rms = metrics::rms(a->image, b->image);
  const double flux = metrics::flux_ratio(a->image, b->image);
  const auto pa = peak(a->image), pb = peak(b->image);
  const double peak_px = std::hypot(pa[0] - pb[0], pa[1] - pb[1]);
  std::optional<double> peak_m;
  if (b->region) {
    const auto& r = *b->region;
    const double sx = (r[2] - r[0]) / b->image.width, sz = (r[3] - r[1]) / b->image.height;
    peak_m = std::hypot((pa[0] - pb[0]) * sx, (pa[1] - pb[1]) * sz);
  }
  if (as_json) {
    nlohmann::ordered_json j{{"a", a_path}, {"b", b_path}, {"eq29", eq29}, {"rel_l1", l1}, {"rms", rms},
                             {"flux_ratio", flux}, {"peak_error_px", peak_px}};
    if (peak_m) j["peak_error_m"] = *peak_m;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("eq. 2-9 (mean CIE Luv difference): %.6g\nrelative L1: %.6g\nRMS: %.6g\nflux ratio: %.6g\n", eq29, l1,
                rms, flux);
    std::printf("peak position error: %.3g px", peak_px);
    if (peak_m) std::printf(" (%.4g m)", *peak_m);
    std::printf("\n");
  }
  return kExitOk;
}
