#pragma once
// What caustix-render and caustix-view open: a .cxb as it is, and a
// scene.json or glTF file (.gltf, .glb) through the bake cache
// (caustix/bake/bake_cache.h): baked in-process, with caustix-bake's
// progress and warnings, on the first open, and reused while nothing it
// was baked from has changed. Include only from tools (needs CLI11).

#include <string>

#include "caustix/bake/bake_cache.h"
#include "caustix/common/cli.h"
#include "caustix/runtime/scene_loader.h"

namespace caustix::tools {

struct OpenOptions {
  std::string path;  // the scene to open
  bake::CacheRequest cache;
  bool quiet = false, verbose = false;
};

// The required positional `scene`, then --bake-preset, --cache and
// --no-default-light.
void add_open_options(CLI::App& app, OpenOptions& options);

// options.path; `tool` prefixes what is said on stderr.
Result<runtime::RuntimeScene> open_scene(const std::string& tool, const OpenOptions& options);

}  // namespace caustix::tools
