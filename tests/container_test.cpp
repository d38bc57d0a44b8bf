// The .cxb container: round trip, and every corruption class refused with its
// specific reason (never a crash; this suite also runs under ASan + UBSan).

#include <gtest/gtest.h>

#include "caustix/formats/container.h"
#include "caustix/formats/scene.h"
#include "cxb_test_util.h"

namespace caustix {
namespace {

using cxb::ReadFailure;
using test::entry;
using test::put_u32;
using test::put_u64;
using test::reseal;

std::vector<std::uint8_t> bytes_of(const char* s) { return std::vector<std::uint8_t>(s, s + std::strlen(s)); }

std::vector<std::uint8_t> sample() {
  cxb::ContainerWriter w;
  w.add_chunk(cxb::kTagScene, cxb::kChunkRequired, bytes_of("hello"));
  w.add_chunk(cxb::kTagCamera, 0, {});
  w.add_chunk(cxb::kTagMesh, cxb::kChunkRequired, std::vector<std::uint8_t>(37, 0xAB));
  return w.finish();
}

ReadFailure failure_of(const std::vector<std::uint8_t>& b) {
  ReadFailure f = ReadFailure::kNone;
  auto c = cxb::read_container(b.data(), b.size(), &f);
  EXPECT_EQ(c.ok(), f == ReadFailure::kNone);
  if (!c.ok()) EXPECT_FALSE(c.error().message.empty());
  return f;
}

TEST(Container, RoundTrip) {
  const auto b = sample();
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok()) << c.error().message;
  ASSERT_EQ(c->chunks().size(), 3u);
  EXPECT_EQ(c->chunks()[0].tag, cxb::kTagScene);
  EXPECT_EQ(std::string(c->payload(0).begin(), c->payload(0).end()), "hello");
  EXPECT_EQ(c->payload(1).size(), 0u);
  EXPECT_EQ(c->payload(2).size(), 37u);
  for (const auto& ch : c->chunks()) EXPECT_EQ(ch.offset % cxb::kPayloadAlignment, 0u);
  EXPECT_EQ(c->find(cxb::kTagMesh), std::vector<std::size_t>{2});
  EXPECT_EQ(b.size(), c->header().file_size);
}

TEST(Container, WriterIsDeterministic) { EXPECT_EQ(sample(), sample()); }

TEST(Container, EmptyContainerIsValid) {
  const auto b = cxb::ContainerWriter().finish();
  EXPECT_EQ(b.size(), cxb::kHeaderSize);
  EXPECT_EQ(failure_of(b), ReadFailure::kNone);
}

TEST(Container, NullAndTiny) {
  EXPECT_EQ(failure_of({}), ReadFailure::kTooSmall);
  ReadFailure f{};
  EXPECT_FALSE(cxb::read_container(nullptr, 100, &f).ok());
  EXPECT_EQ(f, ReadFailure::kTooSmall);
}

TEST(Container, EveryPrefixTruncationIsRefused) {
  const auto b = sample();
  for (std::size_t n = 0; n < b.size(); ++n) {
    std::vector<std::uint8_t> t(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
    const ReadFailure f = failure_of(t);
    ASSERT_NE(f, ReadFailure::kNone) << "prefix of " << n << " bytes accepted";
    if (n < cxb::kHeaderSize) EXPECT_EQ(f, ReadFailure::kTooSmall);
    else EXPECT_EQ(f, ReadFailure::kFileSizeMismatch) << n;
  }
}

TEST(Container, EveryFlippedByteIsRefused) {
  const auto b = sample();
  for (std::size_t i = 0; i < b.size(); ++i) {
    for (std::uint8_t mask : {0x01, 0x80}) {
      auto t = b;
      t[i] ^= mask;
      ASSERT_NE(failure_of(t), ReadFailure::kNone) << "flip at byte " << i << " accepted";
    }
  }
}

TEST(Container, FlippedPayloadByteNamesTheChunk) {
  auto b = sample();
  const std::uint64_t off = test::get_u64(b, entry(2) + 8);
  b[off + 5] ^= 0xFF;
  ReadFailure f{};
  auto c = cxb::read_container(b.data(), b.size(), &f);
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(f, ReadFailure::kPayloadChecksum);
  EXPECT_NE(c.error().message.find("chunk 2 'MESH'"), std::string::npos) << c.error().message;
}

TEST(Container, WrongMagicVersionByteOrder) {
  auto b = sample();
  b[1] = 'X';
  EXPECT_EQ(failure_of(b), ReadFailure::kBadMagic);
  b = sample();
  b[8] = 2;  // version 2
  EXPECT_EQ(failure_of(b), ReadFailure::kUnsupportedVersion);
  b = sample();
  put_u32(b, 12, 0x04030201u);  // big-endian writer
  EXPECT_EQ(failure_of(b), ReadFailure::kBadByteOrder);
  b = sample();
  b[10] = 65;  // header size
  EXPECT_EQ(failure_of(b), ReadFailure::kBadHeaderSize);
}

TEST(Container, HeaderAndTableChecksums) {
  auto b = sample();
  b[20] ^= 1;  // file size field, not resealed
  EXPECT_EQ(failure_of(b), ReadFailure::kHeaderChecksum);
  b = sample();
  b[entry(1) + 4] ^= 1;  // a table byte, not resealed
  EXPECT_EQ(failure_of(b), ReadFailure::kTableChecksum);
}

TEST(Container, ReservedFieldsMustBeZero) {
  auto b = sample();
  b[44] = 1;
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kReservedNotZero);
}

TEST(Container, TrailingBytesAndSizeField) {
  auto b = sample();
  b.push_back(0);
  EXPECT_EQ(failure_of(b), ReadFailure::kFileSizeMismatch);
  b = sample();
  put_u64(b, test::kFileSizeOff, b.size() + 16);
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kFileSizeMismatch);
}

