#pragma once
// The level-map stage of the bake (Tipprasert 2006 §4.2, §4.7.2): for every
// receiver and every light that refracted light can reach, the bounding
// frame, position and diffuse maps, depth profile and both plane sets; and
// a CGAL oriented bounding box per object for culling.
//
// Only what the scene requires: no level map for a scene without water (they
// serve water caustics; glass caustics use light-transport tables), for a
// receiver entirely above the water, for a light that cannot enter the water
// (travelling upward or parallel to it, or a point light under water with
// the receiver above it), for a receiver no refracted ray from the water
// grid can reach, or for one every sampled point of which is shadowed by
// other opaque objects. Each skip is reported with its reason.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "caustix/bake/depth_profile.h"
#include "caustix/common/mesh.h"
#include "caustix/common/status.h"
#include "caustix/formats/level_map.h"
#include "caustix/formats/scene.h"

namespace caustix::bake {

struct LevelMapOptions {
  SlicingOptions slicing;
  std::uint32_t map_size = 512;  // S: the position map is S x S
};

struct PairReport {
  std::uint32_t object = 0;
  std::uint32_t light = 0;
  bool baked = false;
  std::string reason;  // why it was skipped
  double ms_frame = 0, ms_position_map = 0, ms_profile = 0;
  std::uint64_t covered_texels = 0;
  double depth_precision_m = 0;
  std::string warning;
};

struct LevelMapStage {
  std::vector<LevelMap> maps;         // in (object, light) order
  std::vector<PairReport> pairs;      // every (receiver, light) pair, in order
  std::vector<ObjectBox> boxes;       // one per object
  double seconds_boxes = 0, seconds_shadow_tests = 0;
};

// `meshes[i]` is scene.meshes[i] decoded/imported (object space).
// `progress`, if set, is called with the fraction of the (receiver, light)
// pairs' reach tests and maps done, from the worker threads (possibly at
// once: the caller serialises).
Result<LevelMapStage> bake_level_maps(const SceneDesc& scene, const std::vector<TriangleMesh>& meshes,
                                      const LevelMapOptions& options, const std::function<void(double)>& progress = {});

}  // namespace caustix::bake
