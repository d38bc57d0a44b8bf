#include "caustix/bake/depth_profile.h"

#include "caustix/formats/slicing.h"

namespace caustix::bake {

void build_depth_profile(LevelMap& m, const SlicingOptions& o, std::string* warning) {
  const double h = 2.0 * m.frame.half[1];
  // Pixel-density histogram over L depth levels (fig. 4-19).
  m.histogram.assign(o.levels, 0);
  for (std::uint16_t q : m.depth) {
    if (q == kEmptyDepth) continue;
    ++m.histogram[std::min<std::uint64_t>(o.levels - 1, std::uint64_t{q} * o.levels / kDepthQuantum)];
  }
  m.sub_boxes = find_sub_boxes(m.histogram);
  m.uniform_planes = uniform_planes(h, o.planes);
  m.planes_requested = o.planes;
  const double asked = o.epsilon.value_or(h / (2.0 * o.planes));
  double used = asked;
  m.smart_planes = smart_planes(h, o.levels, m.sub_boxes, asked, &used);
  if (used != asked && warning) {
    *warning = "epsilon " + std::to_string(asked) + " m would need more than " + std::to_string(kMaxPlanes) +
               " planes; capped at " + std::to_string(kMaxPlanes) + " (epsilon raised to " + std::to_string(used) + " m)";
  }
  m.epsilon = static_cast<float>(used);
  m.slicing = o.slicing;
}

}  // namespace caustix::bake
