// WaterSimulation (include/caustix/runtime/water_sim.h): the interactive
// height-field water. State: heights ping-ponged between two
// SSBOs (a substep reads one, writes the other) and velocities updated in
// place; two R32F targets hold the bodies' submerged lengths now and at the
// previous push().

#include "caustix/runtime/water_sim.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "caustix_shaders.h"
#include "gl_objects.h"
#include "gl_state.h"

namespace caustix::runtime {
namespace {

Error usage(const std::string& what) { return make_error(ErrorCode::kUsage, what); }

std::optional<std::string> check_options(const WaterSimOptions& o) {
  auto in = [](float v, float lo, float hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  if (!in(o.wave_speed, 0.01f, 100.0f)) return "wave_speed " + std::to_string(o.wave_speed) + " m/s is outside [0.01, 100]";
  if (!in(o.damping, 0.0f, 1000.0f) || o.damping >= 1000.0f) return "damping " + std::to_string(o.damping) + " 1/s is outside [0, 1000)";
  if (!in(o.courant, 0.0f, 0.7f) || o.courant <= 0.0f) return "courant " + std::to_string(o.courant) + " is outside (0, 0.7]";
  if (!in(o.short_wave_damping, 0.0f, 10.0f)) return "short_wave_damping " + std::to_string(o.short_wave_damping) + " 1/s is outside [0, 10]";
  if (o.max_substeps < 1 || o.max_substeps > 100000) return "max_substeps " + std::to_string(o.max_substeps) + " is outside [1, 100000]";
  return std::nullopt;
}

}  // namespace

struct WaterSimulation::Impl {
  WaterGrid grid;
  WaterSimOptions options;
  GLuint nx = 0, nz = 0;
  float dx = 0, dz = 0;
  gl::Program step, ripple, push, displace;
  gl::Buffer heights[2], velocities;
  int current = 0;  // heights[current] is the state
  gl::Texture lengths[2];
  gl::Framebuffer targets[2];
  int now = 0;      // lengths[now] is the latest push
  bool have_lengths = false;
  double time = 0;
  std::uint64_t substeps = 0;
  float last_dt = 0;  // the last substep (WaterSimStats::invariant)

  std::size_t count() const { return std::size_t{nx} * nz; }
  // Square cells (to 1 %) take the nine-point stencil (water_sim_step.comp).
  bool isotropic() const { return std::abs(dx / dz - 1.0f) < 0.01f; }
  float diffusion() const { return options.short_wave_damping * 0.5f * std::min(dx, dz) * std::min(dx, dz); }
  GLsizeiptr bytes() const { return static_cast<GLsizeiptr>(count() * 4); }
  void dispatch() const { glDispatchCompute((nx + 7) / 8, (nz + 7) / 8, 1); }
  gl::StateGuard guard() const { return gl::StateGuard({0, 1}); }
  std::vector<float> read(GLuint buffer) const {
    std::vector<float> out(count());
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buffer, 0, bytes(), out.data());
    return out;
  }
};

WaterSimulation::WaterSimulation() : impl_(std::make_unique<Impl>()) {}
WaterSimulation::~WaterSimulation() = default;

Result<std::unique_ptr<WaterSimulation>> WaterSimulation::create(const WaterGrid& grid, const WaterSimOptions& options) {
  if (grid.columns < 2 || grid.rows < 2 || grid.columns > 8192 || grid.rows > 8192) {
    return usage("WaterSimulation: a grid of " + std::to_string(grid.columns) + " x " + std::to_string(grid.rows) +
                 " vertices (2 .. 8192 each way are needed)");
  }
  if (!(grid.x1 > grid.x0) || !(grid.z1 > grid.z0) || !std::isfinite(grid.x1 - grid.x0) || !std::isfinite(grid.z1 - grid.z0)) {
    return usage("WaterSimulation: the grid's extent is empty or not finite");
  }
  if (auto bad = check_options(options)) return usage("WaterSimulation: " + *bad);
  GLint max_units = 0;
  glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &max_units);
  if (max_units == 0) return make_error(ErrorCode::kGraphics, "WaterSimulation: no current OpenGL context");

