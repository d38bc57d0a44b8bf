// caustix-bake: scene.json + meshes (or a glTF 2.0 scene) -> one .cxb file. See --help and docs/tools.md
// for the exit codes.

#include <tbb/global_control.h>


#include <cmath>
#include <memory>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include "caustix/bake/bake.h"
#include "caustix/bake/console_progress.h"
#include "caustix/bake/presets.h"
#include "caustix/common/cli.h"
#include "caustix/formats/file_io.h"

namespace {

std::string make_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == ' ' || c == '#' || c == '\\') out += '\\';
    if (c == '$') out += '$';
    out += c;
  }
  return out;
}

caustix::Status write_text(const std::string& path, const std::string& text) {
  return caustix::write_file_atomically(path, std::vector<std::uint8_t>(text.begin(), text.end()));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace caustix;
  bake::BakeOptions opt;
  std::string scene_path, out_path, depfile, report_path, slicing = "smart", preset;
  double epsilon = 0;
  int threads = 0;
  bool quiet = false, verbose = false;
  auto& lm = opt.level_maps;

  CLI::App app{"caustix-bake: bake scene.json and its meshes, or a glTF 2.0 scene (.gltf, .glb), into one .cxb file"};
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 invalid or missing input (scene.json, glTF, mesh),\n"
      "            5 output could not be written, 7 stopped by --max-seconds or --max-memory.\n"
      "            The output is written atomically: on failure\n"
      "            an existing file at OUT is left untouched and no partial file is created.");
  app.add_option("scene", scene_path, "scene description: scene.json, or a glTF 2.0 file (.gltf, .glb)")->required();
  app.add_option("-o,--output", out_path, "output .cxb file")->required();
  std::string preset_names;
  std::vector<std::string> preset_list;
  for (const auto& p : bake::presets()) {
    preset_names += std::string(preset_names.empty() ? "" : "; ") + p.name + ": " + p.summary;
    preset_list.push_back(p.name);
  }
  app.add_option("--preset", preset,
                 "start from a preset (docs/tradeoff.md): " + preset_names +
                     "; also records its runtime defaults in the file. Options given explicitly win")
      ->check(CLI::IsMember(preset_list));
  app.add_option("--water-grid-scale", opt.water_grid_scale,
                 "multiply scene.json's water grid cells per axis (the runtime's caustics cost is linear in them)")
      ->check(CLI::Range(1.0 / 64, 64.0))->capture_default_str();
  app.add_option("--position-bits", opt.draco.position_bits,
                 "Draco quantisation of positions, bits per coordinate; error <= extent / 2^(bits+1)")
      ->check(CLI::Range(8, 30))->capture_default_str();
  app.add_option("--normal-bits", opt.draco.normal_bits, "Draco quantisation of normals, bits")
      ->check(CLI::Range(6, 30))->capture_default_str();
  app.add_option("--max-texture-size", opt.max_texture_size,
                 "albedo textures larger than this many texels a side are filtered down to fit")
      ->check(CLI::Range(1u, kMaxTextureSize))->capture_default_str();
  app.add_option("--draco-speed", opt.draco.speed, "Draco speed: 0 smallest file .. 10 fastest")
      ->check(CLI::Range(0, 10))->capture_default_str();
  app.add_option("--planes", lm.slicing.planes,
                 "uniform slicing: n pieces, n + 1 reference planes (eq. 4-6..4-9); also sets the default "
                 "epsilon h/(2n) of smart slicing")
      ->check(CLI::Range(1, 4096))->capture_default_str();
  app.add_option("--epsilon", epsilon,
                 "acceptance half-width in metres for smart slicing (eq. 4-22); default: h/(2n) per receiver")
      ->check(CLI::Range(1e-9, 1e9));
  app.add_option("--levels", lm.slicing.levels, "depth levels L of the depth profile (smart slicing, §4.7.2)")
      ->check(CLI::Range(1, 65536))->capture_default_str();
  app.add_option("--slicing", slicing, "plane set the runtime uses by default; both are stored")
      ->check(CLI::IsMember({"smart", "uniform"}))->capture_default_str();
  app.add_option("--map-size", lm.map_size, "position and diffuse map size S (S x S texels)")
      ->check(CLI::Range(1, 8192))->capture_default_str();
  app.add_option("--ltt-resolution", opt.transport.resolution,
                 "light-transport table: R x R incident directions per vertex of transparent objects (Iwasaki et al.)")
      ->check(CLI::Range(caustix::kMinTransportResolution, caustix::kMaxTransportResolution))->capture_default_str();
  app.add_option("--ltt-bounces", opt.transport.max_bounces,
                 "light-transport table: internal reflections followed inside glass (0 = the paper's refraction only)")
      ->check(CLI::Range(0u, caustix::kMaxTransportBounces))->capture_default_str();
  app.add_option("--ltt-bits", opt.transport.bits,
                 "light-transport table: significant bits kept per stored field (fewer: smaller file, coarser values)")
      ->check(CLI::Range(caustix::kMinTransportBits, caustix::kMaxTransportBits))->capture_default_str();
  app.add_option("--ltt-wavelengths", opt.transport.wavelengths,
                 "light-transport tables of dispersive glass: this many more, at wavelengths evenly over 380..780 nm with "
                 "both ends, for the runtime to interpolate between (0: caustics through the tables refract at n_d only; "
                 "docs/dispersion.md)")
      ->check([](const std::string& v) -> std::string {
        const int k = std::atoi(v.c_str());
        return (v == "0" || (k >= 2 && k <= static_cast<int>(caustix::kMaxTransportWavelengths))) ? ""
                                                                                                   : "must be 0 or 2.." + std::to_string(caustix::kMaxTransportWavelengths);
      })
      ->capture_default_str();
  bool no_switches = false;
  app.add_flag("--no-ltt-switches", no_switches,
               "light-transport tables: do not locate where their path class switches on flat faces (LTTW): a faster "
               "bake (a prism's tables: 0.6 times the time), and the runtime drops triangles torn between two classes "
               "instead of cutting them at the switch (docs/glass-tables.md)");
  std::string ltt_rays = "embree";
  app.add_option("--ltt-rays", ltt_rays,
                 "light-transport tables: what casts their rays: embree (fast, single precision) or cgal (exact "
                 "predicates, doubles: the tables of bakes before Embree)")
      ->check(CLI::IsMember({"embree", "cgal"}))->capture_default_str();
  app.add_option("--volume-res", opt.index_grid.resolution,
                 "scenes that scatter: index-grid voxels along each transparent mesh's longest side (Pfeuti)")
      ->check(CLI::Range(4u, 1024u))->capture_default_str();
  app.add_option("--volume-blur", opt.index_grid.blur, "scenes that scatter: Gaussian filter of the index grid, sigma in voxels")
      ->check(CLI::Range(0.0f, 8.0f))->capture_default_str();
  app.add_option("--octree-eps", opt.index_grid.epsilon,
                 "scenes that scatter: octree threshold on the index; regions varying less take one photon step")
      ->check(CLI::Range(0.0f, 10.0f))->capture_default_str();
  app.add_option("--glass-crease", opt.glass_refine.crease_deg,
                 "transparent meshes: edges whose faces meet at more than this angle (degrees) are sharp; their vertices "
                 "are split so that each face refracts with its own normal (bake/glass_refine.h)")
      ->check(CLI::Range(0.0, 180.0))->capture_default_str();
  app.add_option("--glass-edge", opt.glass_refine.max_edge,
                 "transparent meshes: split edges of flat triangles longer than this fraction of the mesh's bounding-box "
                 "diagonal (the table samples light transport at vertices; 0: no splitting)")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_option("--glass-turn", opt.glass_refine.max_turn_deg,
                 "transparent meshes: also split edges whose end normals turn by more than this (degrees) while longer "
                 "than --glass-edge / 4 of the diagonal: finer sampling of curved glass, a sharper focal spot (0: off)")
      ->check(CLI::Range(0.0, 180.0))->capture_default_str();
  bool no_default_light = false;
  app.add_flag("--no-default-light", no_default_light,
               "a glTF file without lights stays dark, instead of being lit by the default rig (a sun over the camera's "
               "right shoulder and the daylight sky)");
  bool no_share = false;
  app.add_flag("--no-share", no_share,
               "give every object its own mesh and light-transport tables even where they are identical (shared by "
               "default: the LTTR chunk, which older readers refuse)");
  app.add_option("--threads", threads, "worker threads, 0 = all cores (the output does not depend on it)")
      ->check(CLI::Range(0, 1024))->capture_default_str();
  app.add_option("--depfile", depfile, "write a Make-style dependency file listing every input");
  app.add_option("--report", report_path, "write a JSON report of the bake (also when it fails)");
  app.add_option("--max-seconds", opt.max_seconds,
                 "stop the bake, with exit code 7 and no output, once it has run this many seconds (0: no limit)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--max-memory", opt.max_memory_bytes,
                 "stop the bake, with exit code 7 and no output, once the process's peak memory would exceed this "
                 "(bytes, or with a unit: 512MB, 4GB; 0: no limit)")
      ->transform(CLI::AsSizeValue(false))->capture_default_str();
  app.add_flag("-q,--quiet", quiet, "print errors only");
  app.add_flag("-v,--verbose", verbose, "print per-mesh statistics and timings");
  if (auto rc = cli::parse(app, "caustix-bake", argc, argv)) return *rc;
  opt.share = !no_share;
  opt.default_light = !no_default_light;
  opt.transport.rays = ltt_rays == "cgal" ? caustix::bake::RayEngine::kCgal : caustix::bake::RayEngine::kEmbree;
  opt.transport.switches = !no_switches;

  if (!preset.empty()) {
    // The preset's values for every option not given on the command line.
    bake::apply_preset(*bake::find_preset(preset), opt, [&](std::string_view flag) { return app.count(std::string(flag)) != 0; });
  }
  if (epsilon > 0) lm.slicing.epsilon = epsilon;
  lm.slicing.slicing = slicing == "uniform" ? Slicing::kUniform : Slicing::kSmart;
  std::unique_ptr<tbb::global_control> thread_limit;
  if (threads > 0) {
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                         static_cast<std::size_t>(threads));
  }

  bake::ConsoleProgress progress("caustix-bake", quiet, verbose);
  opt.observer = progress.observer();
  auto result = bake::bake_scene(scene_path, opt);
  progress.clear_line();
  if (!result) {
    const int rc = cli::fail("caustix-bake", result.error());
    if (!report_path.empty()) {
      if (Status st = write_text(report_path, bake::failure_report_json(scene_path, result.error(), rc, progress.log())); !st) {
        std::cerr << "caustix-bake: error: " << st.error().message << "\n";
      }
    }
    return rc;
  }
  if (!quiet) {
    for (const auto& n : result->notes) std::cout << "caustix-bake: " << n << "\n";
  }
  if (Status st = write_file_atomically(out_path, result->cxb); !st) {
    return cli::fail("caustix-bake", st.error());
  }

  std::uint64_t raw = 0, draco = 0;
  for (const auto& m : result->meshes) {
    raw += m.raw_bytes;
    draco += m.draco_bytes;
  }
  if (!report_path.empty()) {
    if (Status st = write_text(report_path, bake::report_json(*result, opt)); !st) {
      return cli::fail("caustix-bake", st.error());
    }
  }
  if (!depfile.empty()) {
    std::string text = make_escape(out_path) + ":";
    for (const auto& in : result->inputs) text += " \\\n  " + make_escape(in);
    if (Status st = write_text(depfile, text + "\n"); !st) {
      return cli::fail("caustix-bake", st.error());
    }
  }
  if (verbose) std::fputs(bake::report_text(*result).c_str(), stdout);
  if (!quiet) {
    std::printf("caustix-bake: wrote %s (%zu bytes; meshes %llu raw bytes -> %llu Draco bytes; %zu level maps)\n",
                out_path.c_str(), result->cxb.size(), static_cast<unsigned long long>(raw),
                static_cast<unsigned long long>(draco), result->level_maps.maps.size());
  }
  return kExitOk;
}
