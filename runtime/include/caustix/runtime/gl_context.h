#pragma once
// A headless OpenGL 4.5 core context through EGL, with no window system:
// Mesa's surfaceless platform (llvmpipe, no X server) first, then the EGL
// device platform (NVIDIA GPUs without a display). Rendering goes to FBOs.

#include <memory>
#include <string>

#include "caustix/common/status.h"

namespace caustix::runtime {

class HeadlessContext {
 public:
  // Creates and makes current a context of at least `major.minor` core.
  static Result<std::unique_ptr<HeadlessContext>> create(int major = 4, int minor = 5);
  ~HeadlessContext();
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;

  // "llvmpipe (LLVM 15.0.6, 256 bits) / Mesa 23.x, OpenGL 4.5 core": for
  // naming the renderer beside every timing.
  std::string description() const;

 private:
  HeadlessContext() = default;
  void* display_ = nullptr;
  void* context_ = nullptr;
};

// GL_RENDERER and GL_VERSION of the current context.
std::string current_renderer_description();

}  // namespace caustix::runtime
