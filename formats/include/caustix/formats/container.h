#pragma once
// The .cxb container, format version 1: a fixed header, a chunk table and
// 16-byte-aligned chunk payloads, each checksummed with XXH3-64. The byte
// layout is specified in formats/SPEC.md; this file and container.cpp are the
// only code that knows it.
//
// Contract of read_container(): safe on untrusted input. Whatever the bytes,
// it never reads outside [data, data + size), never asserts, never throws, and
// it validates everything (magic, version, byte order, header and table
// checksums, every offset/size/count against the file size without integer
// overflow, alignment, ordering, padding, payload checksums, unknown required
// chunks) before it returns a Container. On failure it returns an Error with
// code kContainer whose message names the chunk (index and tag) and the reason.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/tags.h"

namespace caustix::cxb {

// Bump kFormatVersion whenever the header, the table or any chunk payload
// changes incompatibly; keep a golden file of the old version in
// assets/golden/ and a test that later readers read it or refuse it clearly.
inline constexpr std::uint16_t kFormatVersion = 1;

inline constexpr std::size_t kHeaderSize = 64;
inline constexpr std::size_t kChunkEntrySize = 32;
inline constexpr std::size_t kPayloadAlignment = 16;
inline constexpr std::uint32_t kByteOrderMark = 0x01020304u;
// Far above any real scene; bounds table allocation for hostile counts.
inline constexpr std::uint32_t kMaxChunkCount = 1u << 20;

// Chunk flags (on disk; never renumber).
inline constexpr std::uint32_t kChunkRequired = 1u << 0;
inline constexpr std::uint32_t kKnownChunkFlags = kChunkRequired;

// Why a container was refused: one value per check, so tests can assert the
// specific reason. On-disk-independent; may grow, never renumbered.
enum class ReadFailure {
  kNone = 0,
  kTooSmall,
  kBadMagic,
  kBadByteOrder,
  kUnsupportedVersion,
  kBadHeaderSize,
  kHeaderChecksum,
  kReservedNotZero,
  kFileSizeMismatch,
  kTooManyChunks,
  kTableOutOfBounds,
  kTableChecksum,
  kUnknownFlags,
  kMisaligned,
  kChunkOutOfBounds,
  kChunkOverlap,
  kBadPadding,
  kPayloadChecksum,
  kUnknownRequiredChunk,
};

const char* to_string(ReadFailure f);

struct ChunkInfo {
  Tag tag;
  std::uint32_t flags = 0;
  std::uint64_t offset = 0;
  std::uint64_t size = 0;
  std::uint64_t checksum = 0;
  bool known = false;  // tag is in this reader's registry (tags.h)
};

struct Header {
  std::uint16_t version = 0;
  std::uint64_t file_size = 0;
  std::uint32_t chunk_count = 0;
};

// A validated view of a container. Payload spans point into the caller's
// buffer, which must outlive the Container.
class Container {
 public:
  const Header& header() const { return header_; }
  const std::vector<ChunkInfo>& chunks() const { return chunks_; }
  std::span<const std::uint8_t> payload(std::size_t chunk_index) const;
  // Indices of the chunks with `tag`, in file order.
  std::vector<std::size_t> find(Tag tag) const;

 private:
  friend Result<Container> read_container(const std::uint8_t*, std::size_t, ReadFailure*);
  const std::uint8_t* data_ = nullptr;
  Header header_;
  std::vector<ChunkInfo> chunks_;
};

// Validates and indexes a container held in memory. See the contract above.
// If `failure` is given it receives the reason (kNone on success).
Result<Container> read_container(const std::uint8_t* data, std::size_t size,
                                 ReadFailure* failure = nullptr);

// Builds a container in memory. Chunks are laid out in the order added;
// identical calls give identical bytes.
class ContainerWriter {
 public:
  void add_chunk(Tag tag, std::uint32_t flags, std::vector<std::uint8_t> payload);
  std::vector<std::uint8_t> finish() const;

 private:
  struct Pending {
    Tag tag;
    std::uint32_t flags;
    std::vector<std::uint8_t> payload;
  };
  std::vector<Pending> chunks_;
};

// XXH3-64 (seed 0) of a byte range: the checksum used everywhere in .cxb.
std::uint64_t checksum64(const void* data, std::size_t size);

}  // namespace caustix::cxb
