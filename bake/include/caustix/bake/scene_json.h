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
// extension): the glTF scene's objects, lights and camera. A glTF file
// without lights (viewers light such files with an environment) gets, with
// `default_light`, the default rig: a sun of E0 = 1 W/m^2 (default_sun())
// under which the renderers' analytic sky is daylight, said in a warning;
// without it the scene stays dark, also with a warning.
Result<SceneDocument> load_scene(const std::string& path, bool default_light = true);

// The default rig's sun for a scene seen by `camera` (the file's, or the
// automatic one's direction when it has none): 55 degrees high, from 40
// degrees to the right of the view's direction seen from above, so that
// what the camera sees is lit from the front and modelled by the shading.
Light default_sun(const std::optional<Camera>& camera);

Result<SceneDocument> load_scene_json(const std::string& path);
// As above for text already in memory; `path` names it in messages and
// anchors relative mesh paths.
Result<SceneDocument> parse_scene_json(const std::string& text, const std::string& path);

}  // namespace caustix::bake
