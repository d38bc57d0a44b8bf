#pragma once
// Shared by the libFuzzer targets: the first input byte picks a mode. 0: the
// rest is read as is. 1: the checksums are recomputed first, so that
// mutations get past them and exercise the structural checks and the
// decoders behind them (which a checksum would otherwise shield from almost
// every mutation).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "caustix/formats/container.h"

namespace caustix::fuzz {

inline std::uint64_t load64(const std::uint8_t* p) { std::uint64_t v; std::memcpy(&v, p, 8); return v; }
inline std::uint32_t load32(const std::uint8_t* p) { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
inline void store64(std::uint8_t* p, std::uint64_t v) { std::memcpy(p, &v, 8); }

inline void reseal(std::vector<std::uint8_t>& b) {
  if (b.size() < cxb::kHeaderSize) return;
  const std::size_t count = std::min<std::size_t>(load32(b.data() + 24), (b.size() - cxb::kHeaderSize) / cxb::kChunkEntrySize);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint8_t* e = b.data() + cxb::kHeaderSize + i * cxb::kChunkEntrySize;
    const std::uint64_t off = load64(e + 8), size = load64(e + 16);
    if (off <= b.size() && size <= b.size() - off) store64(e + 24, cxb::checksum64(b.data() + off, size));
  }
  if (load32(b.data() + 24) == count) {
    store64(b.data() + 32, cxb::checksum64(b.data() + cxb::kHeaderSize, count * cxb::kChunkEntrySize));
  }
  store64(b.data() + 56, cxb::checksum64(b.data(), 56));
}

// The bytes after the mode byte, resealed where the mode asks for it.
inline std::vector<std::uint8_t> fuzz_input(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data + 1, data + size);
  if (data[0] & 1) reseal(bytes);
  return bytes;
}

}  // namespace caustix::fuzz
