// The interactive water (runtime/include/caustix/runtime/water_sim.h;
// docs/water-simulation.md) against the wave equation it integrates:
// - a standing wave's period and its damping rate (the discrete
//   eigenvalues of the flux-form Laplacian, to 0.3 % of the amplitude);
// - a ripple's front running at c;
// - an hour of undamped water: energy bounded, volume conserved, finite;
// - a body pushing the water: the water's volume follows the body's
//   submerged volume (the mesh's own, by the divergence theorem);
// - bad options and arguments refused by name.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bake_fixture.h"
#include "caustix/runtime/engine.h"
#include "caustix/runtime/water_sim.h"
#include "gl_fixture.h"

namespace caustix {
namespace {

using runtime::WaterGrid;
using runtime::WaterSimOptions;
using runtime::WaterSimulation;

class WaterSim : public test::GlTest {};

std::unique_ptr<WaterSimulation> make(const WaterGrid& grid, const WaterSimOptions& options) {
  auto sim = WaterSimulation::create(grid, options);
  EXPECT_TRUE(sim.ok()) << sim.error().message;
  return sim.ok() ? std::move(*sim) : nullptr;
}

// A channel of n x 4 vertices, dx = 1/32 m: the walls sit half a spacing
// beyond the end vertices (no flux across the border), so its length is n dx.
WaterGrid channel(std::uint32_t n) {
  const float dx = 1.0f / 32;
  return WaterGrid{n, 4, 0.0f, 0.0f, dx * static_cast<float>(n - 1), 3 * dx, 0.0f};
}

// The first standing mode of the channel, h_i = A cos(pi (i + 1/2) / n), is
// an eigenvector of the flux-form Laplacian; in the continuum it oscillates
// with omega = pi c / L. At a quarter period it crosses zero, at a half it
// is -A (times exp(-gamma t / 2) with damping).
TEST_F(WaterSim, StandingWaveHasTheWaveEquationsPeriodAndDamping) {
  const std::uint32_t n = 128;
  const float amplitude = 0.01f, c = 1.0f;
  const double length = n / 32.0, omega = std::numbers::pi * c / length;
  for (const float damping : {0.0f, 0.5f}) {
    SCOPED_TRACE("damping " + std::to_string(damping));
    WaterSimOptions o;
    o.wave_speed = c;
    o.damping = damping;
    o.short_wave_damping = 0;
    o.max_substeps = 100000;
    auto sim = make(channel(n), o);
    ASSERT_TRUE(sim);
    std::vector<float> h(std::size_t{n} * 4);
    auto mode = [&](std::size_t k) { return std::cos(std::numbers::pi * (static_cast<double>(k % n) + 0.5) / n); };
    for (std::size_t k = 0; k < h.size(); ++k) h[k] = amplitude * static_cast<float>(mode(k));
    ASSERT_TRUE(sim->set_heights(h).ok());
    // Damped: omega_d = sqrt(omega^2 - gamma^2 / 4).
    const double omega_d = std::sqrt(omega * omega - 0.25 * damping * damping);
    const double quarter = 0.5 * std::numbers::pi / omega_d;
    // The mode's coefficient at time t: projection on the mode.
    auto coefficient = [&] {
      const std::vector<float> now = sim->read_heights();
      double num = 0, den = 0;
      for (std::size_t k = 0; k < now.size(); ++k) {
        num += now[k] * mode(k);
        den += mode(k) * mode(k);
      }
      return num / den;
    };
    // The quarter period comes a little later than pi / (2 omega_d) with
    // damping (the phase of e^(-gamma t/2) cos(omega_d t) + its sine term
    // from v(0) = 0); what stays exact is the half period's extreme.
    // Semi-implicit Euler lags the continuum's phase by omega dt / 2 (its
    // heights live at whole steps, its velocities half a step later): 0.6 %
    // of A here, in the tolerance at the quarter period (where the phase
    // shows linearly); a wave speed 0.5 % off would still fail it.
    ASSERT_TRUE(sim->step(static_cast<float>(quarter)).ok());
    const double dt = o.courant / 32.0 / c;
    const double expected_quarter = amplitude * std::exp(-0.5 * damping * quarter) * (0.5 * damping / omega_d);
    EXPECT_NEAR(coefficient(), expected_quarter, (0.5 * omega * dt + 0.002) * amplitude);
    ASSERT_TRUE(sim->step(static_cast<float>(quarter)).ok());
    const double expected_half = -amplitude * std::exp(-0.5 * damping * 2 * quarter);
    EXPECT_NEAR(coefficient(), expected_half, 0.003 * amplitude);
    EXPECT_NEAR(sim->stats().time, 2 * quarter, 1e-4);
  }
}

// Short-wave damping (WaterSimOptions::short_wave_damping): the channel's
// shortest standing mode, cos(pi (n - 1)(i + 1/2) / n) (two spacings), loses
// energy at 2 x rate (amplitude at rate x sin^2(pi (n - 1) / 2n) ~ rate);
// the longest mode (wavelength 2 n spacings) keeps all but
// 2 rate sin^2(pi / 2n) t of it.
TEST_F(WaterSim, ShortWaveDampingTakesTheShortestWavesAtItsRate) {
  const std::uint32_t n = 64;
  for (const std::uint32_t m : {n - 1, 1u}) {
    WaterSimOptions o;
    o.wave_speed = 1.0f;
    o.damping = 0.0f;
    o.short_wave_damping = 4.0f;
    o.max_substeps = 100000;
    auto sim = make(channel(n), o);
    ASSERT_TRUE(sim);
    std::vector<float> h(std::size_t{n} * 4);
    for (std::size_t k = 0; k < h.size(); ++k) {
      h[k] = 0.01f * static_cast<float>(std::cos(std::numbers::pi * m * (static_cast<double>(k % n) + 0.5) / n));
    }
    ASSERT_TRUE(sim->set_heights(h).ok());
    ASSERT_TRUE(sim->step(1e-3f).ok());
    const double e0 = sim->stats().energy;
    ASSERT_TRUE(sim->step(0.5f).ok());
    const double t = sim->stats().time - 1e-3;
    const double s2 = std::pow(std::sin(std::numbers::pi * m / (2.0 * n)), 2);
    // The diffusion is explicit: each substep dt scales the mode's heights
    // by 1 - dt nu lambda (nu lambda = 2 rate s2), a little more than
    // e^(-dt nu lambda) (4 % at these steps); the energy follows at that rate.
    const double dt = t / static_cast<double>(sim->stats().substeps - 1);
    const double rate = -std::log(1 - dt * 2 * o.short_wave_damping * s2) / dt;
    SCOPED_TRACE("mode " + std::to_string(m));
    EXPECT_NEAR(std::log(sim->stats().energy / e0), -rate * t, 0.05 * 2 * o.short_wave_damping * t);
  }
}

// A ripple at the centre of a 6 m basin: after t its leading front (the
// farthest vertex moved by more than 1 % of the ripple's amplitude) is at
// R + c t, to within two grid spacings (the raised cosine's foot and the
// grid's dispersion). Nothing has reached the walls yet.
TEST_F(WaterSim, RippleFrontRunsAtTheWaveSpeed) {
  const std::uint32_t n = 193;
  const float half = 3.0f, dx = 2 * half / (n - 1);
  WaterSimOptions o;
  o.wave_speed = 0.6f;
  o.damping = 0.0f;
  o.short_wave_damping = 0;
  o.max_substeps = 100000;
  auto sim = make(WaterGrid{n, n, -half, -half, half, half, 1.0f}, o);
  ASSERT_TRUE(sim);
  const float radius = 0.3f, amplitude = 0.02f;
  ASSERT_TRUE(sim->add_ripple(0, 0, radius, amplitude).ok());
  const double v0 = sim->stats().volume;
  EXPECT_LT(std::abs(v0), 0.01 * amplitude * std::numbers::pi * radius * radius) << "a ripple adds no water";
  for (const float t : {1.0f, 2.0f, 3.0f}) {
    ASSERT_TRUE(sim->step(t - static_cast<float>(sim->stats().time)).ok());
    const std::vector<float> h = sim->read_heights();
    double front = 0;
    for (std::uint32_t j = 0; j < n; ++j) {
      for (std::uint32_t i = 0; i < n; ++i) {
        if (std::abs(h[std::size_t{j} * n + i]) > 0.01f * amplitude) {
          front = std::max(front, double{std::hypot(-half + i * dx, -half + j * dx)});
        }
      }
    }
    SCOPED_TRACE("t = " + std::to_string(t));
    EXPECT_NEAR(front, radius + o.wave_speed * t, 2.0 * dx);
    EXPECT_NEAR(sim->stats().volume, v0, 1e-6);
  }
}

// An hour of undamped water (360 steps of 10 s, 68 000 substeps at Courant
// number 0.5): the scheme's invariant (WaterSimStats) stays constant to
// 0.1 % (float rounding over 68 000 steps), the energy stays within the
// bounds the invariant puts on it (a factor 1 -+ c dt sqrt(2) / dx at most,
// here 1 -+ 0.71: it trades energy with the half-step lag, and must not grow
// beyond), the volume is conserved and every value stays finite. Then, with
// damping, the energy falls as exp(-gamma t).
// Cost: its 68 000 substeps, each a compute pass on llvmpipe.
TEST_F(WaterSim, AnHourOfUndampedWaterStaysBoundedAndDampingDecaysIt) {
  const std::uint32_t n = 64;
  WaterSimOptions o;
  o.damping = 0.0f;
  o.short_wave_damping = 0;
  o.max_substeps = 100000;
  auto sim = make(WaterGrid{n, n, -2, -2, 2, 2, 2}, o);
  ASSERT_TRUE(sim);
  ASSERT_TRUE(sim->add_ripple(0.3f, -0.2f, 0.35f, 0.02f).ok());
  ASSERT_TRUE(sim->add_ripple(-1.1f, 0.8f, 0.2f, -0.01f).ok());
  // One whole substep first: the invariant is that of the substep size
  // (the one every later step() uses).
  ASSERT_TRUE(sim->step(o.courant * (4.0f / (n - 1)) / o.wave_speed).ok());
  ASSERT_EQ(sim->stats().substeps, 1u);
  const runtime::WaterSimStats start = sim->stats();
  ASSERT_GT(start.invariant, 0);
  const double bound = o.courant * std::sqrt(2.0);
  double lo = 1e30, hi = 0, drift = 0;
  for (int minute = 1; minute <= 60; ++minute) {
    for (int k = 0; k < 6; ++k) ASSERT_TRUE(sim->step(10.0f).ok());
    const runtime::WaterSimStats st = sim->stats();
    ASSERT_TRUE(st.finite) << "minute " << minute;
    lo = std::min(lo, st.energy / start.invariant);
    hi = std::max(hi, st.energy / start.invariant);
    drift = std::max(drift, std::abs(st.invariant / start.invariant - 1));
    // Float rounding of h += dt v lets the mean level wander: under 10 um
    // over the 16 m^2 pool in the hour.
    EXPECT_NEAR(st.volume, start.volume, 16 * 10e-6) << "minute " << minute;
  }
  const runtime::WaterSimStats end = sim->stats();
  ::testing::Test::RecordProperty("energy_min_ratio", std::to_string(lo));
  ::testing::Test::RecordProperty("energy_max_ratio", std::to_string(hi));
  ::testing::Test::RecordProperty("invariant_drift", std::to_string(drift));
  std::printf("hour: energy / invariant in [%.4f, %.4f], invariant drift %.2e, substeps %llu\n", lo, hi, drift,
              static_cast<unsigned long long>(end.substeps));
  EXPECT_NEAR(end.time, 3600.0, 0.5);
  EXPECT_LT(drift, 1e-3);
  EXPECT_GT(lo, 1 / (1 + bound));
  EXPECT_LT(hi, 1 / (1 - bound));
  EXPECT_LT(hi / lo, 1.1) << "no growth: within 10 % all hour";
  EXPECT_LT(end.max_abs_height, 0.03);

  o.damping = 0.3f;
  ASSERT_TRUE(sim->set_options(o).ok());
  const double e0 = end.energy;
  ASSERT_TRUE(sim->step(10.0f).ok());
  const double ratio = sim->stats().energy / e0;
  EXPECT_NEAR(std::log(ratio), -0.3 * 10.0, 0.15) << "energy ratio " << ratio;
}

// The divergence theorem: a closed mesh's volume from its triangles.
double mesh_volume(const TriangleMesh& m, float scale) {
  double v = 0;
  for (const auto& t : m.triangles) {
    const glm::dvec3 a(m.positions[t[0]][0], m.positions[t[0]][1], m.positions[t[0]][2]);
    const glm::dvec3 b(m.positions[t[1]][0], m.positions[t[1]][1], m.positions[t[1]][2]);
    const glm::dvec3 c(m.positions[t[2]][0], m.positions[t[2]][1], m.positions[t[2]][2]);
    v += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return v * scale * scale * scale;
}

Mat4f placed(float scale, float y, float x = 0) {
  Mat4f t{};
  t[0] = t[5] = t[10] = scale;
  t[12] = x;
  t[13] = y;
  t[15] = 1;
  return t;
}

// thesis_sphere's sphere (radius 0.6) lowered from above the water (level
// 2) to half submerged, then fully, then moved sideways: the water's volume
// follows its submerged volume, to 1 % (the columns sample the sphere at
// the grid's 3 cm spacing).
TEST_F(WaterSim, ABodyPushesTheWaterByItsSubmergedVolume) {
  auto loaded = test::bake_and_load(std::string(CAUSTIX_SOURCE_DIR) + "/assets/scenes/thesis_sphere.json");
  ASSERT_TRUE(loaded);
  auto engine = runtime::Engine::create(*loaded);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  runtime::Engine& e = **engine;
  std::uint32_t sphere = 0;
  while (sphere < e.scene().objects.size() && e.scene().objects[sphere].name != "sphere") ++sphere;
  ASSERT_LT(sphere, e.scene().objects.size());
  const double volume = mesh_volume(loaded->meshes[e.scene().objects[sphere].mesh_index], 0.6f);
  ASSERT_NEAR(volume, 4.0 / 3.0 * std::numbers::pi * 0.216, 0.05 * volume);  // a tessellated sphere of radius 0.6

  WaterSimOptions o;
  o.damping = 0.0f;
  auto sim = make(*e.water_grid(), o);
  ASSERT_TRUE(sim);
  const std::uint32_t bodies[] = {sphere};
  ASSERT_TRUE(e.set_object_transform(sphere, placed(0.6f, 3.0f)).ok());  // bottom at 2.4: dry
  ASSERT_TRUE(sim->push(e, bodies).ok());
  EXPECT_EQ(sim->stats().volume, 0.0) << "the first push only records";
  ASSERT_TRUE(sim->push(e, bodies).ok());
  EXPECT_EQ(sim->stats().volume, 0.0) << "a body above the water pushes nothing";

  ASSERT_TRUE(e.set_object_transform(sphere, placed(0.6f, 2.0f)).ok());  // half under
  ASSERT_TRUE(sim->push(e, bodies).ok());
  EXPECT_NEAR(sim->stats().volume, 0.5 * volume, 0.01 * volume);
  ASSERT_TRUE(e.set_object_transform(sphere, placed(0.6f, 0.6f)).ok());  // under
  ASSERT_TRUE(sim->push(e, bodies).ok());
  EXPECT_NEAR(sim->stats().volume, volume, 0.01 * volume);
  const double max_h = sim->stats().max_abs_height;
  EXPECT_NEAR(max_h, 1.2, 0.05) << "the water over the sphere's axis has risen by its submerged length, the diameter";
  ASSERT_TRUE(sim->step(0.5f).ok());
  ASSERT_TRUE(e.set_object_transform(sphere, placed(0.6f, 0.6f, 0.5f)).ok());  // sideways, still under
  ASSERT_TRUE(sim->push(e, bodies).ok());
  EXPECT_NEAR(sim->stats().volume, volume, 0.01 * volume);
}

// The engine takes the heights (apply): flat simulated water lights a patch
// of floor evenly (relative spread < 1 %); a ripple dropped over it makes
// caustics there (spread > 10 %).
TEST_F(WaterSim, TheEnginesCausticsFollowTheSimulatedWater) {
  auto renderer = test::bake_and_create(std::string(CAUSTIX_SOURCE_DIR) + "/assets/scenes/thesis_sphere.json");
  ASSERT_TRUE(renderer);
  runtime::Engine& e = renderer->engine();
  auto sim = make(*e.water_grid(), {});
  ASSERT_TRUE(sim);
  auto spread = [&] {
    sample::IrradianceRequest req;
    req.receiver = "floor";
    req.x0 = 0.9f, req.z0 = 0.9f, req.x1 = 1.9f, req.z1 = 1.9f;
    req.width = req.height = 64;
    req.pixel_samples = 1;
    auto img = renderer->render_irradiance(req);
    EXPECT_TRUE(img.ok()) << img.error().message;
    double sum = 0, sum2 = 0;
    const std::size_t n = img->rgb.size() / 3;
    for (std::size_t k = 0; k < n; ++k) {
      sum += img->rgb[3 * k + 1];
      sum2 += double{img->rgb[3 * k + 1]} * img->rgb[3 * k + 1];
    }
    const double mean = sum / n;
    return std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean;
  };
  ASSERT_TRUE(sim->apply(e).ok());
  const double flat = spread();
  ASSERT_TRUE(sim->add_ripple(1.4f, 1.4f, 0.3f, 0.02f).ok());
  ASSERT_TRUE(sim->step(0.3f).ok());
  ASSERT_TRUE(sim->apply(e).ok());
  const double rippled = spread();
  ::testing::Test::RecordProperty("flat_spread", std::to_string(flat));
  ::testing::Test::RecordProperty("rippled_spread", std::to_string(rippled));
  EXPECT_LT(flat, 0.01);
  EXPECT_GT(rippled, 0.10);
}

TEST_F(WaterSim, BadOptionsAndArgumentsAreRefusedByName) {
  const WaterGrid grid{16, 16, -1, -1, 1, 1, 0};
  auto refused = [&](WaterSimOptions o, const char* name) {
    auto sim = WaterSimulation::create(grid, o);
    ASSERT_FALSE(sim.ok()) << name;
    EXPECT_EQ(sim.error().code, ErrorCode::kUsage);
    EXPECT_NE(sim.error().message.find(name), std::string::npos) << sim.error().message;
  };
  WaterSimOptions o;
  o.wave_speed = 0;
  refused(o, "wave_speed");
  o = {};
  o.wave_speed = std::nanf("");
  refused(o, "wave_speed");
  o = {};
  o.damping = -1;
  refused(o, "damping");
  o = {};
  o.courant = 0.8f;
  refused(o, "courant");
  o = {};
  o.short_wave_damping = 11;
  refused(o, "short_wave_damping");
  o = {};
  o.max_substeps = 0;
  refused(o, "max_substeps");
  EXPECT_FALSE(WaterSimulation::create(WaterGrid{1, 16, -1, -1, 1, 1, 0}).ok());
  EXPECT_FALSE(WaterSimulation::create(WaterGrid{16, 16, 1, -1, 1, 1, 0}).ok());

  auto sim = make(grid, {});
  ASSERT_TRUE(sim);
  EXPECT_FALSE(sim->step(-1).ok());
  EXPECT_FALSE(sim->step(std::nanf("")).ok());
  EXPECT_FALSE(sim->step(11).ok());
  EXPECT_FALSE(sim->add_ripple(0, 0, 0, 0.1f).ok());
  EXPECT_FALSE(sim->add_ripple(0, 0, 0.1f, 2.0f).ok());
  std::vector<float> h(16 * 16, 0.0f);
  EXPECT_FALSE(sim->set_heights(std::span<const float>(h).first(10)).ok());
  h[7] = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(sim->set_heights(h).ok());
  const runtime::WaterSimStats st = sim->stats();
  EXPECT_TRUE(st.finite);
  EXPECT_EQ(st.volume, 0.0) << "refused calls change nothing";
  EXPECT_EQ(st.substeps, 0u);
}

}  // namespace
}  // namespace caustix