  std::unique_ptr<WaterSimulation> sim(new WaterSimulation());
  Impl& s = *sim->impl_;
  s.grid = grid;
  s.options = options;
  s.nx = grid.columns;
  s.nz = grid.rows;
  s.dx = (grid.x1 - grid.x0) / static_cast<float>(s.nx - 1);
  s.dz = (grid.z1 - grid.z0) / static_cast<float>(s.nz - 1);
  const gl::StateGuard guard = s.guard();
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs({{&s.step, "water_sim_step", shaders::k_water_sim_step_comp_glsl},
                                              {&s.ripple, "water_sim_ripple", shaders::k_water_sim_ripple_comp_glsl},
                                              {&s.push, "water_sim_push", shaders::k_water_sim_push_vert_glsl,
                                               shaders::k_water_sim_push_frag_glsl},
                                              {&s.displace, "water_sim_displace", shaders::k_water_sim_displace_comp_glsl}}));
  for (const gl::Program* p : {&s.step, &s.ripple, &s.displace}) glProgramUniform2ui(p->id(), p->loc("u_vertices"), s.nx, s.nz);
  s.step.set("u_inv_d2", glm::vec2(1.0f / (s.dx * s.dx), 1.0f / (s.dz * s.dz)));
  glProgramUniform1i(s.step.id(), s.step.loc("u_isotropic"), s.isotropic() ? 1 : 0);
  s.ripple.set("u_origin", glm::vec2(grid.x0, grid.z0));
  s.ripple.set("u_spacing", glm::vec2(s.dx, s.dz));
  s.push.set("u_extent", glm::vec4(grid.x0 - 0.5f * s.dx, grid.z0 - 0.5f * s.dz, grid.x1 + 0.5f * s.dx, grid.z1 + 0.5f * s.dz));
  s.push.set("u_level", grid.level);

  for (gl::Buffer* b : {&s.heights[0], &s.heights[1], &s.velocities}) {
    *b = gl::make_buffer();
    glNamedBufferStorage(b->get(), s.bytes(), nullptr, GL_DYNAMIC_STORAGE_BIT);
  }
  for (int i = 0; i < 2; ++i) {
    s.lengths[i] = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(s.lengths[i].get(), 1, GL_R32F, static_cast<GLsizei>(s.nx), static_cast<GLsizei>(s.nz));
    gl::set_sampling(s.lengths[i].get(), GL_NEAREST);
    s.targets[i] = gl::make_framebuffer();
    glNamedFramebufferTexture(s.targets[i].get(), GL_COLOR_ATTACHMENT0, s.lengths[i].get(), 0);
    if (glCheckNamedFramebufferStatus(s.targets[i].get(), GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      return make_error(ErrorCode::kGraphics, "WaterSimulation: an R32F target is not renderable on this context");
    }
  }
  sim->reset();
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("water simulation set-up"));
  return sim;
}

const WaterGrid& WaterSimulation::grid() const { return impl_->grid; }
const WaterSimOptions& WaterSimulation::options() const { return impl_->options; }

Status WaterSimulation::set_options(const WaterSimOptions& options) {
  if (auto bad = check_options(options)) return usage("WaterSimulation::set_options: " + *bad);
  impl_->options = options;
  return Status::success();
}

void WaterSimulation::reset() {
  Impl& s = *impl_;
  const float zero = 0.0f;
  for (const gl::Buffer* b : {&s.heights[0], &s.heights[1], &s.velocities}) {
    glClearNamedBufferData(b->get(), GL_R32F, GL_RED, GL_FLOAT, &zero);
  }
  s.current = 0;
  s.have_lengths = false;
  s.time = 0;
  s.substeps = 0;
}

Status WaterSimulation::set_heights(std::span<const float> heights) {
  Impl& s = *impl_;
  if (heights.size() != s.count()) {
    return usage("WaterSimulation::set_heights: " + std::to_string(heights.size()) + " heights for a grid of " +
                 std::to_string(s.count()) + " vertices");
  }
  for (std::size_t k = 0; k < heights.size(); ++k) {
    if (!std::isfinite(heights[k])) return usage("WaterSimulation::set_heights: height " + std::to_string(k) + " is not finite");
  }
  glNamedBufferSubData(s.heights[s.current].get(), 0, s.bytes(), heights.data());
  const float zero = 0.0f;
  glClearNamedBufferData(s.velocities.get(), GL_R32F, GL_RED, GL_FLOAT, &zero);
  return gl::check_gl("WaterSimulation::set_heights");
}

