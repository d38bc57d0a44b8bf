// What a frame costs an application, counted on llvmpipe:
// no GPU -> CPU synchronisation once a scene has warmed up, nothing remade
// whose inputs did not change, lists that overflow say so and grow, the
// light side at a lower rate when asked, and the planes planned on the GPU
// after a re-derivation equal to the CPU's (formats/slicing.h).

#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bake_fixture.h"
#include "caustix/formats/slicing.h"
#include "gl_objects.h"
#include "caustix/sample/renderer.h"
#include "caustix_shaders.h"
#include "gl_fixture.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

using runtime::CausticsStats;
using sample::FrameParams;
using sample::Renderer;

class FrameCost : public test::GlTest {};

// stats().gl counts only in a build with CAUSTIX_COUNT_GL_CALLS (the
// README's test command has it): whether it counts must be what the build
// says.
bool gl_counted(const CausticsStats& st) {
  EXPECT_EQ(st.gl.counted, static_cast<bool>(CAUSTIX_TEST_GL_COUNTED));
  return st.gl.counted;
}
#define SKIP_UNLESS_GL_COUNTED() \
  if (!CAUSTIX_TEST_GL_COUNTED) GTEST_SKIP() << "built without CAUSTIX_COUNT_GL_CALLS: the runtime counts no GL call"

std::unique_ptr<Renderer> renderer_of(const nlohmann::json& j, const std::string& tag) {
  return test::bake_and_create(test::write_scene(j, tag));
}

FrameParams small_frame(Renderer& r, float time) {
  FrameParams f;
  f.camera = r.default_camera();
  f.time = time;
  f.width = 96;
  f.height = 64;
  f.caustics = runtime::default_caustics_options(r.scene());
  return f;
}

// The same passes at a fraction of the cost (what synchronises does not
// depend on sizes): small maps, few photons, two wavelengths.
FrameParams cheap_frame(Renderer& r, float time) {
  FrameParams f = small_frame(r, time);
  f.caustics.map_size = 128;
  f.caustics.glass_map_size = 128;
  f.caustics.photons = 128;
  f.caustics.wavelengths = 2;
  f.caustics.caustic_map.photons = 96;
  f.caustics.caustic_map.map_size = 128;
  f.caustics.volume.photons = 64;
  f.caustics.volume.grid = 24;
  return f;
}

// Frames 0 and 1 warm up; from frame 2 on, with the waves moving (and, if
// asked, the first light turning), no call of the engine's may wait for
// the GPU: update(), bind(), draw_water/glass/media, stats().
void expect_steady_frames_do_not_sync(Renderer& r, bool move_light) {
  for (int i = 0; i < 4; ++i) {
    if (move_light) {
      Light l = r.scene().lights[0];
      const float a = 0.02f * static_cast<float>(i);
      l.direction = {std::sin(a) * 0.3f, -1.0f, std::cos(a) * 0.3f};
      if (l.type == LightType::kPoint) l.position = {l.position[0] + 0.01f * static_cast<float>(i), l.position[1], l.position[2]};
      ASSERT_TRUE(r.set_light(0, l).ok());
    }
    ASSERT_TRUE(r.render(cheap_frame(r, 0.1f * static_cast<float>(i))).ok());
    const CausticsStats st = r.caustics_stats();
    EXPECT_TRUE(gl_counted(st));
    if (i >= 2) {
      EXPECT_EQ(st.gl.syncs, 0u) << "frame " << i << (move_light ? " (light moving)" : "");
    }
    EXPECT_GT(st.gl.calls, 0u);
  }
}

// Cost: five scenes, each with eight whole frames (water moving, then the
// light turning too) through every method the scene uses.
TEST_F(FrameCost, SteadyFramesNeverWaitForTheGpu) {
  SKIP_UNLESS_GL_COUNTED();
  for (const char* name : {"thesis_teapot", "glass_ball", "mirror_ring", "fog_ball", "dispersive_pool"}) {
    SCOPED_TRACE(name);
    nlohmann::json j = test::canonical_scene(std::string(name) == "dispersive_pool" ? "wavy_pool" : name);
    if (std::string(name) == "dispersive_pool") {
      j["water"]["dispersion"] = 3.0;
      j["water"]["waves"][0]["speed"] = 0.5;  // moving: every frame remakes the caustics
    }
    // A coarser water grid: the same passes and read-backs with a sixteenth
    // of the primitives, whose vertex work is most of llvmpipe's frame.
    if (j.contains("water")) j["water"]["grid"]["cells"] = {32, 32};
    auto r = renderer_of(j, std::string("frame_cost_") + name);
    ASSERT_TRUE(r);
    expect_steady_frames_do_not_sync(*r, false);
    expect_steady_frames_do_not_sync(*r, true);
  }
}

