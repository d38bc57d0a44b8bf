#pragma once
// caustix-bench tradeoff: one knob at a time (and the presets), bake the
// scene, render the reference's irradiance image and time beauty frames;
// one CSV row per setting with cost (bake time, .cxb bytes, ms per frame,
// GPU memory) and error against the reference image (docs/tradeoff.md).

#include <string>
#include <vector>

namespace caustix::bench {

struct TradeoffRequest {
  std::string scene_path;      // scene.json
  std::string reference_path;  // caustix-reference EXR: receiver, region, size and time come from it
  std::vector<std::string> knobs;  // empty: every knob that applies to the scene, then the presets
  std::string base = "balanced";   // preset every sweep starts from
  std::string csv;
  int frame_width = 640, frame_height = 480, warmup = 1, frames = 3;
  // Point samples per pixel and axis of the judged irradiance image. The
  // reference's pixels are exact box averages; sharp fold lines on a curved
  // receiver need 16 x 16 samples before the estimate stops moving
  // (thesis_teapot at accurate: 0.0247 at 4, 0.0196 at 8, 0.0183 at 16).
  int pixel_samples = 16;
};

// Names of the knobs, in sweep order ("presets" evaluates the presets).
std::vector<std::string> tradeoff_knobs();
int tradeoff(const TradeoffRequest& request);

}  // namespace caustix::bench
