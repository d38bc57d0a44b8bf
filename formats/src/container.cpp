// The .cxb container reader and writer (layout: formats/SPEC.md).

#include "caustix/formats/container.h"

#include <xxhash.h>

#include <algorithm>
#include <cstring>
#include <sstream>

#include "bytes.h"

namespace caustix::cxb {
namespace {

using detail::load_u16;
using detail::load_u32;
using detail::load_u64;
using detail::store_u16;
using detail::store_u32;
using detail::store_u64;

// PNG-style magic: a high byte catches 7-bit transfers, CR LF catches
// newline translation, ^Z stops DOS `type`, the final LF catches LF -> CRLF.
constexpr std::uint8_t kMagic[8] = {0x89, 'C', 'X', 'B', '\r', '\n', 0x1A, '\n'};

// Header field offsets (SPEC.md, "Header").
constexpr std::size_t kOffVersion = 8;
constexpr std::size_t kOffHeaderSize = 10;
constexpr std::size_t kOffByteOrder = 12;
constexpr std::size_t kOffFileSize = 16;
constexpr std::size_t kOffChunkCount = 24;
constexpr std::size_t kOffFlags = 28;
constexpr std::size_t kOffTableChecksum = 32;
constexpr std::size_t kOffReserved = 40;  // 16 bytes, zero
constexpr std::size_t kOffHeaderChecksum = 56;

std::uint64_t align_up(std::uint64_t v) {
  return (v + (kPayloadAlignment - 1)) & ~std::uint64_t{kPayloadAlignment - 1};
}

std::string hex64(std::uint64_t v) {
  std::ostringstream s;
  s << "0x" << std::hex << v;
  return s.str();
}

struct Fail {
  ReadFailure* out;
  Error operator()(ReadFailure f, const std::string& msg) const {
    if (out) *out = f;
    return make_error(ErrorCode::kContainer, msg);
  }
};

std::string chunk_name(std::size_t i, Tag tag) {
  return "chunk " + std::to_string(i) + " '" + tag.str() + "'";
}

}  // namespace

const char* to_string(ReadFailure f) {
  switch (f) {
    case ReadFailure::kNone: return "none";
    case ReadFailure::kTooSmall: return "too-small";
    case ReadFailure::kBadMagic: return "bad-magic";
    case ReadFailure::kBadByteOrder: return "bad-byte-order";
    case ReadFailure::kUnsupportedVersion: return "unsupported-version";
    case ReadFailure::kBadHeaderSize: return "bad-header-size";
    case ReadFailure::kHeaderChecksum: return "header-checksum";
    case ReadFailure::kReservedNotZero: return "reserved-not-zero";
    case ReadFailure::kFileSizeMismatch: return "file-size-mismatch";
    case ReadFailure::kTooManyChunks: return "too-many-chunks";
    case ReadFailure::kTableOutOfBounds: return "table-out-of-bounds";
    case ReadFailure::kTableChecksum: return "table-checksum";
    case ReadFailure::kUnknownFlags: return "unknown-flags";
    case ReadFailure::kMisaligned: return "misaligned";
    case ReadFailure::kChunkOutOfBounds: return "chunk-out-of-bounds";
    case ReadFailure::kChunkOverlap: return "chunk-overlap";
    case ReadFailure::kBadPadding: return "bad-padding";
    case ReadFailure::kPayloadChecksum: return "payload-checksum";
    case ReadFailure::kUnknownRequiredChunk: return "unknown-required-chunk";
  }
  return "unknown";
}

std::uint64_t checksum64(const void* data, std::size_t size) {
  return XXH3_64bits(data, size);
}

std::span<const std::uint8_t> Container::payload(std::size_t i) const {
  if (i >= chunks_.size()) return {};
  return {data_ + chunks_[i].offset, static_cast<std::size_t>(chunks_[i].size)};
}

std::vector<std::size_t> Container::find(Tag tag) const {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < chunks_.size(); ++i) {
    if (chunks_[i].tag == tag) out.push_back(i);
  }
  return out;
}

