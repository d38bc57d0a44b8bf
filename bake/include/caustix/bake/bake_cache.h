#pragma once
// In-process bakes for the tools that open a scene directly
// (caustix-render MODEL.glb, caustix-view scene.json): the .cxb that
// `caustix-bake SCENE [--preset P] [--no-default-light]` would write --
// the same bytes -- kept in a cache and reused while nothing it was baked
// from has changed.
//
// An entry's key is a hash (XXH3-128) of caustix's version, the options
// and the bytes of the file named; its manifest lists every file the bake
// read (the glTF's buffers and textures, scene.json's meshes) with a hash
// of each, and the bake's warnings. An entry is reused only when every
// listed file still hashes the same; otherwise the scene is baked again
// and the entry replaced. Entries are written atomically (the .cxb first,
// the manifest last), so a bake stopped half-way leaves no entry and two
// processes baking the same scene leave one. The cache holds nothing else:
// deleting its directory at any time only costs the next open a bake.

#include <string>
#include <vector>

#include "caustix/bake/bake.h"
#include "caustix/common/status.h"

namespace caustix::bake {

struct CacheRequest {
  std::string preset;         // "" : caustix-bake's defaults; else a preset's name (presets.h)
  bool default_light = true;  // BakeOptions::default_light
  std::string dir;            // "" : default_cache_dir()
};

struct CachedBake {
  std::string cxb_path;  // the entry's .cxb: load it with runtime::load_scene_file
  bool reused = false;   // true: no bake ran
  // The bake's warnings; when reused, the ones it said when it was baked.
  std::vector<std::string> warnings;
};

// $CAUSTIX_CACHE_DIR, else $XDG_CACHE_HOME/caustix, else
// $HOME/.cache/caustix, else caustix-cache in the system's temporary
// directory.
std::string default_cache_dir();

// True for a path the runtime loads as it is (.cxb), false for one to bake
// first (scene.json, .gltf, .glb: anything else).
bool is_baked_path(const std::string& path);

// The entry for `scene_path`, baked now (`observer` hears its progress and
// warnings; on reuse only the stored warnings) or reused. Errors: the
// bake's own (ErrorCode::kInput for the scene and its meshes), kUsage for
// an unknown preset, kOutput when the cache directory cannot be made or
// written.
Result<CachedBake> bake_cached(const std::string& scene_path, const CacheRequest& request, const BakeObserver& observer = {});

}  // namespace caustix::bake
