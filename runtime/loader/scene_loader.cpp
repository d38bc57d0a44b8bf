#include "caustix/runtime/scene_loader.h"

#include "caustix/formats/file_io.h"
#include "caustix/formats/mesh_decode.h"

namespace caustix::runtime {

Result<RuntimeScene> load_scene(const std::uint8_t* data, std::size_t size) {
  auto container = cxb::read_container(data, size);
  if (!container) return container.error();
  auto decoded = decode_scene(*container);
  if (!decoded) return decoded.error();
  RuntimeScene out;
  out.desc = std::move(decoded->scene);
  out.level_maps = std::move(decoded->level_maps);
  out.boxes = std::move(decoded->boxes);
  out.meshes.reserve(out.desc.meshes.size());
  for (std::size_t i = 0; i < out.desc.meshes.size(); ++i) {
    auto mesh = decode_draco(decoded->draco_meshes[i], out.desc.meshes[i]);
    if (!mesh) return mesh.error();
    out.meshes.push_back(std::move(*mesh));
  }
  out.transport_tables = std::move(decoded->transport_tables);
  out.spectral_tables = std::move(decoded->spectral_tables);
  out.index_grids = std::move(decoded->index_grids);
  for (const LightTransportTable& t : out.transport_tables) {
    const Object& o = out.desc.objects[t.object];
    if (t.vertex_count != out.meshes[o.mesh_index].positions.size()) {
      return make_error(ErrorCode::kContainer, "light-transport table of '" + o.name + "' has " + std::to_string(t.vertex_count) +
                                                   " vertices, its decoded mesh " + std::to_string(out.meshes[o.mesh_index].positions.size()));
    }
  }
  return out;
}

Result<RuntimeScene> load_scene_file(const std::string& path) {
  auto bytes = read_file(path);
  if (!bytes) return bytes.error();
  auto scene = load_scene(bytes->data(), bytes->size());
  if (!scene) return Error{scene.error().code, path + ": " + scene.error().message};
  return scene;
}

}  // namespace caustix::runtime