Result<Container> read_container(const std::uint8_t* data, std::size_t size,
                                 ReadFailure* failure) {
  const Fail fail{failure};
  if (failure) *failure = ReadFailure::kNone;
  if (data == nullptr || size < kHeaderSize) {
    return fail(ReadFailure::kTooSmall, "file is " + std::to_string(size) +
                                            " bytes, smaller than the " +
                                            std::to_string(kHeaderSize) + "-byte .cxb header");
  }
  if (std::memcmp(data, kMagic, sizeof kMagic) != 0) {
    return fail(ReadFailure::kBadMagic, "header: not a .cxb file (bad magic at offset 0)");
  }
  const std::uint32_t bom = load_u32(data + kOffByteOrder);
  if (bom != kByteOrderMark) {
    return fail(ReadFailure::kBadByteOrder,
                "header: byte-order mark at offset 12 is " + hex64(bom) + ", expected " +
                    hex64(kByteOrderMark) + " (file is not little-endian .cxb or is corrupt)");
  }
  const std::uint16_t version = load_u16(data + kOffVersion);
  if (version != kFormatVersion) {
    return fail(ReadFailure::kUnsupportedVersion,
                "header: format version " + std::to_string(version) +
                    " is not supported (this reader reads version " +
                    std::to_string(kFormatVersion) + "); re-bake the scene with this caustix-bake");
  }
  const std::uint16_t header_size = load_u16(data + kOffHeaderSize);
  if (header_size != kHeaderSize) {
    return fail(ReadFailure::kBadHeaderSize, "header: header size field is " +
                                                 std::to_string(header_size) + ", expected " +
                                                 std::to_string(kHeaderSize));
  }
  const std::uint64_t stored_header_sum = load_u64(data + kOffHeaderChecksum);
  const std::uint64_t header_sum = checksum64(data, kOffHeaderChecksum);
  if (stored_header_sum != header_sum) {
    return fail(ReadFailure::kHeaderChecksum, "header: checksum mismatch (stored " +
                                                  hex64(stored_header_sum) + ", computed " +
                                                  hex64(header_sum) + ")");
  }
  if (load_u32(data + kOffFlags) != 0 || load_u64(data + kOffReserved) != 0 ||
      load_u64(data + kOffReserved + 8) != 0) {
    return fail(ReadFailure::kReservedNotZero, "header: reserved fields (offsets 28 and 40..55) must be zero");
  }
  const std::uint64_t file_size = load_u64(data + kOffFileSize);
  if (file_size != size) {
    return fail(ReadFailure::kFileSizeMismatch,
                "header: file size field says " + std::to_string(file_size) +
                    " bytes but the file has " + std::to_string(size) +
                    (file_size > size ? " (truncated?)" : " (trailing bytes?)"));
  }
  const std::uint32_t count = load_u32(data + kOffChunkCount);
  if (count > kMaxChunkCount) {
    return fail(ReadFailure::kTooManyChunks, "header: chunk count " + std::to_string(count) +
                                                 " exceeds the limit of " +
                                                 std::to_string(kMaxChunkCount));
  }
  // count <= 2^20, so this cannot overflow 64 bits.
  const std::uint64_t table_end = kHeaderSize + std::uint64_t{count} * kChunkEntrySize;
  if (table_end > size) {
    return fail(ReadFailure::kTableOutOfBounds,
                "chunk table: " + std::to_string(count) + " entries end at byte " +
                    std::to_string(table_end) + ", past the end of the " + std::to_string(size) +
                    "-byte file");
  }
  const std::uint8_t* table = data + kHeaderSize;
  const std::uint64_t stored_table_sum = load_u64(data + kOffTableChecksum);
  const std::uint64_t table_sum = checksum64(table, static_cast<std::size_t>(table_end - kHeaderSize));
  if (stored_table_sum != table_sum) {
    return fail(ReadFailure::kTableChecksum, "chunk table: checksum mismatch (stored " +
                                                 hex64(stored_table_sum) + ", computed " +
                                                 hex64(table_sum) + ")");
  }

  Container c;
  c.data_ = data;
  c.header_ = Header{version, file_size, count};
  c.chunks_.reserve(count);
  std::uint64_t prev_end = table_end;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint8_t* e = table + std::size_t{i} * kChunkEntrySize;
    ChunkInfo ci;
    std::memcpy(ci.tag.c.data(), e, 4);
    ci.flags = load_u32(e + 4);
    ci.offset = load_u64(e + 8);
    ci.size = load_u64(e + 16);
    ci.checksum = load_u64(e + 24);
    ci.known = is_known_tag(ci.tag);
    const std::string name = chunk_name(i, ci.tag);
    if ((ci.flags & ~kKnownChunkFlags) != 0) {
      return fail(ReadFailure::kUnknownFlags, name + ": unknown flag bits " + hex64(ci.flags));
    }
    if (ci.offset % kPayloadAlignment != 0) {
      return fail(ReadFailure::kMisaligned, name + ": offset " + std::to_string(ci.offset) +
                                                " is not a multiple of " +
                                                std::to_string(kPayloadAlignment));
    }
    // Overflow-free form of offset + size > file_size.
    if (ci.offset > file_size || ci.size > file_size - ci.offset) {
      return fail(ReadFailure::kChunkOutOfBounds,
                  name + ": payload [" + std::to_string(ci.offset) + ", +" +
                      std::to_string(ci.size) + ") runs past the end of the " +
                      std::to_string(file_size) + "-byte file");
    }
    // Payloads are stored in table order, each at the first aligned offset
    // after the previous one; anything else overlaps or leaves a gap.
    if (ci.offset < prev_end) {
      return fail(ReadFailure::kChunkOverlap, name + ": payload at offset " +
                                                  std::to_string(ci.offset) +
                                                  " overlaps the table or the previous chunk (which ends at " +
                                                  std::to_string(prev_end) + ")");
    }
    if (ci.offset != align_up(prev_end)) {
      return fail(ReadFailure::kBadPadding, name + ": payload at offset " +
                                                std::to_string(ci.offset) + " leaves a gap after byte " +
                                                std::to_string(prev_end) + " (expected offset " +
                                                std::to_string(align_up(prev_end)) + ")");
    }
    for (std::uint64_t p = prev_end; p < ci.offset; ++p) {
      if (data[p] != 0) {
        return fail(ReadFailure::kBadPadding, name + ": padding byte at offset " +
                                                  std::to_string(p) + " before the payload is not zero");
      }
    }
    const std::uint64_t sum = checksum64(data + ci.offset, static_cast<std::size_t>(ci.size));
    if (sum != ci.checksum) {
      return fail(ReadFailure::kPayloadChecksum, name + " at offset " + std::to_string(ci.offset) +
                                                     ": payload checksum mismatch (stored " +
                                                     hex64(ci.checksum) + ", computed " +
                                                     hex64(sum) + ")");
    }
    if (!ci.known && (ci.flags & kChunkRequired)) {
      return fail(ReadFailure::kUnknownRequiredChunk,
                  name + ": required chunk of an unknown kind (written by a newer caustix?)");
    }
    prev_end = ci.offset + ci.size;
    c.chunks_.push_back(ci);
  }
  if (prev_end != file_size) {
    return fail(ReadFailure::kFileSizeMismatch, "file has " +
                                                    std::to_string(file_size - prev_end) +
                                                    " trailing bytes after the last chunk");
  }
  return c;
}

