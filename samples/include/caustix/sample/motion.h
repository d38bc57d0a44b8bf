#pragma once
// Image stacks of a scene in motion, for judging whether the picture holds
// still as the light, the water or an object moves a little
// (caustix-bench temporal and the frame-to-frame tests; docs/temporal.md).
// Frame k is rendered with the motion advanced by k steps; the renderer's
// light and transforms are put back afterwards.

#include <array>
#include <string>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/sample/renderer.h"

namespace caustix::sample {

enum class MotionKind {
  kLight,   // the first light turns about the z axis
  kWater,   // the animation time advances
  kObject,  // an object moves along x
};

struct Motion {
  MotionKind kind = MotionKind::kLight;
  std::string object;  // kObject: the object's name
};

// `light` turned by `degrees` about the z axis: its direction (a spot's
// axis too) and a point light's position about the origin, so that what
// it focuses moves along x in irradiance and in-scatter images alike.
Light turned_about_z(Light light, double degrees);

struct StackRequest {
  std::string receiver;  // irradiance images of this receiver, unless
  bool inscatter = false;  // in-scatter images of the media
  // World rectangle: x0, z0, x1, z1 (in-scatter: x0, y0, x1, y1).
  std::array<float, 4> region{-1, -1, 1, 1};
  int frames = 12, size = 160, pixel_samples = 2;
  double time = 0;  // animation time of frame 0 (seconds)
  CausticsOptions caustics;
};

struct StackFrame {
  int width = 0, height = 0;
  std::vector<float> rgb;  // linear, as the request's image has it
};

// q.frames images, frame k with the motion at k * step (degrees for the
// light, seconds for the water, metres for an object). Errors: kUsage for
// a motion the scene cannot make (no light, no object of that name), and
// the renderer's own.
Result<std::vector<StackFrame>> render_stack(Renderer& renderer, const StackRequest& q, const Motion& motion, double step);

}  // namespace caustix::sample
