#pragma once
// Little-endian byte (de)serialisation used by every .cxb payload. ByteReader
// never reads past its span: each get returns false once the data runs out and
// remembers the offset where it did, so decoders can name the place.

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

namespace caustix::cxb::detail {

static_assert(std::endian::native == std::endian::little,
              "caustix assumes a little-endian host (the .cxb byte order)");

inline std::uint16_t load_u16(const std::uint8_t* p) { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
inline std::uint32_t load_u32(const std::uint8_t* p) { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
inline std::uint64_t load_u64(const std::uint8_t* p) { std::uint64_t v; std::memcpy(&v, p, 8); return v; }
inline void store_u16(std::uint8_t* p, std::uint16_t v) { std::memcpy(p, &v, 2); }
inline void store_u32(std::uint8_t* p, std::uint32_t v) { std::memcpy(p, &v, 4); }
inline void store_u64(std::uint8_t* p, std::uint64_t v) { std::memcpy(p, &v, 8); }

class ByteWriter {
 public:
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v) { append(&v, 2); }
  void u32(std::uint32_t v) { append(&v, 4); }
  void u64(std::uint64_t v) { append(&v, 8); }
  void f32(float v) { append(&v, 4); }
  void f64(double v) { append(&v, 8); }
  void vec3(const std::array<float, 3>& v) {  // three f32, as ChunkDecoder::vec3 reads them
    for (float f : v) f32(f);
  }
  void raw(const void* p, std::size_t n) { append(p, n); }
  void str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    append(s.data(), s.size());
  }
  std::vector<std::uint8_t> take() { return std::move(out_); }

 private:
  void append(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  std::vector<std::uint8_t> out_;
};

class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> bytes) : b_(bytes) {}

  bool u8(std::uint8_t& v) { return read(&v, 1); }
  bool u16(std::uint16_t& v) { return read(&v, 2); }
  bool u32(std::uint32_t& v) { return read(&v, 4); }
  bool u64(std::uint64_t& v) { return read(&v, 8); }
  bool f32(float& v) { return read(&v, 4); }
  bool f64(double& v) { return read(&v, 8); }
  // A view of the next n bytes.
  bool span(std::span<const std::uint8_t>& out, std::size_t n) {
    if (n > remaining()) return false;
    out = b_.subspan(pos_, n);
    pos_ += n;
    return true;
  }
  // A length-prefixed string of at most max_len bytes.
  bool str(std::string& s, std::size_t max_len) {
    std::uint32_t n = 0;
    if (!u32(n) || n > max_len || n > remaining()) return false;
    s.assign(reinterpret_cast<const char*>(b_.data() + pos_), n);
    pos_ += n;
    return true;
  }
  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return b_.size() - pos_; }

 private:
  bool read(void* dst, std::size_t n) {
    if (n > remaining()) return false;
    std::memcpy(dst, b_.data() + pos_, n);
    pos_ += n;
    return true;
  }
  std::span<const std::uint8_t> b_;
  std::size_t pos_ = 0;
};

}  // namespace caustix::cxb::detail
