#pragma once
// GPU time per pass: each pass of the engine's (a shadow map, a level-map
// cull, the glass's illumination draws...) is bracketed by two
// GL_TIMESTAMP queries, labelled compute or raster. With statistics on
// (and ARB_pipeline_statistics_query in the driver) the pass is also
// counted by four pipeline-statistics queries: vertex-shader invocations,
// primitives submitted, fragment-shader and compute-shader invocations --
// the work itself, which a machine without a GPU measures as well as one
// with. Queries of the last few frames stay in flight; a frame's results
// are read once every query of it is available (GL_QUERY_RESULT_AVAILABLE,
// then _NO_WAIT): never a stall, and the results are a frame or more old.
// Off until enabled: then a pass costs two glQueryCounter calls (and,
// with statistics, four glBeginQuery / glEndQuery pairs). Passes follow
// one another; a pass begun inside another ends the outer one's
// statistics there. The engine makes its timer current on the calling
// thread (Timing) for the length of each public call, and the effects
// mark their passes with TimedPass. Internal to the runtime.

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

  // `statistics` takes effect where the driver has the extension (the
  // context must be current).
  void set_enabled(bool on, bool statistics = false);
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
  static constexpr int kStatistics = 4;  // vertex, primitive, fragment, compute counts
  struct Pass {
    const char* name;
    PassKind kind;
    std::size_t query;  // its pair: queries[query], queries[query + 1]
    std::size_t stats;  // with statistics, its four: stats[stats ...]
  };
  struct Frame {
    std::uint64_t frame = 0;
    bool open = false, pending = false;
    std::vector<Pass> passes;
    std::vector<Query> queries;  // pooled; grows to the most passes a frame had
    std::size_t used = 0;
    bool statistics = false;  // its passes were counted
    std::vector<std::array<Query, kStatistics>> stats;  // pooled as `queries`
    std::size_t stats_used = 0;
  };
  void collect();
  void end_statistics();
  bool enabled_ = false, statistics_ = false;
  bool counting_ = false;  // a pass's statistics queries are active
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