void ContainerWriter::add_chunk(Tag tag, std::uint32_t flags, std::vector<std::uint8_t> payload) {
  chunks_.push_back(Pending{tag, flags, std::move(payload)});
}

std::vector<std::uint8_t> ContainerWriter::finish() const {
  const std::uint64_t table_end = kHeaderSize + chunks_.size() * kChunkEntrySize;
  std::uint64_t end = table_end;
  std::vector<std::uint64_t> offsets;
  offsets.reserve(chunks_.size());
  for (const auto& ch : chunks_) {
    const std::uint64_t off = align_up(end);
    offsets.push_back(off);
    end = off + ch.payload.size();
  }
  std::vector<std::uint8_t> out(static_cast<std::size_t>(end), 0);
  std::uint8_t* h = out.data();
  std::memcpy(h, kMagic, sizeof kMagic);
  store_u16(h + kOffVersion, kFormatVersion);
  store_u16(h + kOffHeaderSize, static_cast<std::uint16_t>(kHeaderSize));
  store_u32(h + kOffByteOrder, kByteOrderMark);
  store_u64(h + kOffFileSize, end);
  store_u32(h + kOffChunkCount, static_cast<std::uint32_t>(chunks_.size()));
  for (std::size_t i = 0; i < chunks_.size(); ++i) {
    const auto& ch = chunks_[i];
    std::uint8_t* e = h + kHeaderSize + i * kChunkEntrySize;
    std::memcpy(e, ch.tag.c.data(), 4);
    store_u32(e + 4, ch.flags);
    store_u64(e + 8, offsets[i]);
    store_u64(e + 16, ch.payload.size());
    store_u64(e + 24, checksum64(ch.payload.data(), ch.payload.size()));
    if (!ch.payload.empty()) std::memcpy(h + offsets[i], ch.payload.data(), ch.payload.size());
  }
  store_u64(h + kOffTableChecksum,
            checksum64(h + kHeaderSize, static_cast<std::size_t>(table_end - kHeaderSize)));
  store_u64(h + kOffHeaderChecksum, checksum64(h, kOffHeaderChecksum));
  return out;
}

}  // namespace caustix::cxb
