#pragma once
// Reads one chunk payload field by field. The first failed read records what
// was being read and where, so decoders can name chunk, payload offset and
// field in their error.

#include <string>

#include "bytes.h"
#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/formats/tags.h"

namespace caustix::cxb::detail {

// Reads one chunk payload; the first failed read records what was being read
// so the error can name chunk, payload offset and field.
class ChunkDecoder {
 public:
  ChunkDecoder(Tag tag, std::span<const std::uint8_t> bytes) : tag_(tag), r_(bytes) {}

  bool u8(std::uint8_t& v, const char* what) { return check(r_.u8(v), what); }
  bool u16(std::uint16_t& v, const char* what) { return check(r_.u16(v), what); }
  bool u32(std::uint32_t& v, const char* what) { return check(r_.u32(v), what); }
  bool f32(float& v, const char* what) { return check(r_.f32(v), what); }
  bool f64(double& v, const char* what) { return check(r_.f64(v), what); }
  bool span(std::span<const std::uint8_t>& out, std::size_t n, const char* what) { return check(r_.span(out, n), what); }
  std::size_t remaining() const { return r_.remaining(); }
  bool vec3(Vec3f& v, const char* what) {
    return f32(v[0], what) && f32(v[1], what) && f32(v[2], what);
  }
  bool str(std::string& s, const char* what) { return check(r_.str(s, kMaxNameLength), what); }
  // A count whose records take at least min_record_bytes each.
  bool count(std::uint32_t& n, std::size_t limit, std::size_t min_record_bytes, const char* what) {
    if (!u32(n, what)) return false;
    if (n > limit || std::size_t{n} * min_record_bytes > r_.remaining()) {
      return fail(std::string(what) + " count " + std::to_string(n) +
                  " exceeds the limit or the payload size");
    }
    return true;
  }
  bool zero16(const char* what) {
    std::uint16_t z = 0;
    if (!u16(z, what)) return false;
    return z == 0 || fail(std::string(what) + " must be zero");
  }
  bool fail(const std::string& msg) {
    if (error_.empty()) {
      error_ = "chunk '" + tag_.str() + "' payload offset " + std::to_string(r_.offset()) + ": " + msg;
    }
    return false;
  }
  bool finish() {
    return r_.remaining() == 0 ||
           fail(std::to_string(r_.remaining()) + " unexpected trailing bytes");
  }
  Error error() const { return make_error(ErrorCode::kContainer, error_); }

 private:
  bool check(bool ok, const char* what) {
    return ok || fail(std::string("truncated while reading ") + what);
  }
  Tag tag_;
  ByteReader r_;
  std::string error_;
};

}  // namespace caustix::cxb::detail
