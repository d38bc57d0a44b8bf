// IGRD payload (formats/SPEC.md): the header fields, then one zstd frame of
// three byte planes (coverage low bytes, coverage high bytes, levels).

#include "caustix/formats/index_grid.h"

#include <cmath>

#include "bytes.h"
#include "caustix/formats/scene.h"
#include "chunk_decoder.h"
#include "zstd_frame.h"

namespace caustix {
namespace {

using cxb::detail::ByteWriter;
using cxb::detail::ChunkDecoder;

constexpr int kZstdLevel = 9;
constexpr std::size_t kMaxRatio = 65536;  // raw / packed: zstd's best on constant data is far below

}  // namespace

std::vector<std::uint8_t> encode_index_grid(const IndexGrid& g) {
  ByteWriter w;
  w.u32(g.object);
  w.u32(g.size[0]);
  w.u32(g.size[1]);
  w.u32(g.size[2]);
  w.vec3(g.origin);
  w.f32(g.voxel);
  w.f32(g.ior_inside);
  w.f32(g.ior_outside);
  w.f32(g.blur);
  w.f32(g.epsilon);
  const std::size_t n = g.voxels();
  std::vector<std::uint8_t> raw(3 * n);
  for (std::size_t v = 0; v < n; ++v) {
    raw[v] = static_cast<std::uint8_t>(g.coverage[v] & 0xFF);
    raw[n + v] = static_cast<std::uint8_t>(g.coverage[v] >> 8);
    raw[2 * n + v] = g.level[v];
  }
  cxb::detail::write_zstd_frame(w, raw, kZstdLevel);
  return w.take();
}

Result<IndexGrid> decode_index_grid(std::span<const std::uint8_t> payload, const SceneDesc& scene) {
  ChunkDecoder d(cxb::kTagIndexGrid, payload);
  IndexGrid g;
  std::uint32_t packed_size = 0;
  const bool ok = d.u32(g.object, "object index") && d.u32(g.size[0], "grid size") && d.u32(g.size[1], "grid size") &&
                  d.u32(g.size[2], "grid size") && d.vec3(g.origin, "grid origin") && d.f32(g.voxel, "voxel size") &&
                  d.f32(g.ior_inside, "IOR inside") && d.f32(g.ior_outside, "IOR outside") && d.f32(g.blur, "blur") &&
                  d.f32(g.epsilon, "octree epsilon") && d.u32(packed_size, "grid data size");
  if (!ok) return d.error();
  if (g.object >= scene.objects.size() || !is_transparent(scene.objects[g.object].role)) {
    d.fail("object index " + std::to_string(g.object) + " is not a transparent object of the scene");
    return d.error();
  }
  const std::uint64_t voxels = std::uint64_t{g.size[0]} * g.size[1] * g.size[2];
  bool finite = std::isfinite(g.origin[0]) && std::isfinite(g.origin[1]) && std::isfinite(g.origin[2]);
  if (!finite || !(g.voxel > 0) || !std::isfinite(g.voxel) || g.ior_inside != scene.objects[g.object].material.ior ||
      !(g.ior_outside >= 1 && g.ior_outside <= kMaxIor) || !(g.blur >= 0 && g.blur <= 64) ||
      !(g.epsilon >= 0 && g.epsilon <= kMaxIor)) {
    d.fail("origin, voxel size, indices, blur or epsilon out of range or not the object's");
    return d.error();
  }
  if (g.size[0] == 0 || g.size[1] == 0 || g.size[2] == 0 || voxels > kMaxIndexGridVoxels) {
    d.fail("grid of " + std::to_string(g.size[0]) + " x " + std::to_string(g.size[1]) + " x " + std::to_string(g.size[2]) +
           " voxels is empty or above the limit of " + std::to_string(kMaxIndexGridVoxels));
    return d.error();
  }
  std::span<const std::uint8_t> packed;
  if (!d.span(packed, packed_size, "grid data") || !d.finish()) return d.error();
  const std::size_t n = static_cast<std::size_t>(voxels);
  if (3 * n > kMaxRatio * (packed.size() + 64)) {
    d.fail("grid data expands more than 65536:1");
    return d.error();
  }
  std::vector<std::uint8_t> raw;
  if (!cxb::detail::zstd_decompress_exact(d, packed, 3 * n, "grid data", std::to_string(n) + " voxels", raw)) {
    return d.error();
  }
  g.coverage.resize(n);
  g.level.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    g.coverage[v] = static_cast<std::uint16_t>(raw[v] | raw[n + v] << 8);
    g.level[v] = raw[2 * n + v];
    if (g.level[v] > kMaxOctreeLevel) {
      d.fail("voxel " + std::to_string(v) + " has octree level " + std::to_string(g.level[v]) + ", above 15");
      return d.error();
    }
  }
  return g;
}

}  // namespace caustix
