#pragma once
// The runtime's GL renderer. Needs a current OpenGL 4.5 core context
// (HeadlessContext, or a GLFW window's). Creates only what the loaded scene
// needs: mesh buffers, a shadow map per light kind present, the water grid if
// the scene has water.
//
// A frame: receivers (ambient, then one additive pass per light with its
// shadow map), the animated water surface on top, into a linear float HDR
// target. present() tone-maps it to a display framebuffer; read_hdr() and
// read_display() return its pixels.

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/scene_loader.h"

namespace caustix::runtime {

struct FrameParams {
  Camera camera;
  float time = 0.0f;  // seconds, drives the waves
  int width = 640;
  int height = 480;
};

// The sky's linear colour: the beauty image's background.
inline constexpr float kSkyColor[3] = {0.42f, 0.58f, 0.78f};

class Renderer {
 public:
  static Result<std::unique_ptr<Renderer>> create(const RuntimeScene& scene);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  Status render(const FrameParams& frame);
  // Tone-mapped display image into `framebuffer` (0: the window).
  void present(unsigned framebuffer, int width, int height);

  // Pixels of the last frame, top row first: linear RGBA float, and
  // tone-mapped sRGB RGBA8.
  std::vector<float> read_hdr();
  std::vector<std::uint8_t> read_display();

  // The scene's camera, or one that frames the scene's bounds.
  Camera default_camera() const;
  glm::vec3 bounds_min() const;
  glm::vec3 bounds_max() const;

 private:
  Renderer();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::runtime
