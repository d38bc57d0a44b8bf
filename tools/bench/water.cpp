#include "water.h"

#include <epoxy/gl.h>

#include <cstdio>
#include <functional>

#include "bench_common.h"
#include "caustix/common/cli.h"
#include "caustix/runtime/water_sim.h"

namespace caustix::bench {

int water_effects(const std::string& cxb, int width, int height, int warmup, int frames, const std::string& csv) {
  auto session = open_scene(cxb);
  if (!session) return cli::fail("caustix-bench", session.error());
  sample::Renderer& r = *session->renderer;
  if (!r.scene().water) {
    return cli::fail("caustix-bench", make_error(ErrorCode::kUsage, cxb + ": the scene has no water"));
  }
  const std::string renderer = session->context->description();
  // Under the surface, looking up and across it (§7.5): from the scene's
  // camera target, 0.4 m below the water, towards the default camera.
  Camera below = r.default_camera();
  const float level = r.scene().water->level;
  below.position = {below.target[0], level - 0.4f, below.target[2]};
  below.target = {r.default_camera().position[0], level + 0.6f, r.default_camera().position[2]};

  struct Row {
    std::string name;
    std::function<void(runtime::WaterLook&, runtime::CausticsOptions&)> edit;
    bool under = false;
  };
  using L = runtime::WaterLook;
  using C = runtime::CausticsOptions;
  const std::vector<Row> rows{
      {"plain surface", [](L& l, C&) { l.textures = false; }},
      {"plain surface, no caustics", [](L& l, C& c) { l.textures = false; c.method = runtime::CausticsMethod::kNone; }},
      {"Mihalik 2008 all effects", [](L&, C&) {}},
      {"all effects at their first settings (512^2 textures, 3 steps fixed)", [](L& l, C&) { l.texture_size = 512; l.max_steps = 3; }},
      {"Mihalik 2008 all effects, no caustics", [](L&, C& c) { c.method = runtime::CausticsMethod::kNone; }},
      {"- refraction", [](L& l, C&) { l.refraction = false; }},
      {"- reflection", [](L& l, C&) { l.reflection = false; }},
      {"- water colour", [](L& l, C&) { l.colour = false; }},
      {"- glow", [](L& l, C&) { l.glow = false; }},
      {"exact Fresnel", [](L& l, C&) { l.fresnel = runtime::FresnelMode::kExact; }},
      {"steps 3 (fixed: the paper)", [](L& l, C&) { l.max_steps = 3; }},
      {"steps 1 (fixed)", [](L& l, C&) { l.steps = l.max_steps = 1; }},
      {"steps 2 (fixed)", [](L& l, C&) { l.steps = l.max_steps = 2; }},
      {"steps 8 (fixed)", [](L& l, C&) { l.steps = l.max_steps = 8; }},
      {"steps 16 (fixed)", [](L& l, C&) { l.steps = l.max_steps = 16; }},
      // Table 3's texture sizes; caustics off, so that their (unchanged)
      // cost does not hide the textures'.
      {"textures 256, no caustics", [](L& l, C& c) { l.texture_size = 256; c.method = runtime::CausticsMethod::kNone; }},
      {"textures 512, no caustics", [](L& l, C& c) { l.texture_size = 512; c.method = runtime::CausticsMethod::kNone; }},
      {"textures 1024, no caustics", [](L& l, C& c) { l.texture_size = 1024; c.method = runtime::CausticsMethod::kNone; }},
      {"textures 2048, no caustics", [](L& l, C& c) { l.texture_size = 2048; c.method = runtime::CausticsMethod::kNone; }},
      {"under water, all effects", [](L&, C&) {}, true},
  };
  CsvOut out(csv, "scene,setting,size,median_ms,min_ms,gpu_mb,renderer");
  for (const Row& row : rows) {
    runtime::WaterLook look = r.engine().default_water_look();  // the preset's texture limit
    runtime::CausticsOptions co = runtime::default_caustics_options(r.scene());
    row.edit(look, co);
    auto t = time_frames(r, co, width, height, warmup, frames, false, look,
                         row.under ? std::optional<Camera>(below) : std::nullopt);
    if (!t) return cli::fail("caustix-bench", t.error());
    char line[512];
    std::snprintf(line, sizeof line, "%s,\"%s\",%dx%d,%.2f,%.2f,%.2f,\"%s\"", r.scene().name.c_str(), row.name.c_str(), width,
                  height, t->median_ms, t->min_ms, static_cast<double>(r.caustics_stats(false).gpu_bytes) / 1e6,
                  renderer.c_str());
    out.row(line);
  }
  return kExitOk;
}

namespace {

// Median milliseconds of `count` calls of `f`, each followed by glFinish,
// after two unmeasured ones.
template <typename F>
Result<double> time_calls(int count, F&& f) {
  std::vector<double> ms;
  for (int i = -2; i < count; ++i) {
    const auto t0 = Clock::now();
    CAUSTIX_RETURN_IF_ERROR(f());
    glFinish();
    if (i >= 0) ms.push_back(ms_since(t0));
  }
  return median(ms);
}

}  // namespace

int water_sim_cost(const std::string& cxb, int frames, const std::string& csv) {
  auto fail = [](const Error& e) { return cli::fail("caustix-bench", e); };
  std::optional<Session> session;
  std::unique_ptr<runtime::HeadlessContext> own;
  if (!cxb.empty()) {
    auto s = open_scene(cxb);
    if (!s) return fail(s.error());
    session.emplace(std::move(*s));
  } else {
    auto c = runtime::HeadlessContext::create();
    if (!c) return fail(c.error());
    own = std::move(*c);
  }
  const std::string renderer = session ? session->context->description() : own->description();
  CsvOut out(csv, "scene,grid,part,median_ms,substeps_per_frame,renderer");
  auto row = [&](const std::string& scene, const std::string& grid, const std::string& part, double ms, double substeps) {
    char line[512];
    std::snprintf(line, sizeof line, "%s,%s,%s,%.3f,%.2f,\"%s\"", scene.c_str(), grid.c_str(), part.c_str(), ms, substeps, renderer.c_str());
    out.row(line);
  };
  for (const std::uint32_t n : {64u, 128u, 256u, 512u, 1024u}) {
    auto sim = runtime::WaterSimulation::create(runtime::WaterGrid{n, n, -2, -2, 2, 2, 0});
    if (!sim) return fail(sim.error());
    (void)(*sim)->add_ripple(0, 0, 0.3f, 0.02f);
    auto ms = time_calls(frames, [&] { return (*sim)->step(1.0f / 60.0f); });
    if (!ms) return fail(ms.error());
    const auto st = (*sim)->stats();
    row("-", std::to_string(n) + "x" + std::to_string(n), "step", *ms, static_cast<double>(st.substeps) / (frames + 2));
  }
  if (!session) return kExitOk;
  sample::Renderer& r = *session->renderer;
  runtime::Engine& e = r.engine();
  const auto grid = e.water_grid();
  if (!grid) return fail(make_error(ErrorCode::kUsage, cxb + ": the scene has no water"));
  const std::string scene = r.scene().name, size = std::to_string(grid->columns) + "x" + std::to_string(grid->rows);
  auto sim = runtime::WaterSimulation::create(*grid);
  if (!sim) return fail(sim.error());
  std::vector<std::uint32_t> bodies(r.scene().objects.size());
  for (std::uint32_t i = 0; i < bodies.size(); ++i) bodies[i] = i;
  const runtime::FrameUpdate update{0.0f, runtime::default_caustics_options(r.scene())};
  auto waves = time_calls(frames, [&] { return e.update(update); });
  if (!waves) return fail(waves.error());
  auto step = time_calls(frames, [&] { return (*sim)->step(1.0f / 60.0f); });
  auto push = time_calls(frames, [&] { return (*sim)->push(e, bodies); });
  auto apply = time_calls(frames, [&] { return (*sim)->apply(e); });
  auto simulated = time_calls(frames, [&] { return e.update(update); });
  for (const auto* t : {&step, &push, &apply, &simulated}) {
    if (!*t) return fail(t->error());
  }
  row(scene, size, "step", *step, 0);
  row(scene, size, "push (" + std::to_string(bodies.size()) + " objects)", *push, 0);
  row(scene, size, "apply", *apply, 0);
  row(scene, size, "light side with the wave list", *waves, 0);
  row(scene, size, "light side with simulated water", *simulated, 0);
  return kExitOk;
}

}  // namespace caustix::bench
