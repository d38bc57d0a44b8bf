#pragma once
// The water grid on the GPU (Tipprasert 2006 §4.3): positions and normals
// recomputed by a compute shader each frame, from the scene's wave list
// (analytic normals) or from heights the application supplies (central
// differences), in SSBOs that the caustics passes and the surface's own
// drawing read. Internal to the runtime.

#include <cstdint>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "gl_objects.h"

namespace caustix::runtime {

class WaterSurface {
 public:
  static Result<WaterSurface> create(const Water& water);
  // Brings the surface to `time` (the waves) or to the heights set last.
  // Work happens only when the surface changes: new heights, a new time
  // while some wave moves, a new amplitude scale, back to the waves
  // (a still pool costs nothing). Returns whether it changed.
  bool update(float time);
  // Bumped whenever update() changes the surface: what the light side's
  // products of this water depend on.
  std::uint64_t version() const { return version_; }
  void set_amplitude_scale(float scale) { amplitude_scale_ = scale; }

  // The application's heights (displacements above the rest level, one per
  // grid vertex, row-major along x): from the CPU, from a GL buffer at a
  // byte offset, or from an R32F texture; the caller has checked sizes.
  // update() uses them from then on, until use_waves().
  void set_heights(const float* heights);
  void copy_heights_from_buffer(GLuint buffer, GLintptr offset);
  void copy_heights_from_texture(GLuint texture);
  void use_waves() {
    if (use_heights_) heights_dirty_ = true;
    use_heights_ = false;
  }

  // SSBO bindings used by the shaders: 0 positions, 1 normals, 2 indices.
  void bind_buffers() const;
  void draw() const;  // triangles, vertex pulling from the buffers

  // The grid's vertex positions and normals (vec4 each, row-major along x).
  GLuint positions_buffer() const { return positions_.get(); }
  GLuint normals_buffer() const { return normals_.get(); }
  std::uint32_t vertex_count() const { return vertices_; }
  std::uint32_t triangle_count() const { return triangles_; }
  const Water& water() const { return water_; }
  // Positions, normals, indices, the wave list and the heights.
  std::uint64_t gpu_bytes() const { return std::uint64_t{36} * vertices_ + std::uint64_t{12} * triangles_ + wave_bytes_; }

 private:
  Water water_;
  gl::Program update_, from_heights_;
  gl::Buffer positions_, normals_, indices_, waves_, heights_;
  bool use_heights_ = false;
  bool heights_dirty_ = true;  // new heights, or a switch between heights and waves
  bool moving_waves_ = false;  // some wave has amplitude and speed: the surface changes with time
  float last_time_ = 0.0f, last_scale_ = 0.0f;
  std::uint64_t version_ = 0;
  gl::VertexArray vao_;
  std::uint32_t vertices_ = 0, triangles_ = 0;
  std::uint64_t wave_bytes_ = 0;
  float amplitude_scale_ = 1.0f;
};

}  // namespace caustix::runtime