TEST_F(FrameCost, AStillLightAndStillGlassAreNotRemade) {
  auto r = renderer_of(test::canonical_scene("glass_ball"), "frame_cost_still");
  ASSERT_TRUE(r);
  ASSERT_TRUE(r->render(small_frame(*r, 0.0f)).ok());
  CausticsStats first = r->caustics_stats();
  EXPECT_EQ(first.work.glass.updated, 1u);
  EXPECT_EQ(first.work.shadow_maps.updated, 1u);
  const std::vector<float> before = r->read_hdr();
  ASSERT_TRUE(r->render(small_frame(*r, 1.0f)).ok());
  const CausticsStats still = r->caustics_stats();
  EXPECT_EQ(still.work.glass.updated, 0u);
  EXPECT_EQ(still.work.glass.reused, 1u);
  EXPECT_EQ(still.work.shadow_maps.reused, 1u);
  EXPECT_EQ(still.work.blocks_uploaded, 0u);
  if (gl_counted(still)) {
    EXPECT_LT(still.gl.dispatches, first.gl.dispatches) << "the rays are not traced again";
    EXPECT_LT(still.gl.draws, first.gl.draws) << "nor the illumination textures drawn";
  }
  EXPECT_EQ(r->read_hdr(), before) << "the same image from the kept textures";
  // Moving the ball remakes them.
  Mat4f t = r->scene().objects[1].transform;
  t[12] += 0.05f;
  ASSERT_TRUE(r->set_object_transform(1, t).ok());
  ASSERT_TRUE(r->render(small_frame(*r, 2.0f)).ok());
  EXPECT_EQ(r->caustics_stats().work.glass.updated, 1u);
}

// The level maps' windows pass (caustics_windows.frag) depends on the
// planes, the position map and the map's side, not on the water: under
// moving water a receiver drawn alone runs it once and then keeps its
// result, and the kept result gives the image a fresh engine gives. A new
// plan (the uniform method's planes) runs it again, once. Maps at 64^2,
// coarser than the default pool's position maps, so that texels span
// several windows and take the window of their samples' mean depth.
// Cost: about 3 s on llvmpipe.
TEST_F(FrameCost, TheWindowsPassRunsOnlyWhenItsInputsChange) {
  nlohmann::json j = test::canonical_scene("default");
  j["water"]["grid"]["cells"] = {48, 48};
  const std::string path = test::write_scene(j, "frame_cost_windows");
  auto r = test::bake_and_create(path);
  ASSERT_TRUE(r);
  r->engine().set_gpu_timing(true, false);
  runtime::CausticsOptions o = runtime::default_caustics_options(r->scene());
  o.map_size = 64;
  o.map_batching = runtime::MapBatching::kNever;
  std::map<std::uint64_t, std::uint32_t> windows;  // frame -> windows passes
  auto frame = [&](float time) {
    FrameParams f = small_frame(*r, time);
    f.caustics = o;
    ASSERT_TRUE(r->render(f).ok());
    glFinish();
    const runtime::GpuTimes t = r->engine().gpu_times();
    std::uint32_t n = 0;
    for (const runtime::GpuPassTime& p : t.passes) {
      if (p.name == "level maps: windows") n = p.count;
    }
    if (t.frame > 0) windows[t.frame] = n;
  };
  for (int i = 0; i < 4; ++i) frame(0.25f * static_cast<float>(i));
  o.method = runtime::CausticsMethod::kUniform;
  for (int i = 4; i < 7; ++i) frame(0.25f * static_cast<float>(i));
  o.method = runtime::CausticsMethod::kLevelMap;
  ASSERT_GE(windows.size(), 5u);
  const std::uint32_t maps = windows.begin()->second;
  EXPECT_GE(maps, 3u) << "the first frame makes every map's windows";
  for (const auto& [k, n] : windows) {
    SCOPED_TRACE(k);
    EXPECT_EQ(n, k == 1 || k == 5 ? maps : 0u) << "windows passes in frame " << k;
  }

  // The ball's light after frames that kept the windows, and from a new
  // engine whose first frame makes them.
  sample::IrradianceRequest q{"ball", -1.1f, -0.2f, -0.1f, 0.8f, 64, 64, 0.0f, o};
  q.pixel_samples = 2;
  for (const float t : {0.3f, 0.6f}) {
    q.time = t;
    ASSERT_TRUE(r->render_irradiance(q).ok());
  }
  q.time = 0.9f;
  const auto kept = r->render_irradiance(q);
  ASSERT_TRUE(kept.ok()) << kept.error().message;
  auto fresh_renderer = test::bake_and_create(path);
  ASSERT_TRUE(fresh_renderer);
  const auto fresh = fresh_renderer->render_irradiance(q);
  ASSERT_TRUE(fresh.ok()) << fresh.error().message;
  double peak = 0, worst = 0;
  for (std::size_t i = 0; i < fresh->rgb.size(); ++i) {
    peak = std::max(peak, double{fresh->rgb[i]});
    worst = std::max(worst, std::fabs(double{kept->rgb[i]} - fresh->rgb[i]));
  }
  EXPECT_GT(peak, 0.5) << "the ball is lit";
  EXPECT_LE(worst, 1e-5 * peak);
}

