#pragma once
// Loading a .cxb for rendering: validate the container and the scene chunks
// (formats/), then decode every Draco mesh and check it against what the
// baker recorded. Safe on hostile files: any failure is an Error (kContainer)
// naming the file and the chunk; nothing is uploaded to GL here.

#include <string>
#include <vector>

#include "caustix/common/mesh.h"
#include "caustix/common/status.h"
#include "caustix/formats/index_grid.h"
#include "caustix/formats/scene.h"

namespace caustix::runtime {

struct RuntimeScene {
  SceneDesc desc;
  std::vector<TriangleMesh> meshes;  // desc.meshes[i] <-> meshes[i]
  std::vector<LevelMap> level_maps;  // at most one per (object, light)
  std::vector<ObjectBox> boxes;
  std::vector<LightTransportTable> transport_tables;  // one per solid transparent object that has its own (Object::tables_from)
  std::vector<LightTransportTable> spectral_tables;   // dispersive objects' tables at other wavelengths
  std::vector<IndexGrid> index_grids;  // one per transparent object, only in scenes that scatter
};

Result<RuntimeScene> load_scene(const std::uint8_t* data, std::size_t size);
Result<RuntimeScene> load_scene_file(const std::string& path);

}  // namespace caustix::runtime
