#pragma once
// Pieces shared by the caustix-bench subcommands.

#include <chrono>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/sample/renderer.h"

namespace CLI {
class App;
}

namespace caustix::bench {

// A group of subcommands registered on caustix-bench's command line; the
// one the user chose runs.
class Modes {
 public:
  virtual ~Modes() = default;
  virtual bool chosen() const = 0;
  virtual int run() = 0;
};

// A table printed to stdout and, given a path, written as CSV too. Each row
// is flushed: long runs can be watched, and a failure keeps the rows so far.
class CsvOut {
 public:
  CsvOut(const std::string& path, const std::string& header);
  void row(const std::string& line);

 private:
  std::ofstream file_;
};

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
double median(std::vector<double> v);

// A baked scene loaded into a headless context and a renderer.
struct Session {
  std::unique_ptr<runtime::HeadlessContext> context;
  std::unique_ptr<sample::Renderer> renderer;
};
Result<Session> open_scene(const std::string& cxb);

struct FrameTimes {
  double median_ms = 0, min_ms = 0;
};
// Milliseconds per frame (render + glFinish) of `count` frames after
// `warmup` unmeasured ones, the animation advancing 1/30 s per frame; with
// move_light the first light turns 2 degrees about the vertical each frame
// (its level maps are re-derived on the GPU every frame). The camera is the
// scene's unless given; `look` is the water surface's, `glass_view` how the
// view through glass is found, `supersample` the antialiasing factor.
// With `gpu`, the engine's per-pass GPU times are on and every measured
// frame's (as they arrive: each the frame before) is appended. `still`
// keeps the time at 0 (a paused scene); `out_of_view` > 0 tells the engine
// the camera (FrameParams::out_of_view_interval).
Result<FrameTimes> time_frames(sample::Renderer& r, const runtime::CausticsOptions& co, int width, int height,
                               int warmup, int count, bool move_light = false, const runtime::WaterLook& look = {},
                               const std::optional<Camera>& camera = std::nullopt,
                               const runtime::GlassViewOptions& glass_view = {}, int supersample = 1,
                               std::vector<runtime::GpuTimes>* gpu = nullptr, bool still = false, std::uint32_t out_of_view = 0);

}  // namespace caustix::bench
