// libFuzzer target: the .cxb container reader and the scene decoder on
// arbitrary bytes. Must never crash, hang, leak or read out of bounds.
// Build: CC=clang-14 CXX=clang++-14 cmake -DCAUSTIX_FORMATS_ONLY=ON -DCAUSTIX_FUZZ=ON
//
// The first input byte picks a mode. 0: the rest is read as is. 1: the
// checksums are recomputed first, so that mutations get past them and
// exercise the structural checks and the scene decoder (which a checksum
// would otherwise shield from almost every mutation).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "caustix/formats/container.h"
#include "caustix/formats/scene.h"

namespace {

using namespace caustix::cxb;

std::uint64_t load64(const std::uint8_t* p) { std::uint64_t v; std::memcpy(&v, p, 8); return v; }
std::uint32_t load32(const std::uint8_t* p) { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
void store64(std::uint8_t* p, std::uint64_t v) { std::memcpy(p, &v, 8); }

void reseal(std::vector<std::uint8_t>& b) {
  if (b.size() < kHeaderSize) return;
  const std::size_t count = std::min<std::size_t>(load32(b.data() + 24), (b.size() - kHeaderSize) / kChunkEntrySize);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint8_t* e = b.data() + kHeaderSize + i * kChunkEntrySize;
    const std::uint64_t off = load64(e + 8), size = load64(e + 16);
    if (off <= b.size() && size <= b.size() - off) store64(e + 24, checksum64(b.data() + off, size));
  }
  if (load32(b.data() + 24) == count) {
    store64(b.data() + 32, checksum64(b.data() + kHeaderSize, count * kChunkEntrySize));
  }
  store64(b.data() + 56, checksum64(b.data(), 56));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  std::vector<std::uint8_t> bytes(data + 1, data + size);
  if (data[0] & 1) reseal(bytes);
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
