#pragma once
// The knobs of the water-caustics pass, switchable at run time. Every method
// produces the same thing, a caustics map per (receiver, light), so their
// images can be compared pixel for pixel.

#include <cstdint>
#include <optional>
#include <string>

#include "caustix/formats/scene.h"

namespace caustix::runtime {

enum class CausticsMethod {
  kLevelMap,    // level map with smart-sliced planes (seed 000 ch. 4, §4.7.2)
  kUniform,     // level map with the uniform planes (eq. 4-6..4-9)
  kVolumetric,  // the volumetric baseline: one slice image per plane (§5.2.1)
  kSplat,       // photon splatting (seed 001 ch. 8, GPU variant): photon texture -> points, additive
  kNone,        // no caustics: refraction and Fresnel through flat water only; glass casts a plain shadow
};

const char* to_string(CausticsMethod m);
std::optional<CausticsMethod> parse_method(const std::string& name);

struct CausticsOptions {
  CausticsMethod method = CausticsMethod::kLevelMap;
  std::optional<std::uint32_t> planes;  // re-slice with n pieces (uniform) / eps = h/(2n) (smart)
  std::optional<float> epsilon;         // re-slice smart planes with this eps (metres)
  std::uint32_t map_size = 512;         // caustics map S x S
  // Largest magnification of a beam's cross-section (A_w cos / A_d in
  // eq. 4-18): keeps folds where refracted rays cross finite.
  float max_magnification = 1.0e4f;
  // Beyond the thesis (§6.1): drop illumination volumes that miss the
  // frame, and draw each volume only through the planes the surface under
  // it needs. Off: every volume through every plane, as the thesis did.
  bool cull = true;
  // Photon splatting: the water is rasterised into a photons x photons
  // texture over the frame's window (plus a margin), one photon a texel.
  std::uint32_t photons = 1024;
  // Glass (seed 002 §4.2): virtual planes per target (the paper: 4; at most
  // 16) and the illumination-texture size (the paper: 512).
  std::uint32_t glass_planes = 4;
  std::uint32_t glass_map_size = 512;
};

// Sets the fields a bake preset records (RNDR chunk): map sizes, glass planes.
void apply_render_defaults(CausticsOptions& options, const RenderDefaults& render);
// The options a renderer starts from for this scene: the built-in defaults
// above, or the runtime defaults a bake preset recorded.
CausticsOptions default_caustics_options(const SceneDesc& scene);

// What the last frame's caustics pass did, per level map (for benchmarks).
struct CausticsStats {
  std::uint64_t water_triangles = 0;  // per light
  std::uint64_t volumes_drawn = 0;    // primitives drawn: (volume, plane) pairs, or volumes when not culling
  bool overflowed = false;            // a map's pair list was full (pieces missing)
  std::uint64_t volumes_total = 0;    // before culling, summed over maps
  std::uint64_t planes_drawn = 0;     // summed over maps
  std::uint64_t gpu_bytes = 0;        // caustics-pass allocations (maps, slices, buffers; glass tables and textures)
};

}  // namespace caustix::runtime
