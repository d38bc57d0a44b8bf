#pragma once
// The water grid on the GPU (seed 000 §4.3): positions and analytic normals
// recomputed by a compute shader each frame, in SSBOs that the caustics
// passes and the surface's own drawing read. Internal to the runtime.

#include <cstdint>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "gl_program.h"

namespace caustix::runtime {

class WaterSurface {
 public:
  static Result<WaterSurface> create(const Water& water);
  void update(float time);
  void set_amplitude_scale(float scale) { amplitude_scale_ = scale; }

  // SSBO bindings used by the shaders: 0 positions, 1 normals, 2 indices.
  void bind_buffers() const;
  void draw() const;  // triangles, vertex pulling from the buffers

  std::uint32_t vertex_count() const { return vertices_; }
  std::uint32_t triangle_count() const { return triangles_; }
  const Water& water() const { return water_; }

 private:
  Water water_;
  gl::Program update_;
  gl::Buffer positions_, normals_, indices_, waves_;
  gl::VertexArray vao_;
  std::uint32_t vertices_ = 0, triangles_ = 0;
  float amplitude_scale_ = 1.0f;
};

}  // namespace caustix::runtime