// What an engine's temporal antialiasing sees: the light side takes no
// camera (Engine::update), so a camera jittered by a fraction of a pixel,
// as TAA does every frame, remakes none of its textures: they hold still
// under the jitter (docs/temporal.md).
TEST_F(FrameCost, AJitteredCameraRemakesNoLightSideTexture) {
  auto r = renderer_of(test::canonical_scene("fog_ball"), "frame_cost_jitter");
  ASSERT_TRUE(r);
  FrameParams f = small_frame(*r, 0.0f);
  ASSERT_TRUE(r->render(f).ok());
  const auto& c = f.camera;
  const float distance = std::hypot(c.position[0] - c.target[0], c.position[1] - c.target[1], c.position[2] - c.target[2]);
  // Half a pixel at the target's distance.
  const float d = std::tan(0.5f * c.fov_y_deg * 3.14159265f / 180.0f) * distance / static_cast<float>(f.height);
  for (int k = 0; k < 4; ++k) {
    // Along x, then y, then back.
    FrameParams g = f;
    g.camera.position[k % 2] += (k < 2 ? d : -d);
    g.camera.target[k % 2] += (k < 2 ? d : -d);
    ASSERT_TRUE(r->render(g).ok());
    const CausticsStats st = r->caustics_stats();
    SCOPED_TRACE(k);
    EXPECT_EQ(st.work.shadow_maps.updated, 0u);
    EXPECT_EQ(st.work.glass.updated, 0u);
    EXPECT_EQ(st.work.media.updated, 0u);
    EXPECT_EQ(st.work.blocks_uploaded, 0u);
    if (gl_counted(st)) EXPECT_EQ(st.gl.dispatches, 0u) << "no compute pass: nothing of the light side was made again";
  }
}

TEST_F(FrameCost, AStillPoolIsNotRemade) {
  auto r = renderer_of(test::canonical_scene("flat_pool"), "frame_cost_flat");
  ASSERT_TRUE(r);
  ASSERT_TRUE(r->render(small_frame(*r, 0.0f)).ok());
  EXPECT_TRUE(r->caustics_stats().work.water);
  EXPECT_EQ(r->caustics_stats().work.level_maps.updated, 1u);
  // No waves: another time is the same surface.
  ASSERT_TRUE(r->render(small_frame(*r, 3.0f)).ok());
  const CausticsStats st = r->caustics_stats();
  EXPECT_FALSE(st.work.water);
  EXPECT_EQ(st.work.level_maps.reused, 1u);
  if (gl_counted(st)) EXPECT_EQ(st.gl.dispatches, 0u) << "a still pool runs no compute pass";
}

