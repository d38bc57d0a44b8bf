#pragma once
// The runtime's GL call counter, built with CAUSTIX_COUNT_GL_CALLS (a CMake
// option, off by default; scripts/test.sh and the frame-cost benchmarks
// turn it on): every OpenGL call the runtime's own sources make then goes
// through a counting wrapper, so Engine::stats() can say what a frame
// costs the application in calls, draws, dispatches and, above all,
// GPU -> CPU synchronisations (a read-back of a buffer, texture or query
// result, glFinish, a fence wait): the calls that stall the pipeline.
//
// How: the build force-includes the generated gl_counted.h into every
// runtime source (runtime/CMakeLists.txt, cmake/CountGlCalls.cmake). It
// redefines each of libepoxy's `#define glFoo epoxy_glFoo` as a call
// through Counted<>::call (a tally, then epoxy's pointer), except the
// functions below, whose kind depends on their arguments. A call counts
// only while a Counting scope is alive on the calling thread (the Engine
// opens one in each of its public calls), so the application's own GL
// calls, and the runtime's outside an engine call, cost one branch.
// Nothing here changes what GL does. Without the option only the tally
// and its scopes exist, the tally stays zero and the sources call
// libepoxy directly.

#include <epoxy/gl.h>

#include <cstdint>

#if defined(CAUSTIX_COUNT_GL_CALLS) && CAUSTIX_COUNT_GL_CALLS
#define CAUSTIX_GL_COUNTING_BUILT 1
#else
#define CAUSTIX_GL_COUNTING_BUILT 0
#endif

namespace caustix::runtime::gl {

// What a frame's calls cost; the counters only grow.
struct CallTally {
  std::uint64_t calls = 0;       // every GL call
  std::uint64_t draws = 0;       // glDraw* and glMultiDraw* (clears are not draws)
  std::uint64_t dispatches = 0;  // glDispatchCompute*
  // GPU -> CPU synchronisations: buffer read-backs (glGet*BufferSubData,
  // a synchronised map), texture and pixel read-backs into client memory
  // (not into a pixel-pack buffer: that copy stays on the GPU), query
  // results asked with GL_QUERY_RESULT (not _AVAILABLE or _NO_WAIT),
  // glFinish, and glClientWaitSync with a non-zero timeout.
  std::uint64_t syncs = 0;
  std::uint64_t upload_bytes = 0;  // glBufferSubData / glNamedBufferSubData
};

enum class CallKind : std::uint8_t { kCall, kDraw, kDispatch, kSync };

// The calling thread's tally, or null.
inline thread_local CallTally* t_tally = nullptr;

inline void tally(CallKind k) {
  CallTally* t = t_tally;
  if (!t) return;
  ++t->calls;
  if (k == CallKind::kDraw) ++t->draws;
  if (k == CallKind::kDispatch) ++t->dispatches;
  if (k == CallKind::kSync) ++t->syncs;
}

// Counts into `t` while alive (scopes nest: the innermost wins).
class Counting {
 public:
  explicit Counting(CallTally& t) : previous_(t_tally) { t_tally = &t; }
  ~Counting() { t_tally = previous_; }
  Counting(const Counting&) = delete;
  Counting& operator=(const Counting&) = delete;

 private:
  CallTally* previous_;
};

inline constexpr bool kCountingBuilt = CAUSTIX_GL_COUNTING_BUILT;

#if CAUSTIX_GL_COUNTING_BUILT
// The counting wrapper of libepoxy's pointer *Slot (gl_counted.h).
template <auto* Slot, CallKind K, typename F>
struct Counted;
template <auto* Slot, CallKind K, typename R, typename... A>
struct Counted<Slot, K, R (*)(A...)> {
  static R call(A... a) {
    tally(K);
    return (*Slot)(a...);
  }
};

// ---- calls whose kind depends on their arguments or on bound state ----

// A read-back into client memory waits for the GPU; into a pixel-pack
// buffer it is a GPU copy.
inline void tally_pixels() {
  if (!t_tally) return;
  GLint pack = 0;
  epoxy_glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack);
  tally(pack != 0 ? CallKind::kCall : CallKind::kSync);
}
inline void tally_query_result(GLenum pname) {
  if (!t_tally) return;
  GLint query_buffer = 0;
  if (pname == GL_QUERY_RESULT) epoxy_glGetIntegerv(GL_QUERY_BUFFER_BINDING, &query_buffer);
  tally(pname == GL_QUERY_RESULT && query_buffer == 0 ? CallKind::kSync : CallKind::kCall);
}
inline void tally_upload(GLsizeiptr size) {
  tally(CallKind::kCall);
  if (t_tally && size > 0) t_tally->upload_bytes += static_cast<std::uint64_t>(size);
}

