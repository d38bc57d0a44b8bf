// caustix-bake: scene.json + meshes -> one .cxb file. See --help and README.md
// for the exit codes.

#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "caustix/bake/bake.h"
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
  std::string scene_path, out_path, depfile, report_path;
  bool quiet = false, verbose = false;

  CLI::App app{"caustix-bake: bake scene.json and its meshes into one .cxb file"};
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 invalid or missing input (scene.json, mesh),\n"
      "            5 output could not be written. The output is written atomically: on failure\n"
      "            an existing file at OUT is left untouched and no partial file is created.");
  app.add_option("scene", scene_path, "scene description (scene.json)")->required();
  app.add_option("-o,--output", out_path, "output .cxb file")->required();
  app.add_option("--position-bits", opt.draco.position_bits,
                 "Draco quantisation of positions, bits per coordinate; error <= extent / 2^(bits+1)")
      ->check(CLI::Range(8, 30))->capture_default_str();
  app.add_option("--normal-bits", opt.draco.normal_bits, "Draco quantisation of normals, bits")
      ->check(CLI::Range(6, 30))->capture_default_str();
  app.add_option("--draco-speed", opt.draco.speed, "Draco speed: 0 smallest file .. 10 fastest")
      ->check(CLI::Range(0, 10))->capture_default_str();
  app.add_option("--depfile", depfile, "write a Make-style dependency file listing every input");
  app.add_option("--report", report_path, "write a JSON report of the bake");
  app.add_flag("-q,--quiet", quiet, "print errors only");
  app.add_flag("-v,--verbose", verbose, "print per-mesh statistics and timings");
  if (auto rc = cli::parse(app, "caustix-bake", argc, argv)) return *rc;

  auto result = bake::bake_scene(scene_path, opt);
  if (!result) {
    return cli::fail("caustix-bake", result.error());
  }
  if (!quiet) {
    for (const auto& w : result->warnings) std::cerr << "caustix-bake: warning: " << w << "\n";
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
    nlohmann::ordered_json j;
    j["output"] = out_path;
    j["bytes"] = result->cxb.size();
    j["options"] = {{"position_bits", opt.draco.position_bits},
                    {"normal_bits", opt.draco.normal_bits},
                    {"draco_speed", opt.draco.speed}};
    for (const auto& m : result->meshes) {
      j["meshes"].push_back({{"path", m.path}, {"vertices", m.vertices}, {"triangles", m.triangles},
                             {"raw_bytes", m.raw_bytes}, {"draco_bytes", m.draco_bytes},
                             {"max_position_error_m", m.max_position_error},
                             {"normals_from_file", m.normals_from_file}});
    }
    j["seconds"] = {{"import", result->seconds_import},
                    {"compress", result->seconds_compress},
                    {"write", result->seconds_write}};
    j["warnings"] = result->warnings;
    if (Status st = write_text(report_path, j.dump(2) + "\n"); !st) {
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
  if (verbose) {
    for (const auto& m : result->meshes) {
      std::printf("  %-40s %7u vertices %7u triangles  raw %8llu B  draco %7llu B  max error %.3g m%s\n",
                  m.path.c_str(), m.vertices, m.triangles, static_cast<unsigned long long>(m.raw_bytes),
                  static_cast<unsigned long long>(m.draco_bytes), m.max_position_error,
                  m.normals_from_file ? "" : "  (normals computed)");
    }
    std::printf("  time: import %.3f s, compress %.3f s, write %.3f s\n", result->seconds_import,
                result->seconds_compress, result->seconds_write);
  }
  if (!quiet) {
    std::printf("caustix-bake: wrote %s (%zu bytes; meshes %llu raw bytes -> %llu Draco bytes)\n",
                out_path.c_str(), result->cxb.size(), static_cast<unsigned long long>(raw),
                static_cast<unsigned long long>(draco));
  }
  return kExitOk;
}