TEST_F(FrameCost, TheLightSideCanRunEveryNthFrame) {
  nlohmann::json j = test::canonical_scene("wavy_pool");
  j["water"]["waves"][0]["speed"] = 0.5;  // the sine moves
  auto r = renderer_of(j, "frame_cost_interval");
  ASSERT_TRUE(r);
  std::vector<std::uint32_t> updated;
  for (int i = 0; i < 6; ++i) {
    FrameParams f = small_frame(*r, 0.1f * static_cast<float>(i));
    auto& engine = r->engine();
    runtime::FrameUpdate u{f.time, f.caustics};
    u.light_side_interval = 3;
    ASSERT_TRUE(engine.update(u).ok());
    const runtime::FrameWork w = engine.stats().work;
    EXPECT_TRUE(w.water) << "the surface itself moves every frame";
    updated.push_back(w.level_maps.updated);
    if (i > 0) EXPECT_EQ(w.level_maps.updated + w.level_maps.deferred, 1u);
  }
  // update() k = 1..6: the first makes the maps; then k = 3 and 6.
  EXPECT_EQ(updated, (std::vector<std::uint32_t>{1, 0, 1, 0, 0, 1}));
  runtime::FrameUpdate bad;
  bad.light_side_interval = 0;
  EXPECT_FALSE(r->engine().update(bad).ok());
}

