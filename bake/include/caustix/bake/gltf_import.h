#pragma once
// glTF 2.0 input (.gltf with embedded or external buffers, .glb), parsed by
// tinygltf; what maps to what is in docs/scene-format.md, "glTF scenes".
//
//  - Every mesh node of the file's default scene becomes one object per
//    triangle primitive, placed by the node hierarchy (matrices or TRS) and
//    named after its node.
//  - Materials: KHR_materials_transmission > 0 makes the object transparent
//    (index from KHR_materials_ior, absorption from KHR_materials_volume's
//    attenuation); metallic >= 0.9 with roughness <= 0.2 makes a mirror
//    (reflectance: the base colour); anything else is a receiver whose
//    albedo is the base colour, textured by its baseColorTexture (through
//    TEXCOORD_n, the sampler's wraps and KHR_texture_transform; the images
//    listed in GltfScene::images for the baker to read).
//  - KHR_lights_punctual's directional, point and spot lights (with their
//    cones), photometric units over 683 lm/W; the
//    first camera in node order.
//  - KHR_draco_mesh_compression and KHR_mesh_quantization are read.
//
// Contract: never crashes on any input. A file that cannot be read, that
// requires an extension caustix does not know, or whose indices, accessors,
// buffer views or node hierarchy are inconsistent is refused (kInput) with
// "FILE: /json/pointer: what is wrong" (tinygltf's own parse errors carry
// its message instead of a pointer). What the file holds and caustix does
// not use (other textures, animations, skins, morph targets, lines and points,
// unknown optional extensions) is named in a warning, never dropped
// silently.

#include <memory>
#include <string>
#include <vector>

#include "caustix/bake/mesh_import.h"
#include "caustix/bake/texture_import.h"
#include "caustix/common/status.h"
#include "caustix/formats/scene.h"

namespace caustix::bake {

struct GltfScene {
  // Objects, lights and camera; scene.meshes[i].source names the primitive
  // ("file.glb#/meshes/0/primitives/1") and meshes[i] holds it.
  SceneDesc scene;
  std::vector<ImportedMesh> meshes;
  // Receivers' textures' images, not yet read: every MapTexture::image
  // (for_each_texture) indexes this list (scene.images is empty).
  std::vector<ImageSource> images;
  std::vector<std::string> warnings;  // each starts with the file's path (load's own are in GltfFile::warnings())
};

class GltfFile {
 public:
  // Reads the file and its external buffers (at most 2 GiB each) and checks
  // its required extensions.
  static Result<GltfFile> load(const std::string& path);
  GltfFile(GltfFile&&) noexcept;
  GltfFile& operator=(GltfFile&&) noexcept;
  ~GltfFile();

  // The default scene (else the first; else every root node).
  Result<GltfScene> scene() const;
  // The mesh of the node named `node` (all its triangle primitives), in the
  // node's own frame: the caller places it. With `weld`, corners at the same
  // position become one vertex whatever their normals (exporters split
  // vertices at hard edges and UV seams, which would open a closed solid);
  // otherwise only corners with the same position and normal are merged.
  Result<ImportedMesh> node_mesh(const std::string& node, bool weld) const;

  const std::string& path() const;
  // The glTF file and its external buffers, for depfiles.
  const std::vector<std::string>& inputs() const;
  // What loading found (tinygltf's warnings, ignored extensions).
  const std::vector<std::string>& warnings() const;

 private:
  struct Impl;
  explicit GltfFile(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Whether a path names a glTF file (.gltf or .glb, in any case).
bool is_gltf_path(const std::string& path);

}  // namespace caustix::bake
