// caustix-reference: the independent photon tracer (tools/reference/reference.h).
// Exit codes: 0 ok, 2 usage, 3 scene or mesh invalid, 5 image not written.

#include <chrono>
#include <cstdio>

#include "caustix/common/cli.h"
#include "caustix/sample/image_output.h"
#include "caustix/formats/spectrum.h"
#include "reference.h"

int main(int argc, char** argv) {
  using namespace caustix;
  reference::Request q;
  std::string region = "-2,-2,2,2", size = "128", out_path;
  CLI::App app{"caustix-reference: irradiance images by photon tracing scene.json (independent of the .cxb)"};
  app.footer(
      "The image is the irradiance at the receiver's first surface seen from above over --region, divided by E0\n"
      "(as caustix-render --irradiance), estimated with a one-pixel box kernel from --batches independent seeded\n"
      "batches; the relative noise printed is the batches' standard error of the mean.\n"
      "Exit codes: 0 ok, 2 usage, 3 scene or mesh invalid, 5 image not written.");
  app.add_option("scene", q.scene_path, "scene description (scene.json)")->required();
  bool inscatter = false;
  reference::InscatterRequest iq;
  auto* irr = app.add_option("--irradiance", q.receiver, "receiver whose irradiance is imaged");
  auto* ins = app.add_flag("--inscatter", inscatter,
                           "image the single-scattered radiance of the scene's media instead (orthographic along -z; "
                           "--region is then x0,y0,x1,y1)");
  irr->excludes(ins);
  app.add_option("--grid", iq.grid, "--inscatter: voxels along the medium's longest side, for views through glass")
      ->check(CLI::Range(2, 512))->capture_default_str();
  app.add_option("--view-samples", iq.view_samples, "--inscatter: view rays per pixel axis through glass")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("-o,--output", out_path, "output image (.exr)")->required();
  app.add_option("--region", region, "world rectangle x0,z0,x1,z1 (--inscatter: x0,y0,x1,y1)")->capture_default_str();
  cli::add_size_option(app, "--size", size, "image size");
  app.add_option("--time", q.time, "animation time in seconds")->capture_default_str();
  app.add_option("--photons", q.photons, "photons per light")->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 40))->capture_default_str();
  app.add_option("--batches", q.batches, "independent batches (noise estimate; parallel)")->check(CLI::Range(1, 1024))->capture_default_str();
  app.add_option("--seed", q.seed, "random seed")->capture_default_str();
  app.add_option("--glass-crease", q.glass_crease_deg,
                 "transparent meshes: edges sharper than this (degrees) keep each face's own normal (as caustix-bake --glass-crease)")
      ->check(CLI::Range(0.0, 180.0))->capture_default_str();
  app.add_option("--wavelength", q.wavelength_nm,
                 "dispersion: every photon at this wavelength in nm, weight 1 (a monochromatic image); default: in a scene with "
                 "dispersion each photon draws its wavelength from 380-780 nm (the RGB image is the spectral integral)")
      ->check(CLI::Range(double{kMinWavelength}, double{kMaxWavelength}));
  if (auto rc = cli::parse(app, "caustix-reference", argc, argv)) return *rc;
  if (!inscatter && q.receiver.empty()) {
    return cli::fail("caustix-reference", make_error(ErrorCode::kUsage, "give --irradiance RECEIVER or --inscatter"));
  }
  if (std::sscanf(region.c_str(), "%lf,%lf,%lf,%lf", &q.x0, &q.z0, &q.x1, &q.z1) != 4) {
    return cli::fail("caustix-reference", make_error(ErrorCode::kUsage, "--region '" + region + "' is not four numbers"));
  }
  cli::parse_size(size, q.width, q.height);
  const auto t0 = std::chrono::steady_clock::now();
  if (inscatter) {
    iq.scene_path = q.scene_path;
    iq.x0 = q.x0;
    iq.y0 = q.z0;
    iq.x1 = q.x1;
    iq.y1 = q.z1;
    iq.width = q.width;
    iq.height = q.height;
    iq.photons = q.photons;
    iq.batches = q.batches;
    iq.seed = q.seed;
    iq.glass_crease_deg = q.glass_crease_deg;
    iq.time = q.time;
    iq.wavelength_nm = q.wavelength_nm;
    reference::InscatterStats stats;
    auto img = reference::trace_inscatter(iq, &stats);
    if (!img) return cli::fail("caustix-reference", img.error());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    char rect[160];
    std::snprintf(rect, sizeof rect, "%.9g,%.9g,%.9g,%.9g", iq.x0, iq.y0, iq.x1, iq.y1);
    if (Status st = sample::write_float_image(out_path, img->width, img->height, 3, img->rgb,
                                               {{"caustix:region", rect}, {"caustix:image", "inscatter"},
                                                {"caustix:e0", std::to_string(img->e0)}, {"caustix:method", "reference"},
                                                {"caustix:wavelength", iq.wavelength_nm > 0 ? std::to_string(iq.wavelength_nm) : "rgb"},
                                                {"caustix:relative_noise", std::to_string(img->relative_noise)}});
        !st) {
      return cli::fail("caustix-reference", st.error());
    }
    std::printf("caustix-reference: wrote %s (%dx%d in-scatter, %llu photons, relative noise %.3g, %.1f s)\n"
                "  power / E0 (luminance): into media %.6g, scattered %.6g, absorbed %.6g, leaving %.6g\n",
                out_path.c_str(), img->width, img->height, static_cast<unsigned long long>(img->photons),
                img->relative_noise, seconds, stats.power_in, stats.scattered, stats.absorbed, stats.leaving);
    return kExitOk;
  }
  auto img = reference::trace(q);
  if (!img) return cli::fail("caustix-reference", img.error());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  char rect[160];
  std::snprintf(rect, sizeof rect, "%.9g,%.9g,%.9g,%.9g", q.x0, q.z0, q.x1, q.z1);
  if (Status st = sample::write_float_image(out_path, img->width, img->height, 3, img->rgb,
                                             {{"caustix:region", rect}, {"caustix:receiver", q.receiver},
                                              {"caustix:e0", std::to_string(img->e0)}, {"caustix:method", "reference"},
                                              {"caustix:time", std::to_string(q.time)},
                                              {"caustix:wavelength", q.wavelength_nm > 0 ? std::to_string(q.wavelength_nm) : "rgb"},
                                              {"caustix:relative_noise", std::to_string(img->relative_noise)}});
      !st) {
    return cli::fail("caustix-reference", st.error());
  }
  std::printf("caustix-reference: wrote %s (%dx%d, %llu photons, %llu landed, relative noise %.3g, %.1f s)\n",
              out_path.c_str(), img->width, img->height, static_cast<unsigned long long>(img->photons),
              static_cast<unsigned long long>(img->photons_landed), img->relative_noise, seconds);
  return kExitOk;
}
