// libFuzzer target: the .cxb container reader and the scene decoder on
// arbitrary bytes. Must never crash, hang, leak or read out of bounds.
// Build: CC=clang-14 CXX=clang++-14 cmake -DCAUSTIX_FORMATS_ONLY=ON -DCAUSTIX_FUZZ=ON

#include <cstddef>
#include <cstdint>

#include "caustix/formats/container.h"
#include "caustix/formats/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto container = caustix::cxb::read_container(data, size);
  if (!container) return 0;
  auto scene = caustix::decode_scene(*container);
  if (scene) {
    // Touch everything the decoder handed out.
    std::size_t sum = 0;
    for (auto span : scene->draco_meshes) sum += span.empty() ? 0 : span.back();
    for (const auto& o : scene->scene.objects) sum += o.name.size() + o.mesh_index;
    (void)sum;
  }
  return 0;
}
