#pragma once
// The water grid on the GPU (seed 000 §4.3): positions and normals
// recomputed by a compute shader each frame, from the scene's wave list
// (analytic normals) or from heights the application supplies (central
// differences), in SSBOs that the caustics passes and the surface's own
// drawing read. Internal to the runtime.

#include <cstdint>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/gl_objects.h"

namespace caustix::runtime {

class WaterSurface {
 public:
  static Result<WaterSurface> create(const Water& water);
  void update(float time);
  void set_amplitude_scale(float scale) { amplitude_scale_ = scale; }

  // The application's heights (displacements above the rest level, one per
  // grid vertex, row-major along x): from the CPU, from a GL buffer at a
  // byte offset, or from an R32F texture; the caller has checked sizes.
  // update() uses them from then on, until use_waves().
  void set_heights(const float* heights);
  void copy_heights_from_buffer(GLuint buffer, GLintptr offset);
  void copy_heights_from_texture(GLuint texture);
  void use_waves() { use_heights_ = false; }

  // SSBO bindings used by the shaders: 0 positions, 1 normals, 2 indices.
  void bind_buffers() const;
  void draw() const;  // triangles, vertex pulling from the buffers

  // The grid's vertex positions and normals (vec4 each, row-major along x).
  GLuint positions_buffer() const { return positions_.get(); }
  GLuint normals_buffer() const { return normals_.get(); }
  std::uint32_t vertex_count() const { return vertices_; }
  std::uint32_t triangle_count() const { return triangles_; }
  const Water& water() const { return water_; }

 private:
  Water water_;
  gl::Program update_, from_heights_;
  gl::Buffer positions_, normals_, indices_, waves_, heights_;
  bool use_heights_ = false;
  gl::VertexArray vao_;
  std::uint32_t vertices_ = 0, triangles_ = 0;
  float amplitude_scale_ = 1.0f;
};

}  // namespace caustix::runtime