inline void counted_glReadPixels(GLint x, GLint y, GLsizei w, GLsizei h, GLenum f, GLenum t, void* p) {
  tally_pixels();
  epoxy_glReadPixels(x, y, w, h, f, t, p);
}
inline void counted_glReadnPixels(GLint x, GLint y, GLsizei w, GLsizei h, GLenum f, GLenum t, GLsizei n, void* p) {
  tally_pixels();
  epoxy_glReadnPixels(x, y, w, h, f, t, n, p);
}
inline void counted_glGetTexImage(GLenum target, GLint level, GLenum f, GLenum t, void* p) {
  tally_pixels();
  epoxy_glGetTexImage(target, level, f, t, p);
}
inline void counted_glGetTextureImage(GLuint tex, GLint level, GLenum f, GLenum t, GLsizei n, void* p) {
  tally_pixels();
  epoxy_glGetTextureImage(tex, level, f, t, n, p);
}
inline void counted_glGetTextureSubImage(GLuint tex, GLint level, GLint x, GLint y, GLint z, GLsizei w, GLsizei h, GLsizei d, GLenum f,
                                         GLenum t, GLsizei n, void* p) {
  tally_pixels();
  epoxy_glGetTextureSubImage(tex, level, x, y, z, w, h, d, f, t, n, p);
}
inline void counted_glGetQueryObjectiv(GLuint id, GLenum pname, GLint* p) {
  tally_query_result(pname);
  epoxy_glGetQueryObjectiv(id, pname, p);
}
inline void counted_glGetQueryObjectuiv(GLuint id, GLenum pname, GLuint* p) {
  tally_query_result(pname);
  epoxy_glGetQueryObjectuiv(id, pname, p);
}
inline void counted_glGetQueryObjecti64v(GLuint id, GLenum pname, GLint64* p) {
  tally_query_result(pname);
  epoxy_glGetQueryObjecti64v(id, pname, p);
}
inline void counted_glGetQueryObjectui64v(GLuint id, GLenum pname, GLuint64* p) {
  tally_query_result(pname);
  epoxy_glGetQueryObjectui64v(id, pname, p);
}
// Mapping waits for the GPU's pending writes unless told not to; a
// persistent mapping is made once, when the buffer is new.
inline void* counted_glMapNamedBufferRange(GLuint b, GLintptr offset, GLsizeiptr length, GLbitfield access) {
  tally((access & (GL_MAP_UNSYNCHRONIZED_BIT | GL_MAP_PERSISTENT_BIT)) ? CallKind::kCall : CallKind::kSync);
  return epoxy_glMapNamedBufferRange(b, offset, length, access);
}
inline void* counted_glMapBufferRange(GLenum target, GLintptr offset, GLsizeiptr length, GLbitfield access) {
  tally((access & (GL_MAP_UNSYNCHRONIZED_BIT | GL_MAP_PERSISTENT_BIT)) ? CallKind::kCall : CallKind::kSync);
  return epoxy_glMapBufferRange(target, offset, length, access);
}
// A wait with timeout 0 only polls.
inline GLenum counted_glClientWaitSync(GLsync s, GLbitfield flags, GLuint64 timeout) {
  tally(timeout == 0 ? CallKind::kCall : CallKind::kSync);
  return epoxy_glClientWaitSync(s, flags, timeout);
}
inline void counted_glNamedBufferSubData(GLuint b, GLintptr offset, GLsizeiptr size, const void* data) {
  tally_upload(size);
  epoxy_glNamedBufferSubData(b, offset, size, data);
}
inline void counted_glBufferSubData(GLenum target, GLintptr offset, GLsizeiptr size, const void* data) {
  tally_upload(size);
  epoxy_glBufferSubData(target, offset, size, data);
}

#endif  // CAUSTIX_GL_COUNTING_BUILT

}  // namespace caustix::runtime::gl

#if CAUSTIX_GL_COUNTING_BUILT
// The generator (cmake/CountGlCalls.cmake) skips the names defined here.
#undef glReadPixels
#define glReadPixels ::caustix::runtime::gl::counted_glReadPixels
#undef glReadnPixels
#define glReadnPixels ::caustix::runtime::gl::counted_glReadnPixels
#undef glGetTexImage
#define glGetTexImage ::caustix::runtime::gl::counted_glGetTexImage
#undef glGetTextureImage
#define glGetTextureImage ::caustix::runtime::gl::counted_glGetTextureImage
#undef glGetTextureSubImage
#define glGetTextureSubImage ::caustix::runtime::gl::counted_glGetTextureSubImage
#undef glGetQueryObjectiv
#define glGetQueryObjectiv ::caustix::runtime::gl::counted_glGetQueryObjectiv
#undef glGetQueryObjectuiv
#define glGetQueryObjectuiv ::caustix::runtime::gl::counted_glGetQueryObjectuiv
#undef glGetQueryObjecti64v
#define glGetQueryObjecti64v ::caustix::runtime::gl::counted_glGetQueryObjecti64v
#undef glGetQueryObjectui64v
#define glGetQueryObjectui64v ::caustix::runtime::gl::counted_glGetQueryObjectui64v
#undef glMapNamedBufferRange
#define glMapNamedBufferRange ::caustix::runtime::gl::counted_glMapNamedBufferRange
#undef glMapBufferRange
#define glMapBufferRange ::caustix::runtime::gl::counted_glMapBufferRange
#undef glClientWaitSync
#define glClientWaitSync ::caustix::runtime::gl::counted_glClientWaitSync
#undef glNamedBufferSubData
#define glNamedBufferSubData ::caustix::runtime::gl::counted_glNamedBufferSubData
#undef glBufferSubData
#define glBufferSubData ::caustix::runtime::gl::counted_glBufferSubData
#endif  // CAUSTIX_GL_COUNTING_BUILT