Status WaterSimulation::step(float dt) {
  Impl& s = *impl_;
  if (!std::isfinite(dt) || dt < 0.0f || dt > 10.0f) return usage("WaterSimulation::step: dt " + std::to_string(dt) + " s is outside [0, 10]");
  if (dt == 0.0f) return Status::success();
  const WaterSimOptions& o = s.options;
  // Courant number c dt / d <= courant on the finer spacing (the 2D
  // five-point scheme is stable up to 1/sqrt(2)).
  double max_dt = o.courant * std::min(s.dx, s.dz) / o.wave_speed;
  // The explicit diffusion is stable while dt nu 8 / d^2 <= 2: rate dt <= 1/2.
  if (o.short_wave_damping > 0.0f) max_dt = std::min(max_dt, 0.5 / o.short_wave_damping);
  const auto wanted = static_cast<std::uint64_t>(std::ceil(dt / max_dt));
  const std::uint32_t n = static_cast<std::uint32_t>(std::clamp<std::uint64_t>(wanted, 1, o.max_substeps));
  const float sub = static_cast<float>(std::min<double>(dt / static_cast<double>(n), max_dt));
  const gl::StateGuard guard = s.guard();
  s.step.use();
  s.step.set("u_dt", sub);
  s.step.set("u_c2", o.wave_speed * o.wave_speed);
  s.step.set("u_damping", o.damping);
  s.step.set("u_diffusion", s.diffusion());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, s.velocities.get());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  for (std::uint32_t i = 0; i < n; ++i) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, s.heights[s.current].get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, s.heights[1 - s.current].get());
    s.dispatch();
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    s.current = 1 - s.current;
  }
  s.time += static_cast<double>(n) * sub;
  s.last_dt = sub;
  s.substeps += n;
  return gl::check_gl("WaterSimulation::step");
}

Status WaterSimulation::add_ripple(float x, float z, float radius, float amplitude) {
  Impl& s = *impl_;
  if (!std::isfinite(x) || !std::isfinite(z)) return usage("WaterSimulation::add_ripple: the centre is not finite");
  if (!std::isfinite(radius) || radius <= 0.0f) return usage("WaterSimulation::add_ripple: radius " + std::to_string(radius) + " m is not > 0");
  if (!std::isfinite(amplitude) || std::abs(amplitude) > 1.0f) {
    return usage("WaterSimulation::add_ripple: amplitude " + std::to_string(amplitude) + " m is outside [-1, 1]");
  }
  const gl::StateGuard guard = s.guard();
  s.ripple.use();
  s.ripple.set("u_center", glm::vec2(x, z));
  s.ripple.set("u_radius", radius);
  s.ripple.set("u_amplitude", amplitude);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, s.heights[s.current].get());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  s.dispatch();
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  return gl::check_gl("WaterSimulation::add_ripple");
}

Status WaterSimulation::push(const Engine& engine, std::span<const std::uint32_t> objects) {
  Impl& s = *impl_;
  const auto grid = engine.water_grid();
  if (!grid || grid->columns != s.nx || grid->rows != s.nz || grid->x0 != s.grid.x0 || grid->x1 != s.grid.x1 ||
      grid->z0 != s.grid.z0 || grid->z1 != s.grid.z1) {
    return usage("WaterSimulation::push: the engine's water grid is not this simulation's");
  }
  const auto& scene_objects = engine.scene().objects;
  for (std::uint32_t i : objects) {
    if (i >= scene_objects.size()) return usage("WaterSimulation::push: no object " + std::to_string(i));
  }
  const gl::StateGuard guard = s.guard();
  const int target = s.have_lengths ? 1 - s.now : s.now;
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, s.targets[target].get());
  glViewport(0, 0, static_cast<GLsizei>(s.nx), static_cast<GLsizei>(s.nz));
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(s.targets[target].get(), GL_COLOR, 0, zero);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  s.push.use();
  for (std::uint32_t i : objects) {
    const glm::mat4 model = glm::make_mat4(scene_objects[i].transform.data());
    s.push.set("u_model", model);
    // The projection maps +x right and +z up on the target, a mirror of
    // the view from above: faces counter-clockwise seen from +y (upward,
    // outward-wound) come out clockwise, unless the transform mirrors too.
    glFrontFace(glm::determinant(glm::mat3(model)) < 0.0f ? GL_CCW : GL_CW);
    CAUSTIX_RETURN_IF_ERROR(engine.draw_object(i));
  }
  if (s.have_lengths) {
    s.displace.use();
    glBindTextureUnit(0, s.lengths[target].get());
    glBindTextureUnit(1, s.lengths[s.now].get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, s.heights[s.current].get());
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    s.dispatch();
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  s.now = target;
  s.have_lengths = true;
  return gl::check_gl("WaterSimulation::push");
}

