#pragma once
// GPU -> CPU data without a stall: small GPU buffers (counters,
// sums) are copied on the GPU into a slot of a persistently mapped ring,
// a fence follows, and later frames poll the fences (never wait on them)
// and read the slots whose copies have landed, from mapped memory, with no
// GL call. What arrives is a few frames old; whoever needs it now must
// read it the slow way (and is counted a synchronisation, gl_calls.h).
// Internal to the runtime.

#include <epoxy/gl.h>

#include <array>
#include <cstdint>
#include <functional>

#include "gl_objects.h"

namespace caustix::runtime::gl {

class ReadbackRing {
 public:
  static constexpr int kSlots = 4;  // frames in flight before a frame's copy is skipped

  ReadbackRing() = default;
  ~ReadbackRing();
  ReadbackRing(const ReadbackRing&) = delete;
  ReadbackRing& operator=(const ReadbackRing&) = delete;

  // Slots of `slot_bytes` each (re-allocates, dropping what is in flight,
  // when the size changes).
  void reserve(std::size_t slot_bytes);
  std::size_t slot_bytes() const { return slot_bytes_; }

  // Opens the next free slot for this frame's copies; false (and the copies
  // below do nothing) when every slot is still in flight.
  bool begin();
  // GPU copy of `size` bytes of `src` at `src_offset` to `offset` in the open slot.
  void copy(GLuint src, GLintptr src_offset, std::size_t offset, GLsizeiptr size) const;
  // Closes the open slot with a fence; `tag` comes back with its data.
  void end(std::uint64_t tag);

  // Hands every slot whose fence has signalled, oldest first, to `read`
  // (the tag and the slot's bytes, valid during the call) and frees it.
  // Never waits. Returns how many arrived.
  int poll(const std::function<void(std::uint64_t, const std::uint8_t*)>& read);
  // Whether any slot is in flight.
  bool pending() const;
  // Waits until every slot in flight has landed (a synchronisation: for
  // tools and tests that want this frame's data now).
  void wait() const;

  std::uint64_t gpu_bytes() const { return std::uint64_t{slot_bytes_} * kSlots; }

 private:
  void release();
  struct Slot {
    GLsync fence = nullptr;
    std::uint64_t tag = 0;
    std::uint64_t order = 0;
  };
  Buffer buffer_;
  const std::uint8_t* mapped_ = nullptr;
  std::size_t slot_bytes_ = 0;
  std::array<Slot, kSlots> slots_{};
  int open_ = -1;
  std::uint64_t next_order_ = 0;
};

}  // namespace caustix::runtime::gl