TEST_F(FrameCost, AnOverflowingListDrawsWhatFitsSaysSoAndGrows) {
  // The floor first mostly beside the water (few volumes reach it: a short
  // list), then moved under it: that frame's list overflows, is drawn
  // clamped and reported, and the next frames' list holds every volume.
  nlohmann::json j = test::canonical_scene("flat_pool");
  j["lights"][0]["direction"] = {0.0, -1.0, 0.0};
  auto r = renderer_of(j, "frame_cost_overflow");
  ASSERT_TRUE(r);
  const Mat4f home = r->scene().objects[0].transform;
  Mat4f aside = home;
  aside[12] += 9.8f;  // x in [5.8, 13.8]: 0.2 m under the water (which ends at 6)
  ASSERT_TRUE(r->set_object_transform(0, aside).ok());
  sample::IrradianceRequest q{"floor", -1, -1, 1, 1, 16, 16, 0.0f, runtime::default_caustics_options(r->scene())};
  q.pixel_samples = 1;
  ASSERT_TRUE(r->render_irradiance(q).ok());  // warm-up: the list measured for the floor aside
  ASSERT_FALSE(r->caustics_stats(true).overflowed);
  ASSERT_TRUE(r->set_object_transform(0, home).ok());
  auto clamped = r->render_irradiance(q);
  ASSERT_TRUE(clamped.ok());
  EXPECT_TRUE(r->caustics_stats(true).overflowed) << "more pairs than the list held";
  for (float v : clamped->rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
  auto full = r->render_irradiance(q);
  ASSERT_TRUE(full.ok());
  EXPECT_FALSE(r->caustics_stats(true).overflowed) << "the list grew from the count read back";
  const double t0 = 0.9799;  // Fresnel T at normal incidence from air into n = 1.33, times cos 0
  double worst = 0;
  for (float v : full->rgb) worst = std::max(worst, std::fabs(v / t0 - 1.0));
  EXPECT_LT(worst, 0.01) << "after growing, flat water lights the floor evenly";
}

// The pipeline's counts per pass (ARB_pipeline_statistics_query, which
// llvmpipe has): glass_ball's caustic map with a 96^2 photon grid, no
// focus window and no adaptive levels dispatches ceil(96 / 8)^2 groups of
// causticmap_photons.comp's 8 x 8 and splats 96^2 points, one per photon.
TEST_F(FrameCost, PassStatisticsCountWhatEachPassRuns) {
  auto r = renderer_of(test::canonical_scene("glass_ball"), "frame_cost_statistics");
  ASSERT_TRUE(r);
  if (!epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query")) GTEST_SKIP() << "the driver has no pipeline statistics";
  r->engine().set_gpu_timing(true, true);
  FrameParams f = small_frame(*r, 0.0f);
  f.caustics.glass_method = runtime::GlassMethod::kCausticMap;
  f.caustics.caustic_map.photons = 96;
  f.caustics.caustic_map.adaptive_levels = 0;
  f.caustics.caustic_map.focus = false;
  // gpu_times() gives the latest frame before the current one whose
  // queries completed: the first, once a second has begun.
  for (int i = 0; i < 2; ++i) {
    const Status frame = r->render(f);
    ASSERT_TRUE(frame.ok()) << frame.error().message;
    glFinish();
  }
  const runtime::GpuTimes t = r->engine().gpu_times();
  ASSERT_TRUE(t.statistics);
  ASSERT_EQ(t.frame, 1u);
  const runtime::GpuPassTime* photons = nullptr;
  const runtime::GpuPassTime* splats = nullptr;
  for (const runtime::GpuPassTime& p : t.passes) {
    if (p.name == "caustic maps: photons") photons = &p;
    if (p.name == "caustic maps: splats") splats = &p;
    // Each pass counts its own kind of work only.
    if (p.compute) EXPECT_EQ(p.fragment_invocations, 0u) << p.name;
    if (!p.compute) EXPECT_EQ(p.compute_invocations, 0u) << p.name;
  }
  ASSERT_TRUE(photons && splats);
  EXPECT_EQ(photons->count, 1u);
  EXPECT_EQ(photons->compute_invocations, 12u * 12u * 64u);
  EXPECT_EQ(splats->primitives, 96u * 96u);
  EXPECT_GT(splats->fragment_invocations, 0u);
}

TEST_F(FrameCost, PlanesPlannedOnTheGpuEqualTheCpus) {
  auto program = runtime::gl::Program::build_compute("caustics_plan", shaders::k_caustics_plan_comp_glsl);
  ASSERT_TRUE(program.ok()) << program.error().message;
  std::mt19937 rng(7);
  runtime::gl::Buffer hist = runtime::gl::make_buffer(), planes = runtime::gl::make_buffer(), scratch = runtime::gl::make_buffer();
  const GLsizeiptr plane_bytes = 16 + 8 * GLsizeiptr{kMaxPlanes};
  glNamedBufferStorage(planes.get(), plane_bytes, nullptr, 0);
  glNamedBufferStorage(hist.get(), 4 * 4096, nullptr, GL_DYNAMIC_STORAGE_BIT);
  glNamedBufferStorage(scratch.get(), 4 * (2 * 4096 + 2), nullptr, 0);
  for (int trial = 0; trial < 40; ++trial) {
    const std::uint32_t levels = std::uniform_int_distribution<std::uint32_t>(1, trial < 30 ? 256 : 4096)(rng);
    std::vector<std::uint32_t> h(levels, 0);
    const double fill = std::uniform_real_distribution<double>(0.05, 0.95)(rng);
    for (auto& b : h) b = std::uniform_real_distribution<double>(0, 1)(rng) < fill ? 1 + rng() % 500 : 0;
    const double height = std::uniform_real_distribution<double>(0.01, 20.0)(rng);
    // Epsilons from generous to so small the count is capped (eps raised).
    const double eps = height * std::pow(10.0, std::uniform_real_distribution<double>(trial < 35 ? -3.0 : -7.0, -0.5)(rng));
    glNamedBufferSubData(hist.get(), 0, static_cast<GLsizeiptr>(4 * levels), h.data());
    program->use();
    program->set("u_levels", levels);
    glProgramUniform1d(program->id(), program->loc("u_height"), height);
    glProgramUniform1d(program->id(), program->loc("u_epsilon"), eps);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, hist.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, planes.get());
    glClearNamedBufferData(scratch.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, scratch.get());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> got(static_cast<std::size_t>(plane_bytes / 4));
    glGetNamedBufferSubData(planes.get(), 0, plane_bytes, got.data());
    const std::vector<ReferencePlane> want = smart_planes(height, levels, find_sub_boxes(h), eps, nullptr);
    std::uint32_t count = 0;
    std::memcpy(&count, got.data(), 4);
    ASSERT_EQ(count, want.size()) << "trial " << trial << ": levels " << levels << ", h " << height << ", eps " << eps << ", gl error "
                                  << glGetError() << ", header " << got[1] << " " << got[2] << " " << got[3];
    float lo = 1e30f, hi = -1e30f;
    for (std::size_t k = 0; k < want.size(); ++k) {
      ASSERT_EQ(got[4 + 2 * k], want[k].offset) << "trial " << trial << ", plane " << k;
      ASSERT_EQ(got[5 + 2 * k], want[k].epsilon) << "trial " << trial << ", plane " << k;
      lo = std::min(lo, want[k].offset - want[k].epsilon);
      hi = std::max(hi, want[k].offset + want[k].epsilon);
    }
    EXPECT_EQ(got[1], lo);
    EXPECT_EQ(got[2], hi);
  }
  glUseProgram(0);
}

}  // namespace
}  // namespace caustix
