#include "readback.h"

#include <algorithm>

namespace caustix::runtime::gl {

ReadbackRing::~ReadbackRing() { release(); }

void ReadbackRing::release() {
  for (Slot& s : slots_) {
    if (s.fence) glDeleteSync(s.fence);
    s = Slot{};
  }
  if (mapped_) glUnmapNamedBuffer(buffer_.get());
  mapped_ = nullptr;
  buffer_ = Buffer();
  open_ = -1;
}

void ReadbackRing::reserve(std::size_t slot_bytes) {
  if (slot_bytes == slot_bytes_ && mapped_) return;
  release();
  slot_bytes_ = std::max<std::size_t>(slot_bytes, 4);
  buffer_ = make_buffer();
  const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  const auto size = static_cast<GLsizeiptr>(slot_bytes_ * kSlots);
  glNamedBufferStorage(buffer_.get(), size, nullptr, flags);
  mapped_ = static_cast<const std::uint8_t*>(glMapNamedBufferRange(buffer_.get(), 0, size, flags));
}

bool ReadbackRing::begin() {
  open_ = -1;
  if (!mapped_) return false;
  for (int i = 0; i < kSlots; ++i) {
    if (!slots_[static_cast<std::size_t>(i)].fence) {
      open_ = i;
      return true;
    }
  }
  return false;
}

void ReadbackRing::copy(GLuint src, GLintptr src_offset, std::size_t offset, GLsizeiptr size) const {
  if (open_ < 0 || size <= 0 || offset + static_cast<std::size_t>(size) > slot_bytes_) return;
  glCopyNamedBufferSubData(src, buffer_.get(), src_offset, static_cast<GLintptr>(static_cast<std::size_t>(open_) * slot_bytes_ + offset), size);
}

void ReadbackRing::end(std::uint64_t tag) {
  if (open_ < 0) return;
  Slot& s = slots_[static_cast<std::size_t>(open_)];
  // Shader writes before the copies become visible to the mapping with the fence.
  glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
  s.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  s.tag = tag;
  s.order = next_order_++;
  open_ = -1;
  // A fence signals only once the commands before it are submitted.
  glFlush();
}

int ReadbackRing::poll(const std::function<void(std::uint64_t, const std::uint8_t*)>& read) {
  std::array<int, kSlots> done{};
  int n = 0;
  for (int i = 0; i < kSlots; ++i) {
    const Slot& s = slots_[static_cast<std::size_t>(i)];
    if (!s.fence) continue;
    GLint status = GL_UNSIGNALED;
    glGetSynciv(s.fence, GL_SYNC_STATUS, 1, nullptr, &status);
    if (status == GL_SIGNALED) done[static_cast<std::size_t>(n++)] = i;
  }
  std::sort(done.begin(), done.begin() + n,
            [&](int a, int b) { return slots_[static_cast<std::size_t>(a)].order < slots_[static_cast<std::size_t>(b)].order; });
  for (int k = 0; k < n; ++k) {
    Slot& s = slots_[static_cast<std::size_t>(done[static_cast<std::size_t>(k)])];
    read(s.tag, mapped_ + static_cast<std::size_t>(done[static_cast<std::size_t>(k)]) * slot_bytes_);
    glDeleteSync(s.fence);
    s = Slot{};
  }
  return n;
}

void ReadbackRing::wait() const {
  for (const Slot& s : slots_) {
    if (!s.fence) continue;
    while (glClientWaitSync(s.fence, GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000) == GL_TIMEOUT_EXPIRED) {
    }
  }
}

bool ReadbackRing::pending() const {
  return std::any_of(slots_.begin(), slots_.end(), [](const Slot& s) { return s.fence != nullptr; });
}

}  // namespace caustix::runtime::gl
