#include "open_scene.h"

#include <chrono>
#include <cstdio>
#include <vector>

#include "caustix/bake/console_progress.h"
#include "caustix/bake/presets.h"

namespace caustix::tools {

void add_open_options(CLI::App& app, OpenOptions& o) {
  app.add_option("scene", o.path,
                 "baked scene (.cxb), or a scene.json or glTF file (.gltf, .glb), baked first into a cache and reused "
                 "(docs/tools.md, \"Opening a scene or glTF file\")")
      ->required();
  std::vector<std::string> names;
  for (const auto& p : bake::presets()) names.emplace_back(p.name);
  app.add_option("--bake-preset", o.cache.preset,
                 "a scene.json or glTF file: bake it with this preset (as caustix-bake --preset; default: caustix-bake's "
                 "defaults)")
      ->check(CLI::IsMember(names));
  app.add_option("--cache", o.cache.dir,
                 "a scene.json or glTF file: the bake cache's directory (default: $CAUSTIX_CACHE_DIR, else "
                 "$XDG_CACHE_HOME/caustix, else ~/.cache/caustix)");
  app.add_flag_callback(
      "--no-default-light", [&o] { o.cache.default_light = false; },
      "a glTF file without lights stays dark, instead of being lit by the default rig (a sun over the camera's right "
      "shoulder and the daylight sky)");
}

Result<runtime::RuntimeScene> open_scene(const std::string& tool, const OpenOptions& o) {
  const std::string& path = o.path;
  if (bake::is_baked_path(path)) return runtime::load_scene_file(path);
  bake::ConsoleProgress progress(tool, o.quiet, o.verbose);
  const auto start = std::chrono::steady_clock::now();
  auto cached = bake::bake_cached(path, o.cache, progress.observer());
  progress.clear_line();
  if (!cached) return cached.error();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (cached->reused) {
    // Said again: a warning is about the scene, not about this bake.
    for (const std::string& w : cached->warnings) progress.warning(w);
    if (o.verbose && !o.quiet) std::fprintf(stderr, "%s: %s: baked before (%s)\n", tool.c_str(), path.c_str(), cached->cxb_path.c_str());
  } else if (!o.quiet) {
    std::fprintf(stderr, "%s: %s: baked in %.1f s into the cache (%s); the next open reuses it\n", tool.c_str(), path.c_str(),
                 seconds, cached->cxb_path.c_str());
  }
  return runtime::load_scene_file(cached->cxb_path);
}

}  // namespace caustix::tools
