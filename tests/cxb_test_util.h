#pragma once
// Helpers for tests that edit .cxb bytes: patch a field, then re-seal the
// header and table checksums so that a later check is the one that fires.

#include <cstdint>
#include <cstring>
#include <vector>

#include "caustix/formats/container.h"

namespace caustix::test {

inline void put_u32(std::vector<std::uint8_t>& b, std::size_t off, std::uint32_t v) { std::memcpy(b.data() + off, &v, 4); }
inline void put_u64(std::vector<std::uint8_t>& b, std::size_t off, std::uint64_t v) { std::memcpy(b.data() + off, &v, 8); }
inline std::uint64_t get_u64(const std::vector<std::uint8_t>& b, std::size_t off) {
  std::uint64_t v;
  std::memcpy(&v, b.data() + off, 8);
  return v;
}
inline std::uint32_t get_u32(const std::vector<std::uint8_t>& b, std::size_t off) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + off, 4);
  return v;
}

// Offsets from formats/SPEC.md.
inline constexpr std::size_t kFileSizeOff = 16, kCountOff = 24, kTableSumOff = 32, kHeaderSumOff = 56;
inline std::size_t entry(std::size_t i) { return cxb::kHeaderSize + i * cxb::kChunkEntrySize; }

// Recomputes the table checksum (over `count` entries) and the header checksum.
inline void reseal(std::vector<std::uint8_t>& b) {
  const std::uint32_t count = get_u32(b, kCountOff);
  const std::size_t table_bytes = std::size_t{count} * cxb::kChunkEntrySize;
  if (cxb::kHeaderSize + table_bytes <= b.size()) {
    put_u64(b, kTableSumOff, cxb::checksum64(b.data() + cxb::kHeaderSize, table_bytes));
  }
  put_u64(b, kHeaderSumOff, cxb::checksum64(b.data(), kHeaderSumOff));
}

// Recomputes chunk i's payload checksum, then reseals.
inline void reseal_payload(std::vector<std::uint8_t>& b, std::size_t i) {
  const std::uint64_t off = get_u64(b, entry(i) + 8), size = get_u64(b, entry(i) + 16);
  put_u64(b, entry(i) + 24, cxb::checksum64(b.data() + off, size));
  reseal(b);
}

}  // namespace caustix::test
