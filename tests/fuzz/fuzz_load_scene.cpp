// libFuzzer target: the runtime's whole loading path, runtime::load_scene —
// the container, the scene and map decoders, Draco decoding of every MESH
// chunk against its recorded counts and bounds, and the light-transport
// tables against their decoded meshes — on arbitrary bytes. Nothing here
// touches OpenGL. Must never crash, hang, leak or read out of bounds.
// The first input byte picks a mode (reseal.h).

#include "caustix/runtime/scene_loader.h"
#include "fuzz/reseal.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::vector<std::uint8_t> bytes = caustix::fuzz::fuzz_input(data, size);
  auto scene = caustix::runtime::load_scene(bytes.data(), bytes.size());
  if (scene) {
    // Touch what a renderer would: every index and every vertex.
    double sum = 0;
    for (const caustix::TriangleMesh& m : scene->meshes) {
      for (const auto& t : m.triangles) {
        for (std::uint32_t i : t) sum += m.positions.at(i)[0] + m.normals.at(i)[1];
      }
    }
    for (const auto& t : scene->transport_tables) {
      for (std::size_t e = 0; e < t.words.size() / 4; ++e) sum += t.load(e).transmittance;
    }
    if (sum == 1234.5678) __builtin_trap();  // keeps `sum` alive
  }
  return 0;
}
