// libFuzzer target: the mesh importer (bake::import_mesh) on arbitrary
// bytes -- OpenMesh's OBJ reader, CGAL's OFF, PLY and STL readers, the
// header and layout checks in front of them, the polygon triangulation and
// the validation behind them. The first input byte picks the file
// extension (its two low bits: .obj, .off, .ply, .stl); the rest is the
// file. Must never crash, hang, leak, read out of bounds or exhaust memory.
// Build: CC=clang-14 CXX=clang++-14 cmake -DCAUSTIX_PARTS=bake -DCAUSTIX_FUZZ=ON
// Seeds: tests/fuzz/corpus_mesh (the files of tests/data/meshes, each with
// its extension byte in front).

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "caustix/bake/mesh_import.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExt[4] = {".obj", ".off", ".ply", ".stl"};
  // The importer reads files (as the baker does): one per process, in
  // memory-backed /dev/shm where there is one.
  static const std::string base = (std::filesystem::is_directory("/dev/shm") ? std::string("/dev/shm")
                                                                              : std::filesystem::temp_directory_path().string()) +
                                  "/caustix_fuzz_mesh_" + std::to_string(getpid());
  const std::string path = base + kExt[data[0] & 3];
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    if (size > 1) std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
  } else {
    return 0;
  }
  auto m = caustix::bake::import_mesh(path);
  std::remove(path.c_str());
  if (m) {
    // Touch what the baker would: every index, position and normal.
    double sum = 0;
    for (const auto& t : m->mesh.triangles) {
      for (std::uint32_t i : t) sum += m->mesh.positions.at(i)[0] + m->mesh.normals.at(i)[1];
    }
    if (sum == 1234.5678) __builtin_trap();  // keeps `sum` alive
  }
  return 0;
}
