#include "water_surface.h"

#include <cstring>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "caustix_shaders.h"
#include "pass_timer.h"

namespace caustix::runtime {
namespace {

constexpr int kMaxWaves = 256;  // matches water_update.comp.glsl

struct WaveBlock {  // std140 layout of the Waves block
  glm::vec4 a[kMaxWaves];
  glm::vec4 b[kMaxWaves];
  glm::ivec4 count;
};

}  // namespace

Result<WaterSurface> WaterSurface::create(const Water& w) {
  WaterSurface s;
  s.water_ = w;
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs({{&s.update_, "water_update", shaders::k_water_update_comp_glsl},
                                              {&s.from_heights_, "water_heights", shaders::k_water_heights_comp_glsl}}));

  const std::uint32_t nx = w.cells[0], nz = w.cells[1];
  s.vertices_ = (nx + 1) * (nz + 1);
  s.triangles_ = 2 * nx * nz;
  std::vector<std::uint32_t> idx;
  idx.reserve(std::size_t{s.triangles_} * 3);
  for (std::uint32_t j = 0; j < nz; ++j) {
    for (std::uint32_t i = 0; i < nx; ++i) {
      const std::uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      idx.insert(idx.end(), {a, c, b, b, c, d});  // counter-clockwise seen from +y
    }
  }
  s.positions_ = gl::make_buffer();
  glNamedBufferStorage(s.positions_.get(), GLsizeiptr{16} * s.vertices_, nullptr, 0);
  s.normals_ = gl::make_buffer();
  glNamedBufferStorage(s.normals_.get(), GLsizeiptr{16} * s.vertices_, nullptr, 0);
  s.indices_ = gl::make_buffer();
  glNamedBufferStorage(s.indices_.get(), static_cast<GLsizeiptr>(idx.size() * 4), idx.data(), 0);
  s.vao_ = gl::make_vertex_array();
  glVertexArrayElementBuffer(s.vao_.get(), s.indices_.get());

  auto block = std::make_unique<WaveBlock>();
  std::memset(block.get(), 0, sizeof(WaveBlock));
  const std::size_t n = std::min<std::size_t>(w.waves.size(), kMaxWaves);
  for (std::size_t i = 0; i < n; ++i) {
    const Wave& wave = w.waves[i];
    const float k = 2.0f * 3.14159265358979f / wave.wavelength;
    block->a[i] = glm::vec4(wave.amplitude, k, wave.direction[0], wave.direction[1]);
    block->b[i] = glm::vec4(k * wave.speed, wave.phase, 0, 0);
  }
  block->count = glm::ivec4(static_cast<int>(n), 0, 0, 0);
  for (const Wave& wave : w.waves) s.moving_waves_ = s.moving_waves_ || (wave.amplitude != 0.0f && wave.speed != 0.0f);
  s.waves_ = gl::make_buffer();
  glNamedBufferStorage(s.waves_.get(), sizeof(WaveBlock), block.get(), 0);
  s.wave_bytes_ = sizeof(WaveBlock);
  s.heights_ = gl::make_buffer();
  glNamedBufferStorage(s.heights_.get(), GLsizeiptr{4} * s.vertices_, nullptr, GL_DYNAMIC_STORAGE_BIT);
  for (const gl::Program* p : {&s.update_, &s.from_heights_}) {
    glProgramUniform2ui(p->id(), p->loc("u_cells"), nx, nz);
    p->set("u_extent", glm::vec4(w.extent[0], w.extent[1], w.extent[2], w.extent[3]));
    p->set("u_level", w.level);
  }
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("water set-up"));
  return s;
}

void WaterSurface::bind_buffers() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, positions_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, normals_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, indices_.get());
}

void WaterSurface::set_heights(const float* heights) {
  glNamedBufferSubData(heights_.get(), 0, GLsizeiptr{4} * vertices_, heights);
  use_heights_ = heights_dirty_ = true;
}

void WaterSurface::copy_heights_from_buffer(GLuint buffer, GLintptr offset) {
  glCopyNamedBufferSubData(buffer, heights_.get(), offset, 0, GLsizeiptr{4} * vertices_);
  use_heights_ = heights_dirty_ = true;
}

void WaterSurface::copy_heights_from_texture(GLuint texture) {
  // Into the buffer through the pixel-pack binding: no CPU round trip.
  glBindBuffer(GL_PIXEL_PACK_BUFFER, heights_.get());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(texture, 0, GL_RED, GL_FLOAT, GLsizei{4} * static_cast<GLsizei>(vertices_), nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glMemoryBarrier(GL_PIXEL_BUFFER_BARRIER_BIT);
  use_heights_ = heights_dirty_ = true;
}

bool WaterSurface::update(float time) {
  if (use_heights_) {
    if (!heights_dirty_) return false;
    heights_dirty_ = false;
    ++version_;
    const gl::TimedPass timed("water: surface", gl::PassKind::kCompute);
    from_heights_.use();
    bind_buffers();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, heights_.get());
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);
    glDispatchCompute((vertices_ + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    return true;
  }
  // Without moving waves the surface is the same at every time.
  const float t = moving_waves_ ? time : 0.0f;
  if (!heights_dirty_ && version_ > 0 && t == last_time_ && amplitude_scale_ == last_scale_) return false;
  heights_dirty_ = false;
  last_time_ = t;
  last_scale_ = amplitude_scale_;
  ++version_;
  const gl::TimedPass timed("water: surface", gl::PassKind::kCompute);
  update_.use();
  update_.set("u_time", time);
  update_.set("u_amplitude_scale", amplitude_scale_);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, waves_.get());
  bind_buffers();
  glDispatchCompute((vertices_ + 63) / 64, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  return true;
}

void WaterSurface::draw() const {
  bind_buffers();
  glBindVertexArray(vao_.get());
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(triangles_ * 3), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace caustix::runtime
