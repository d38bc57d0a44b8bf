#pragma once
// scene.json -> SceneDesc (schema: docs/scene-format.md).
//
// Contract: never crashes or throws on any input. Every error (kInput) has
// the form "FILE:LINE:COLUMN: /json/pointer: what was expected", pointing at
// the offending key or array element (or at the enclosing object for a
// missing field). Syntax errors, wrong types, missing fields, duplicate keys
// and out-of-range values are errors; unknown fields are warnings. A glTF
// file the scene names ("gltf", or a mesh "file.glb#Node") is read here;
// its errors keep their own "FILE: /pointer: ..." after the scene's place.

#include <optional>
#include <string>
#include <vector>

#include "caustix/bake/mesh_import.h"
#include "caustix/bake/texture_import.h"

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"

namespace caustix::bake {

struct SceneDocument {
  // meshes[i].source is the path as written; counts are filled by the baker.
  SceneDesc scene;
  // Resolved path of each mesh (relative to the scene file's directory);
  // for a mesh from a glTF file, the file's path and "#" what in it.
  std::vector<std::string> mesh_paths;
  // Meshes already read from glTF files (bake/gltf_import.h); empty for a
  // mesh file, which the baker imports (mesh_import.h).
  std::vector<std::optional<ImportedMesh>> imported;
  // The albedo textures' images, not yet read (the baker reads them):
  // AlbedoTexture::image indexes this list, scene.images is empty.
  std::vector<ImageSource> images;
  // Every file read so far (the scene, glTF files and their buffers).
  std::vector<std::string> inputs;
  std::vector<std::string> warnings;
};

// A scene from scene.json, or straight from a .gltf or .glb file (by its
// extension): the glTF scene's objects, lights and camera.
Result<SceneDocument> load_scene(const std::string& path);

Result<SceneDocument> load_scene_json(const std::string& path);
// As above for text already in memory; `path` names it in messages and
// anchors relative mesh paths.
Result<SceneDocument> parse_scene_json(const std::string& text, const std::string& path);

}  // namespace caustix::bake
