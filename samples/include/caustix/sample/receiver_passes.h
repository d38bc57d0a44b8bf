#pragma once
// An application's two ways of lighting every receiver from every light
// (docs/embedding.md, "Deferred and multi-light renderers"), as
// a client of the public Engine API: a G-buffer of the receivers (world
// position with the object's index, world normal), then either
//   - per pair: for each light and receiver, Engine::bind(object, light)
//     and an additive forward draw calling caustix_irradiance() on the
//     G-buffer's depth (the per-receiver path), or
//   - deferred: Engine::bind_all() and one full-screen pass calling
//     caustix_irradiance_all() with the G-buffer's object index.
// Both write irradiance (W/m^2 x the lights' colours, summed) into one
// RGBA32F target. For tests and caustix-bench (cost and agreement).

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/runtime/engine.h"
#include "gl_objects.h"

namespace caustix::sample {

// The sample is a client of the runtime's public API and uses its names as
// they are (Engine, View, CausticsOptions, ...).
using namespace caustix::runtime;

class ReceiverPasses {
 public:
  static Result<std::unique_ptr<ReceiverPasses>> create(Engine& engine, int width, int height);

  // The receivers' G-buffer seen through `view_proj` (GL clip conventions).
  Status draw_gbuffer(const glm::mat4& view_proj);
  // The per-pair path into the target (after draw_gbuffer with the same
  // matrix). `level0`: the receivers' mipmapped caustics maps, glass
  // illumination textures and caustic maps (those with focus windows) are read at
  // level 0 only, as the table reads them (for comparing texel for texel;
  // it sets and restores their GL_TEXTURE_MAX_LEVEL).
  Status shade_per_pair(const glm::mat4& view_proj, bool level0 = false);
  // The deferred path into the target.
  Status shade_deferred();
  // Object `object` alone, lit through receiver `host`'s resources
  // (bind(host, light) for every light, added): how an object that is not
  // in the .cxb is lit (docs/embedding.md, "Objects that are not in the
  // .cxb"). Depth-tested against itself (a depth pre-pass), not the
  // G-buffer; pixels it does not cover keep alpha 0.
  Status shade_through(const glm::mat4& view_proj, std::uint32_t object, std::uint32_t host);

  // Read-backs (synchronising): the target's RGBA, and each pixel's object (-1: none).
  std::vector<float> read_irradiance() const;
  std::vector<int> read_objects() const;
  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t receivers() const { return receivers_.size(); }

 private:
  ReceiverPasses(Engine& engine, int width, int height);
  void begin_target(GLuint framebuffer) const;
  Engine& engine_;
  int width_, height_;
  std::vector<std::uint32_t> receivers_;
  gl::Program gbuffer_, forward_, deferred_;
  gl::Texture position_, normal_, depth_, color_;
  gl::Framebuffer gbuffer_fbo_, target_fbo_;
  gl::VertexArray empty_vao_;
};

}  // namespace caustix::sample
