// LMAP and OBBS payloads (formats/SPEC.md). The position and diffuse maps are
// one zstd frame; everything else is plain little-endian fields.

#include <cmath>

#include "bytes.h"
#include "caustix/formats/level_map.h"
#include "caustix/formats/scene.h"
#include "chunk_decoder.h"
#include "zstd_frame.h"

namespace caustix {
namespace {

using cxb::detail::ByteWriter;
using cxb::detail::ChunkDecoder;
using cxb::detail::write_zstd_frame;
using cxb::detail::zstd_decompress_exact;

// zstd level: 3 is zstd's default; higher levels cost bake time for a few
// percent on these maps.
constexpr int kZstdLevel = 3;

// Depth maps are smooth: store each row as differences from the texel to its
// left (mod 2^16), split into a plane of low bytes and one of high bytes, so
// zstd sees long runs of small numbers (PNG's "Sub" filter, plus a byte
// shuffle). The diffuse map follows unchanged.
std::vector<std::uint8_t> filter_maps(const LevelMap& m) {
  const std::size_t n = m.depth.size(), s = m.map_size;
  std::vector<std::uint8_t> raw(n * 2 + m.diffuse.size());
  for (std::size_t i = 0; i < n; ++i) {
    const auto d = static_cast<std::uint16_t>(m.depth[i] - (i % s == 0 ? 0 : m.depth[i - 1]));
    raw[i] = static_cast<std::uint8_t>(d & 0xFF);
    raw[n + i] = static_cast<std::uint8_t>(d >> 8);
  }
  std::copy(m.diffuse.begin(), m.diffuse.end(), raw.begin() + static_cast<std::ptrdiff_t>(2 * n));
  return raw;
}

void unfilter_maps(const std::vector<std::uint8_t>& raw, LevelMap& m) {
  const std::size_t n = std::size_t{m.map_size} * m.map_size, s = m.map_size;
  m.depth.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto d = static_cast<std::uint16_t>(raw[i] | (raw[n + i] << 8));
    m.depth[i] = static_cast<std::uint16_t>(d + (i % s == 0 ? 0 : m.depth[i - 1]));
  }
  m.diffuse.assign(raw.begin() + static_cast<std::ptrdiff_t>(2 * n), raw.end());
}

bool finite3(const Vec3f& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
float dot(const Vec3f& a, const Vec3f& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3f cross(const Vec3f& a, const Vec3f& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// An orthonormal, right-handed triple (tolerance for float rounding).
bool orthonormal(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  if (!finite3(a) || !finite3(b) || !finite3(c)) return false;
  constexpr float tol = 1e-4f;
  return std::fabs(dot(a, a) - 1) < tol && std::fabs(dot(b, b) - 1) < tol && std::fabs(dot(c, c) - 1) < tol &&
         std::fabs(dot(a, b)) < tol && std::fabs(dot(a, c)) < tol && std::fabs(dot(b, c)) < tol &&
         dot(cross(a, b), c) > 1 - tol;
}

void put_planes(ByteWriter& w, const std::vector<ReferencePlane>& planes) {
  w.u32(static_cast<std::uint32_t>(planes.size()));
  for (const auto& p : planes) {
    w.f32(p.offset);
    w.f32(p.epsilon);
  }
}

bool get_planes(ChunkDecoder& d, std::vector<ReferencePlane>& planes, float h) {
  std::uint32_t n = 0;
  if (!d.count(n, kMaxPlanes, 8, "plane")) return false;
  planes.resize(n);
  for (auto& p : planes) {
    if (!d.f32(p.offset, "plane offset") || !d.f32(p.epsilon, "plane epsilon")) return false;
    if (!std::isfinite(p.offset) || std::fabs(p.offset) > 2 * h + 1e-6f || !(p.epsilon > 0) || !std::isfinite(p.epsilon)) {
      return d.fail("plane offset or epsilon out of range");
    }
  }
  return true;
}

}  // namespace

std::vector<std::uint8_t> encode_level_map(const LevelMap& m) {
  ByteWriter w;
  w.u32(m.object);
  w.u32(m.light);
  for (double o : m.frame.origin) w.f64(o);
  w.vec3(m.frame.u);
  w.vec3(m.frame.v);
  w.vec3(m.frame.w);
  w.vec3(m.frame.half);
  w.vec3(m.frame.symmetric_size);
  w.u32(m.map_size);
  w.u8(static_cast<std::uint8_t>(m.slicing));
  w.u8(0);
  w.u16(0);
  w.f32(m.epsilon);
  w.u32(m.planes_requested);
  w.u32(static_cast<std::uint32_t>(m.histogram.size()));
  for (std::uint32_t c : m.histogram) w.u32(c);
  w.u32(static_cast<std::uint32_t>(m.sub_boxes.size()));
  for (const auto& b : m.sub_boxes) {
    w.u32(b.first_level);
    w.u32(b.last_level);
  }
  put_planes(w, m.uniform_planes);
  put_planes(w, m.smart_planes);

  write_zstd_frame(w, filter_maps(m), kZstdLevel);
  return w.take();
}

Result<LevelMap> decode_level_map(std::span<const std::uint8_t> payload, const SceneDesc& scene) {
  ChunkDecoder d(cxb::kTagLevelMap, payload);
  LevelMap m;
  std::uint8_t slicing = 0, pad = 0;
  std::uint32_t levels = 0, boxes = 0, packed_size = 0;
  bool ok = d.u32(m.object, "object index") && d.u32(m.light, "light index");
  for (double& o : m.frame.origin) ok = ok && d.f64(o, "frame origin");
  ok = ok && d.vec3(m.frame.u, "frame U") && d.vec3(m.frame.v, "frame V") && d.vec3(m.frame.w, "frame W") &&
       d.vec3(m.frame.half, "frame extents") && d.vec3(m.frame.symmetric_size, "frame symmetric size") &&
       d.u32(m.map_size, "map size") && d.u8(slicing, "slicing") && d.u8(pad, "reserved") && d.zero16("reserved") &&
       d.f32(m.epsilon, "epsilon") && d.u32(m.planes_requested, "planes requested");
  if (!ok) return d.error();
  if (m.object >= scene.objects.size() || !is_receiver(scene.objects[m.object].role)) {
    d.fail("object index " + std::to_string(m.object) + " is not a receiver of the scene");
    return d.error();
  }
  if (m.light >= scene.lights.size()) {
    d.fail("light index " + std::to_string(m.light) + " is out of range");
    return d.error();
  }
  const auto& f = m.frame;
  const bool origin_ok = std::isfinite(f.origin[0]) && std::isfinite(f.origin[1]) && std::isfinite(f.origin[2]);
  if (!origin_ok || !orthonormal(f.u, f.v, f.w) || !finite3(f.half) || f.half[0] < 0 || f.half[1] < 0 ||
      f.half[2] < 0 || !finite3(f.symmetric_size)) {
    d.fail("the bounding frame is not finite, orthonormal and right-handed");
    return d.error();
  }
  if (m.map_size < 1 || m.map_size > kMaxMapSize || pad != 0 || (slicing != 1 && slicing != 2) ||
      !(m.epsilon > 0) || !std::isfinite(m.epsilon)) {
    d.fail("map size, slicing or epsilon out of range");
    return d.error();
  }
  m.slicing = static_cast<Slicing>(slicing);
  if (!d.count(levels, kMaxDepthLevels, 4, "depth level")) return d.error();
  if (levels == 0) {
    d.fail("no depth levels");
    return d.error();
  }
  m.histogram.resize(levels);
  std::uint64_t texels = 0;
  for (auto& c : m.histogram) {
    if (!d.u32(c, "histogram")) return d.error();
    texels += c;
  }
  if (texels > std::uint64_t{m.map_size} * m.map_size) {
    d.fail("the histogram counts more texels than the map has");
    return d.error();
  }
  if (!d.count(boxes, levels, 8, "sub-box")) return d.error();
  m.sub_boxes.resize(boxes);
  std::int64_t prev_last = -1;
  for (auto& b : m.sub_boxes) {
    if (!d.u32(b.first_level, "sub-box") || !d.u32(b.last_level, "sub-box")) return d.error();
    if (b.first_level > b.last_level || b.last_level >= levels || std::int64_t{b.first_level} <= prev_last) {
      d.fail("sub-boxes must be ordered, disjoint and within the depth levels");
      return d.error();
    }
    prev_last = b.last_level;
  }
  const float h = 2 * f.half[1];
  if (!get_planes(d, m.uniform_planes, h + 1e-6f) || !get_planes(d, m.smart_planes, h + 1e-6f) ||
      !d.u32(packed_size, "map data size")) {
    return d.error();
  }
  std::span<const std::uint8_t> packed;
  if (!d.span(packed, packed_size, "map data") || !d.finish()) return d.error();

  const std::size_t texel_count = std::size_t{m.map_size} * m.map_size;
  const std::size_t raw_size = texel_count * 5;
  std::vector<std::uint8_t> raw;
  if (!zstd_decompress_exact(d, packed, raw_size, "map data",
                             "a " + std::to_string(m.map_size) + "^2 position and diffuse map", raw)) {
    return d.error();
  }
  unfilter_maps(raw, m);
  std::uint64_t filled = 0;
  for (std::uint16_t q : m.depth) {
    if (q != kEmptyDepth && q > kDepthQuantum) {
      d.fail("a position-map depth is out of range");
      return d.error();
    }
    filled += q != kEmptyDepth ? 1 : 0;
  }
  if (filled != texels) {
    d.fail("the histogram does not match the position map");
    return d.error();
  }
  return m;
}

std::vector<std::uint8_t> encode_object_boxes(const std::vector<ObjectBox>& boxes) {
  ByteWriter w;
  w.u32(static_cast<std::uint32_t>(boxes.size()));
  for (const auto& b : boxes) {
    w.u32(b.object);
    for (double c : b.center) w.f64(c);
    for (const auto& a : b.axes) w.vec3(a);
    w.vec3(b.half);
  }
  return w.take();
}

Result<std::vector<ObjectBox>> decode_object_boxes(std::span<const std::uint8_t> payload, const SceneDesc& scene) {
  ChunkDecoder d(cxb::kTagObjectBoxes, payload);
  std::uint32_t n = 0;
  if (!d.count(n, scene.objects.size(), 4 + 24 + 48, "box")) return d.error();
  std::vector<ObjectBox> boxes(n);
  for (auto& b : boxes) {
    bool ok = d.u32(b.object, "object index");
    for (double& c : b.center) ok = ok && d.f64(c, "box centre");
    for (auto& a : b.axes) ok = ok && d.vec3(a, "box axis");
    ok = ok && d.vec3(b.half, "box extents");
    if (!ok) return d.error();
    if (b.object >= scene.objects.size() || !std::isfinite(b.center[0]) || !std::isfinite(b.center[1]) ||
        !std::isfinite(b.center[2]) || !finite3(b.half) || b.half[0] < 0 || b.half[1] < 0 || b.half[2] < 0) {
      d.fail("box " + std::to_string(&b - boxes.data()) + ": object index, centre or extents out of range");
      return d.error();
    }
    // CGAL's boxes are orthonormal but may be left-handed; accept either.
    const Vec3f c = cross(b.axes[0], b.axes[1]);
    if (!orthonormal(b.axes[0], b.axes[1], dot(c, b.axes[2]) > 0 ? b.axes[2] : Vec3f{-b.axes[2][0], -b.axes[2][1], -b.axes[2][2]})) {
      d.fail("box " + std::to_string(&b - boxes.data()) + ": axes are not orthonormal");
      return d.error();
    }
  }
  if (!d.finish()) return d.error();
  return boxes;
}

}  // namespace caustix
