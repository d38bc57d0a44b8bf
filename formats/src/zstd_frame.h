#pragma once
// One zstd frame per map or table payload (LMAP, LTTB): compression at a
// fixed level, and decompression that trusts nothing in the frame — the
// declared content size must be exactly the size the chunk's own fields
// imply, and the output must fill it.

#include <zstd.h>

#include <string>
#include <vector>

#include "bytes.h"
#include "chunk_decoder.h"

namespace caustix::cxb::detail {

inline std::vector<std::uint8_t> zstd_compress(const std::vector<std::uint8_t>& raw, int level) {
  std::vector<std::uint8_t> packed(ZSTD_compressBound(raw.size()));
  const std::size_t n = ZSTD_compress(packed.data(), packed.size(), raw.data(), raw.size(), level);
  packed.resize(ZSTD_isError(n) ? 0 : n);  // cannot fail into a compressBound buffer
  return packed;
}

// Writes `raw` compressed as one zstd frame, preceded by its u32 size (the
// "data size" + "data" fields of LMAP and LTTB).
inline void write_zstd_frame(ByteWriter& w, const std::vector<std::uint8_t>& raw, int level) {
  const std::vector<std::uint8_t> packed = zstd_compress(raw, level);
  w.u32(static_cast<std::uint32_t>(packed.size()));
  w.raw(packed.data(), packed.size());
}

// Decompresses `packed` into exactly `raw_size` bytes. `what` names the
// data in errors ("map data"); `expected` says what it should hold.
inline bool zstd_decompress_exact(ChunkDecoder& d, std::span<const std::uint8_t> packed, std::size_t raw_size,
                                  const std::string& what, const std::string& expected, std::vector<std::uint8_t>& raw) {
  if (ZSTD_getFrameContentSize(packed.data(), packed.size()) != raw_size) {
    return d.fail(what + " does not hold " + expected);
  }
  raw.resize(raw_size);
  const std::size_t got = ZSTD_decompress(raw.data(), raw.size(), packed.data(), packed.size());
  if (ZSTD_isError(got) || got != raw_size) {
    return d.fail(what + " does not decompress: " + (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "short"));
  }
  return true;
}

}  // namespace caustix::cxb::detail
