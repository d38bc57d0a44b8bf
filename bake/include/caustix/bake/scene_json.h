#pragma once
// scene.json -> SceneDesc (schema: docs/scene-format.md).
//
// Contract: never crashes or throws on any input. Every error (kInput) has
// the form "FILE:LINE:COLUMN: /json/pointer: what was expected", pointing at
// the offending key or array element (or at the enclosing object for a
// missing field). Syntax errors, wrong types, missing fields, duplicate keys
// and out-of-range values are errors; unknown fields are warnings.

#include <string>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"

namespace caustix::bake {

struct SceneDocument {
  // meshes[i].source is the path as written; counts are filled by the baker.
  SceneDesc scene;
  // Resolved path of each mesh (relative to the scene file's directory).
  std::vector<std::string> mesh_paths;
  std::vector<std::string> warnings;
};

Result<SceneDocument> load_scene_json(const std::string& path);
// As above for text already in memory; `path` names it in messages and
// anchors relative mesh paths.
Result<SceneDocument> parse_scene_json(const std::string& text, const std::string& path);

}  // namespace caustix::bake
