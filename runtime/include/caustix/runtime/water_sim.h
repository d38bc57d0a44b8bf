#pragma once
// caustix::runtime::WaterSimulation: interactive water for an Engine's pool
// (docs/water-simulation.md). A height field on the GPU, one
// height and one vertical velocity per vertex of the scene's water grid
// (Engine::water_grid()), advanced by the linear wave equation
//     dv/dt = c^2 lap(h) - gamma v,    dh/dt = v (+ nu lap(h), below)
// with semi-implicit (symplectic) Euler steps: v first, then h from the new
// v; damping implicit, v <- (v + dt c^2 lap h) / (1 + gamma dt). The
// Laplacian (nine-point isotropic on square cells, else five-point) is
// written as fluxes between neighbouring vertices, and beyond the grid's
// border it reads the mirror image across a wall half a spacing out
// (reflecting walls: the pool's), so the water's volume sum(h) dA is
// conserved up to float rounding. Each step() splits
// its dt into substeps at Courant number c dt / min(dx, dz) <= `courant`
// (the scheme is stable up to 1/sqrt(2)); without damping the discrete
// energy stays bounded (tests/water_sim_test.cpp runs an hour).
//
// Feeding the engine: after step(), apply(engine) hands the heights to
// Engine::set_water_heights_buffer, so the caustics, the surface and the
// light shafts all follow (a GPU copy, no read-back).
//
// Ripples and bodies: add_ripple() drops a volume-neutral disturbance;
// push() makes the named objects (closed meshes, at their current engine
// transforms) push the water: each vertex's column is rasterised from
// above and its submerged length (the object's extent along the column
// below the rest level) found from the mesh's upward and downward faces;
// where it grew since the last push() the water over it rises by as much
// (and sinks where it shrank), so sum(h) dA follows the submerged volume.
//
// Same context rules as the Engine (engine.h): the application's OpenGL
// 4.5 context current, every call restores the GL state it touches.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/runtime/engine.h"

namespace caustix::runtime {

struct WaterSimOptions {
  // Wave speed c, m/s (0.01 .. 100). Deep-water waves of wavelength L run at
  // sqrt(g L / 2 pi): 0.6 m/s is a 0.23 m ripple; shallow water of depth d
  // at sqrt(g d).
  float wave_speed = 0.6f;
  // gamma, 1/s (>= 0, < 1000): amplitudes decay as exp(-gamma t / 2).
  float damping = 0.3f;
  // 1/s (0 .. 10): how fast the shortest waves the grid holds die out.
  // The heights diffuse, dh/dt += nu lap(h) with nu = rate d^2 / 2 (d the
  // finer spacing), so a wave of wavelength L along the grid loses
  // amplitude at rate sin^2(pi d / L): all of `rate` at two spacings, 9.5 %
  // of it at ten, 0.4 % at fifty. Short waves are what the grid gets wrong
  // (they lag and leave a checkerboard wake); 0 keeps the scheme undamped.
  float short_wave_damping = 4.0f;
  // Substep size as a Courant number c dt / min(dx, dz), in (0, 0.7].
  float courant = 0.5f;
  // At most this many substeps per step() (1 .. 100000): a longer dt is cut
  // short (the water runs slower than real time) instead of going unstable.
  std::uint32_t max_substeps = 64;
};

struct WaterSimStats {
  double volume = 0;          // sum(h) dA, m^3 (relative to the rest level)
  // Per unit density, m^5/s^2: sum (v^2 + c^2 |grad h|^2) dA / 2, with
  // the step's own sum |grad h|^2 = -sum h lap(h). Semi-implicit Euler
  // trades it back and forth with the heights' half-step lag, by at most
  // c dt sqrt(lambda_max) / 2 of itself (lambda_max <= 8 / d^2: 0.71 at
  // Courant number 0.5); what it conserves exactly (without damping and
  // short-wave damping, up to float rounding) is
  //   invariant = energy - (dt / 2) sum v (K h) dA,  K h = -c^2 lap(h),
  // dt the last substep.
  double energy = 0;
  double invariant = 0;
  double max_abs_height = 0;  // m
  double time = 0;            // simulated seconds since creation or reset()
  std::uint64_t substeps = 0; // since creation or reset()
  bool finite = true;         // every height and velocity finite
};

class WaterSimulation {
 public:
  // A simulation over `grid` (Engine::water_grid()), at rest. kUsage for
  // options out of range or a grid with fewer than 2 x 2 vertices.
  static Result<std::unique_ptr<WaterSimulation>> create(const WaterGrid& grid, const WaterSimOptions& options = {});
  ~WaterSimulation();
  WaterSimulation(const WaterSimulation&) = delete;
  WaterSimulation& operator=(const WaterSimulation&) = delete;

  const WaterGrid& grid() const;
  const WaterSimOptions& options() const;
  // Same limits as create(); takes effect at the next step().
  Status set_options(const WaterSimOptions& options);

  // Advances dt seconds (0 .. 10), in substeps (see WaterSimOptions).
  Status step(float dt);
  // A ripple at (x, z): amplitude a (m, |a| <= 1) times a raised cosine of
  // radius r (m, > 0), minus its mean over the disc, so that no water is
  // added. Outside the grid it is clipped.
  Status add_ripple(float x, float z, float radius, float amplitude);
  // Objects `objects` of `engine` (its scene must be the grid's) push the
  // water by the change of their submerged volume per column since the
  // previous push() (the first call only records it). Objects above the
  // water push nothing; glass and opaque alike.
  Status push(const Engine& engine, std::span<const std::uint32_t> objects);
  // Heights (columns * rows finite floats, index j * columns + i) replace
  // the state's, velocities set to 0; and back to rest.
  Status set_heights(std::span<const float> heights);
  void reset();

  // Engine::set_water_heights_buffer(heights_buffer(), 0).
  Status apply(Engine& engine) const;
  // The GL buffer of the current heights (columns * rows floats), valid
  // until the next call of this object.
  unsigned heights_buffer() const;

  // Read back (a stall): volume, energy, extremes.
  WaterSimStats stats() const;
  std::vector<float> read_heights() const;
  std::vector<float> read_velocities() const;

 private:
  WaterSimulation();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::runtime
