#include "pass_timer.h"

#include <string>

namespace caustix::runtime::gl {

namespace {
// The pipeline-statistics targets a pass is counted by, in GpuPassTime's
// order.
constexpr std::array<GLenum, 4> kStatisticTargets = {GL_VERTEX_SHADER_INVOCATIONS_ARB, GL_PRIMITIVES_SUBMITTED_ARB,
                                                     GL_FRAGMENT_SHADER_INVOCATIONS_ARB, GL_COMPUTE_SHADER_INVOCATIONS_ARB};
}  // namespace

void PassTimer::set_enabled(bool on, bool statistics) {
  enabled_ = on;
  statistics_ = on && statistics && epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
}

void PassTimer::begin_frame(std::uint64_t frame) {
  collect();
  current_ = -1;
  if (!enabled_) return;
  for (int i = 0; i < kFrames; ++i) {
    Frame& f = frames_[static_cast<std::size_t>(i)];
    if (f.pending) continue;
    // Pending from now: a frame with no pass (everything reused) arrives
    // too, with no times.
    f = Frame{frame, true, true, {}, std::move(f.queries), 0, statistics_, std::move(f.stats), 0};
    current_ = i;
    return;
  }
}

void PassTimer::begin(const char* name, PassKind kind) {
  if (current_ < 0) return;
  Frame& f = frames_[static_cast<std::size_t>(current_)];
  while (f.queries.size() < f.used + 2) f.queries.push_back(make_query(GL_TIMESTAMP));
  f.passes.push_back(Pass{name, kind, f.used, f.stats_used});
  glQueryCounter(f.queries[f.used].get(), GL_TIMESTAMP);
  f.used += 2;
  if (!f.statistics) return;
  end_statistics();
  if (f.stats.size() <= f.stats_used) {
    std::array<Query, kStatistics> q;
    // Named, not created: Mesa's glCreateQueries refuses the statistics
    // targets (GL_INVALID_ENUM); glBeginQuery gives a named one its type.
    for (Query& query : q) {
      GLuint id = 0;
      glGenQueries(1, &id);
      query = Query(id);
    }
    f.stats.push_back(std::move(q));
  }
  for (int k = 0; k < kStatistics; ++k) {
    glBeginQuery(kStatisticTargets[static_cast<std::size_t>(k)], f.stats[f.stats_used][static_cast<std::size_t>(k)].get());
  }
  ++f.stats_used;
  counting_ = true;
}

void PassTimer::end_statistics() {
  if (!counting_) return;
  for (GLenum target : kStatisticTargets) glEndQuery(target);
  counting_ = false;
}

void PassTimer::end() {
  if (current_ < 0) return;
  Frame& f = frames_[static_cast<std::size_t>(current_)];
  if (f.passes.empty()) return;
  glQueryCounter(f.queries[f.passes.back().query + 1].get(), GL_TIMESTAMP);
  end_statistics();
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
    for (std::size_t q = 0; q < f.stats_used && ready; ++q) {
      for (const Query& query : f.stats[q]) {
        GLint available = GL_FALSE;
        glGetQueryObjectiv(query.get(), GL_QUERY_RESULT_AVAILABLE, &available);
        ready = ready && available == GL_TRUE;
      }
    }
    if (!ready) continue;
    f.pending = false;
    if (newest && newest->frame > f.frame) continue;
    // Sum a frame's passes by name and kind, in the order they first ran.
    GpuTimes t;
    t.frame = f.frame;
    t.statistics = f.statistics;
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
      if (f.statistics) {
        std::array<GLuint64, kStatistics> n{};
        for (int k = 0; k < kStatistics; ++k) {
          glGetQueryObjectui64v(f.stats[p.stats][static_cast<std::size_t>(k)].get(), GL_QUERY_RESULT_NO_WAIT, &n[static_cast<std::size_t>(k)]);
        }
        same->vertex_invocations += n[0];
        same->primitives += n[1];
        same->fragment_invocations += n[2];
        same->compute_invocations += n[3];
      }
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
