#include "pass_timer.h"

#include <string>

namespace caustix::runtime::gl {

void PassTimer::begin_frame(std::uint64_t frame) {
  collect();
  current_ = -1;
  if (!enabled_) return;
  for (int i = 0; i < kFrames; ++i) {
    Frame& f = frames_[static_cast<std::size_t>(i)];
    if (f.pending) continue;
    // Pending from now: a frame with no pass (everything reused) arrives
    // too, with no times.
    f = Frame{frame, true, true, {}, std::move(f.queries), 0};
    current_ = i;
    return;
  }
}

void PassTimer::begin(const char* name, PassKind kind) {
  if (current_ < 0) return;
  Frame& f = frames_[static_cast<std::size_t>(current_)];
  while (f.queries.size() < f.used + 2) f.queries.push_back(make_query(GL_TIMESTAMP));
  f.passes.push_back(Pass{name, kind, f.used});
  glQueryCounter(f.queries[f.used].get(), GL_TIMESTAMP);
  f.used += 2;
}

void PassTimer::end() {
  if (current_ < 0) return;
  Frame& f = frames_[static_cast<std::size_t>(current_)];
  if (f.passes.empty()) return;
  glQueryCounter(f.queries[f.passes.back().query + 1].get(), GL_TIMESTAMP);
}

void PassTimer::collect() {
  const Frame* newest = nullptr;
  for (Frame& f : frames_) {
    if (!f.pending || (current_ >= 0 && &f == &frames_[static_cast<std::size_t>(current_)])) continue;
    bool ready = true;
    for (std::size_t q = 0; q < f.used && ready; ++q) {
      GLint available = GL_FALSE;
      glGetQueryObjectiv(f.queries[q].get(), GL_QUERY_RESULT_AVAILABLE, &available);
      ready = available == GL_TRUE;
    }
    if (!ready) continue;
    f.pending = false;
    if (newest && newest->frame > f.frame) continue;
    // Sum a frame's passes by name and kind, in the order they first ran.
    GpuTimes t;
    t.frame = f.frame;
    for (const Pass& p : f.passes) {
      GLuint64 a = 0, b = 0;
      glGetQueryObjectui64v(f.queries[p.query].get(), GL_QUERY_RESULT_NO_WAIT, &a);
      glGetQueryObjectui64v(f.queries[p.query + 1].get(), GL_QUERY_RESULT_NO_WAIT, &b);
      const double ms = b > a ? static_cast<double>(b - a) * 1e-6 : 0.0;
      const bool compute = p.kind == PassKind::kCompute;
      GpuPassTime* same = nullptr;
      for (GpuPassTime& q : t.passes) {
        if (q.name == p.name && q.compute == compute) same = &q;
      }
      if (!same) {
        t.passes.push_back(GpuPassTime{p.name, compute, 0.0, 0});
        same = &t.passes.back();
      }
      same->ms += ms;
      ++same->count;
      (compute ? t.compute_ms : t.raster_ms) += ms;
    }
    if (t.frame >= latest_.frame) latest_ = std::move(t);
    newest = &f;
  }
}

const GpuTimes& PassTimer::latest() {
  collect();
  return latest_;
}

}  // namespace caustix::runtime::gl
