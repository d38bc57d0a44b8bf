#pragma once
// Level maps (Tipprasert 2006 §4.2, §4.7.2) as stored in the .cxb: one per
// (receiver, light) pair that refracted light can reach. Each holds the
// bounding frame, the position map and diffuse map, the depth profile and
// both plane sets (uniform and smart). Also the per-object oriented bounding
// boxes used for culling. Layouts: formats/SPEC.md ("LMAP", "OBBS").
//
// Conventions (frame space): the frame's origin is the centre of the tight
// box; U, V, W are orthonormal and right-handed (W = U x V); V = -T points
// back toward the light, so light travels along -V. A point p has frame
// coordinates ((p - origin) . U, (p - origin) . V, (p - origin) . W), within
// [-half, +half]. The position map looks along -V: texel (row r, column c)
// is centred at u = -half.u + (c + 1/2) 2 half.u / S, w = -half.w +
// (r + 1/2) 2 half.w / S, and stores the normalised depth below the frame's
// top face, t = (half.v - v_hit) / (2 half.v), quantised to 16 bits.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/types.h"

namespace caustix {

struct SceneDesc;

struct BoundingFrame {
  std::array<double, 3> origin{};  // world; f64 keeps precision far from the world origin
  Vec3f u{1, 0, 0}, v{0, 1, 0}, w{0, 0, 1};
  Vec3f half{};                    // tight half-extents along U, V, W (metres)
  Vec3f symmetric_size{};          // thesis eq. 4-3: 2 max |coordinate| about the object origin
};

// On disk; never renumber.
enum class Slicing : std::uint8_t { kSmart = 1, kUniform = 2 };

struct ReferencePlane {
  float offset = 0;   // coordinate along V from the frame origin (metres)
  float epsilon = 0;  // acceptance half-width (eq. 4-15): offset - epsilon < v <= offset + epsilon
};

struct SubBox {
  std::uint32_t first_level = 0;  // inclusive; level 0 is nearest the light
  std::uint32_t last_level = 0;   // inclusive
};

inline constexpr std::uint16_t kEmptyDepth = 0xFFFF;
inline constexpr std::uint32_t kDepthQuantum = 0xFFFE;  // t = q / kDepthQuantum
inline constexpr std::uint32_t kMaxMapSize = 8192;
inline constexpr std::uint32_t kMaxDepthLevels = 65536;
inline constexpr std::uint32_t kMaxPlanes = 4097;  // 4096 uniform pieces give 4097 planes

struct LevelMap {
  std::uint32_t object = 0;  // index into SceneDesc::objects
  std::uint32_t light = 0;   // index into SceneDesc::lights
  BoundingFrame frame;
  std::uint32_t map_size = 0;
  std::vector<std::uint16_t> depth;   // map_size^2, row-major; kEmptyDepth where no surface
  std::vector<std::uint8_t> diffuse;  // map_size^2 * 3, linear albedo in 8 bits
  std::vector<std::uint32_t> histogram;  // texels per depth level (L = size)
  std::vector<SubBox> sub_boxes;         // groups of adjacent valid levels
  std::vector<ReferencePlane> uniform_planes;  // eq. 4-6..4-9
  std::vector<ReferencePlane> smart_planes;    // eq. 4-21, 4-22
  Slicing slicing = Slicing::kSmart;           // which set the runtime uses by default
  float epsilon = 0;                           // the acceptance threshold asked for (metres)
  std::uint32_t planes_requested = 0;          // n of the uniform slicing
};

// Oriented bounding box of an object in world space (CGAL), for culling.
struct ObjectBox {
  std::uint32_t object = 0;
  std::array<double, 3> center{};
  std::array<Vec3f, 3> axes{};  // orthonormal
  Vec3f half{};
};

std::vector<std::uint8_t> encode_level_map(const LevelMap& map);
std::vector<std::uint8_t> encode_object_boxes(const std::vector<ObjectBox>& boxes);

// Safe on hostile bytes (bounded decompression, every count and index
// checked against the scene); errors (kContainer) name the chunk and field.
Result<LevelMap> decode_level_map(std::span<const std::uint8_t> payload, const SceneDesc& scene);
Result<std::vector<ObjectBox>> decode_object_boxes(std::span<const std::uint8_t> payload, const SceneDesc& scene);

}  // namespace caustix