Status WaterSimulation::apply(Engine& engine) const { return engine.set_water_heights_buffer(heights_buffer(), 0); }

unsigned WaterSimulation::heights_buffer() const { return impl_->heights[impl_->current].get(); }

std::vector<float> WaterSimulation::read_heights() const { return impl_->read(impl_->heights[impl_->current].get()); }
std::vector<float> WaterSimulation::read_velocities() const { return impl_->read(impl_->velocities.get()); }

WaterSimStats WaterSimulation::stats() const {
  const Impl& s = *impl_;
  const std::vector<float> h = read_heights(), v = read_velocities();
  WaterSimStats st;
  st.time = s.time;
  st.substeps = s.substeps;
  const double area = double{s.dx} * s.dz, c2 = double{s.options.wave_speed} * s.options.wave_speed;
  // The step's Laplacian (water_sim_step.comp), in double precision.
  auto h_at = [&](long i, long j) {
    i = std::clamp(i, 0L, static_cast<long>(s.nx) - 1);
    j = std::clamp(j, 0L, static_cast<long>(s.nz) - 1);
    return double{h[static_cast<std::size_t>(j) * s.nx + static_cast<std::size_t>(i)]};
  };
  const double inv_dx2 = 1.0 / (double{s.dx} * s.dx), inv_dz2 = 1.0 / (double{s.dz} * s.dz);
  auto laplacian = [&](long i, long j) {
    const double c = h_at(i, j);
    if (s.isotropic()) {
      const double edges = h_at(i + 1, j) + h_at(i - 1, j) + h_at(i, j + 1) + h_at(i, j - 1) - 4 * c;
      const double corners = h_at(i + 1, j + 1) + h_at(i - 1, j + 1) + h_at(i + 1, j - 1) + h_at(i - 1, j - 1) - 4 * c;
      return (4 * edges + corners) * std::sqrt(inv_dx2 * inv_dz2) / 6;
    }
    return (h_at(i + 1, j) + h_at(i - 1, j) - 2 * c) * inv_dx2 + (h_at(i, j + 1) + h_at(i, j - 1) - 2 * c) * inv_dz2;
  };
  // Energy: sum v^2 / 2 + c^2 |grad h|^2 / 2 with the discrete
  // sum |grad h|^2 = -sum h lap(h) (the Laplacian is symmetric).
  double kinetic = 0, potential = 0, volume = 0, cross = 0;
  for (GLuint j = 0; j < s.nz; ++j) {
    for (GLuint i = 0; i < s.nx; ++i) {
      const std::size_t k = std::size_t{j} * s.nx + i;
      st.finite = st.finite && std::isfinite(h[k]) && std::isfinite(v[k]);
      volume += h[k];
      kinetic += double{v[k]} * v[k];
      st.max_abs_height = std::max(st.max_abs_height, std::abs(double{h[k]}));
      const double lap = laplacian(i, j);
      potential -= h[k] * lap;
      cross += v[k] * (-c2 * lap);
    }
  }
  st.invariant = 0.5 * area * (kinetic + c2 * potential - double{s.last_dt} * cross);
  st.volume = volume * area;
  st.energy = 0.5 * area * (kinetic + c2 * potential);
  return st;
}

}  // namespace caustix::runtime