TEST(Container, CountsThatOverflowOrRunPastTheEnd) {
  auto b = sample();
  put_u32(b, test::kCountOff, 0xFFFFFFFFu);
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kTooManyChunks);
  b = sample();
  put_u32(b, test::kCountOff, cxb::kMaxChunkCount);  // allowed count, but the table cannot fit
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kTableOutOfBounds);
}

TEST(Container, OffsetsAndSizesPastTheEnd) {
  auto b = sample();
  put_u64(b, entry(2) + 16, 1u << 20);  // size past the end
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kChunkOutOfBounds);
  b = sample();
  put_u64(b, entry(2) + 16, ~std::uint64_t{0});  // offset + size overflows 64 bits
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kChunkOutOfBounds);
  b = sample();
  put_u64(b, entry(2) + 8, ~std::uint64_t{15});  // aligned offset far past the end
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kChunkOutOfBounds);
}

TEST(Container, OverlapsMisalignmentPaddingFlags) {
  auto b = sample();
  put_u64(b, entry(2) + 8, test::get_u64(b, entry(0) + 8));  // chunk 2 starts where chunk 0 does
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kChunkOverlap);
  b = sample();
  put_u64(b, entry(0) + 8, 64);  // into the table
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kChunkOverlap);
  b = sample();
  put_u64(b, entry(2) + 8, test::get_u64(b, entry(2) + 8) + 4);
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kMisaligned);
  b = sample();
  b[test::get_u64(b, entry(0) + 8) + 5] = 7;  // "hello" is 5 bytes; byte 5 is padding
  EXPECT_EQ(failure_of(b), ReadFailure::kBadPadding);
  b = sample();
  put_u32(b, entry(1) + 4, 0x10);
  reseal(b);
  EXPECT_EQ(failure_of(b), ReadFailure::kUnknownFlags);
}

TEST(Container, UnknownChunks) {
  cxb::ContainerWriter w;
  w.add_chunk(cxb::make_tag("ZZZZ"), 0, bytes_of("optional, from the future"));
  auto b = w.finish();
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  EXPECT_FALSE(c->chunks()[0].known);

  cxb::ContainerWriter w2;
  w2.add_chunk(cxb::make_tag("ZZZZ"), cxb::kChunkRequired, bytes_of("required, from the future"));
  b = w2.finish();
  ReadFailure f{};
  auto c2 = cxb::read_container(b.data(), b.size(), &f);
  ASSERT_FALSE(c2.ok());
  EXPECT_EQ(f, ReadFailure::kUnknownRequiredChunk);
  EXPECT_NE(c2.error().message.find("'ZZZZ'"), std::string::npos);
}

TEST(Container, TagPrintsUnprintableBytes) {
  const cxb::Tag t{{'A', '\0', '\n', char(0xFF)}};
  EXPECT_EQ(t.str(), "A\\x00\\x0A\\xFF");
}

}  // namespace
}  // namespace caustix

namespace caustix {
namespace {

// The same corruption sweep over a real baked file (the v1 golden), through
// the container reader and the scene decoder.
TEST(Container, GoldenFileEveryPrefixAndFlip) {
  const std::string path = std::string(CAUSTIX_SOURCE_DIR) + "/assets/golden/default-v1.cxb";
  std::FILE* f = std::fopen(path.c_str(), "rb");
  ASSERT_NE(f, nullptr) << path;
  std::vector<std::uint8_t> b(1 << 20);
  b.resize(std::fread(b.data(), 1, b.size(), f));
  std::fclose(f);
  auto whole = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  ASSERT_TRUE(decode_scene(*whole).ok());
  for (std::size_t n = 0; n < b.size(); ++n) {
    auto c = cxb::read_container(b.data(), n);
    ASSERT_FALSE(c.ok()) << "prefix " << n;
  }
  for (std::size_t i = 0; i < b.size(); i += 3) {
    auto t = b;
    t[i] ^= 0x10;
    auto c = cxb::read_container(t.data(), t.size());
    ASSERT_FALSE(c.ok()) << "flip at " << i;
  }
}

}  // namespace
}  // namespace caustix
