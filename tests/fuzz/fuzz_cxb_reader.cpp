// libFuzzer target: the .cxb container reader and the scene decoder (every
// chunk: scene, level maps, boxes, light-transport tables) on arbitrary
// bytes. Must never crash, hang, leak or read out of bounds.
// Build: CC=clang-14 CXX=clang++-14 cmake -DCAUSTIX_PARTS=formats -DCAUSTIX_FUZZ=ON
// The first input byte picks a mode (reseal.h).

#include "caustix/formats/scene.h"
#include "fuzz/reseal.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::vector<std::uint8_t> bytes = caustix::fuzz::fuzz_input(data, size);
  auto container = caustix::cxb::read_container(bytes.data(), bytes.size());
  if (!container) return 0;
  auto scene = caustix::decode_scene(*container);
  if (scene) {
    // Touch everything the decoder handed out.
    std::size_t sum = 0;
    for (auto span : scene->draco_meshes) sum += span.empty() ? 0 : span.back();
    for (const auto& o : scene->scene.objects) sum += o.name.size() + o.mesh_index;
    if (sum == 0xFFFFFFFF) __builtin_trap();  // keeps `sum` alive
  }
  return 0;
}
