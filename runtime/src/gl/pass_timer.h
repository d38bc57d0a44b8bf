#pragma once
// GPU time per pass (issue 44): each pass of the engine's (a shadow map, a
// level-map cull, the glass's illumination draws...) is bracketed by two
// GL_TIMESTAMP queries, labelled compute or raster. Queries of the last
// few frames stay in flight; a frame's times are read once every query of
// it is available (GL_QUERY_RESULT_AVAILABLE, then _NO_WAIT): never a
// stall, and the times are a frame or more old. Off until enabled: then a
// pass costs two glQueryCounter calls. The engine makes its timer current
// on the calling thread (Timing) for the length of each public call, and
// the effects mark their passes with TimedPass. Internal to the runtime.

#include <epoxy/gl.h>

#include <array>
#include <cstdint>
#include <vector>

#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"
#include "gl_objects.h"

namespace caustix::runtime::gl {

enum class PassKind : std::uint8_t { kCompute, kRaster };

class PassTimer {
 public:
  static constexpr int kFrames = 4;  // frames whose queries may be in flight

  void set_enabled(bool on) { enabled_ = on; }
  bool enabled() const { return enabled_; }
  // Opens frame `frame` for passes after collecting the frames whose
  // queries have all completed (never waiting). A frame whose slot is
  // still in flight kFrames later goes untimed.
  void begin_frame(std::uint64_t frame);
  void begin(const char* name, PassKind kind);
  void end();
  // The latest frame whose times arrived (collecting first).
  const GpuTimes& latest();

 private:
  struct Pass {
    const char* name;
    PassKind kind;
    std::size_t query;  // its pair: queries[query], queries[query + 1]
  };
  struct Frame {
    std::uint64_t frame = 0;
    bool open = false, pending = false;
    std::vector<Pass> passes;
    std::vector<Query> queries;  // pooled; grows to the most passes a frame had
    std::size_t used = 0;
  };
  void collect();
  bool enabled_ = false;
  std::array<Frame, kFrames> frames_{};
  int current_ = -1;
  GpuTimes latest_;
};

// The calling thread's timer, or null (while no engine call is running).
inline thread_local PassTimer* t_timer = nullptr;

// Makes `t` the calling thread's timer while alive.
class Timing {
 public:
  explicit Timing(PassTimer& t) : previous_(t_timer) { t_timer = &t; }
  ~Timing() { t_timer = previous_; }
  Timing(const Timing&) = delete;
  Timing& operator=(const Timing&) = delete;

 private:
  PassTimer* previous_;
};

// Times the GL commands issued while alive as one pass of the current
// timer's frame (nothing when there is none, or it is off).
class TimedPass {
 public:
  TimedPass(const char* name, PassKind kind) : timer_(t_timer && t_timer->enabled() ? t_timer : nullptr) {
    if (timer_) timer_->begin(name, kind);
  }
  ~TimedPass() {
    if (timer_) timer_->end();
  }
  TimedPass(const TimedPass&) = delete;
  TimedPass& operator=(const TimedPass&) = delete;

 private:
  PassTimer* timer_;
};

}  // namespace caustix::runtime::gl
