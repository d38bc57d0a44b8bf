// libFuzzer target: the glTF importer (bake::GltfFile) on arbitrary bytes --
// tinygltf's JSON and GLB parsing, then caustix's checks of every index,
// accessor and buffer-view range, the node hierarchy, the materials and
// lights, Draco-compressed primitives and the mesh validation behind them.
// The first input byte picks the extension (its low bit: .gltf, .glb); the
// rest is the file. Must never crash, hang, leak, read out of bounds or
// exhaust memory.
// Build: CC=clang-14 CXX=clang++-14 cmake -DCAUSTIX_PARTS=bake -DCAUSTIX_FUZZ=ON
// Seeds: tests/fuzz/corpus_gltf (files tests/gltf_fixture.h writes, each
// with its extension byte in front).

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "caustix/bake/gltf_import.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const std::string base = (std::filesystem::is_directory("/dev/shm") ? std::string("/dev/shm")
                                                                              : std::filesystem::temp_directory_path().string()) +
                                  "/caustix_fuzz_gltf_" + std::to_string(getpid());
  const std::string path = base + ((data[0] & 1) ? ".glb" : ".gltf");
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    if (size > 1) std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
  } else {
    return 0;
  }
  auto file = caustix::bake::GltfFile::load(path);
  std::remove(path.c_str());
  if (!file) return 0;
  double sum = 0;
  if (auto scene = file->scene()) {
    // Touch what the baker would: every object's transform, every vertex.
    for (const auto& o : scene->scene.objects) sum += o.transform[12];
    for (const auto& m : scene->meshes) {
      for (const auto& t : m.mesh.triangles) sum += m.mesh.positions[t[0]][0] + m.mesh.normals[t[2]][1];
    }
    for (const char* node : {"Glass", "Floor", "D", "Q"}) {
      if (auto m = file->node_mesh(node, true)) sum += m->mesh.positions.front()[1];
    }
  }
  return sum == 12345.678 ? 1 : 0;
}
