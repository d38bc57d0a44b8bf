#include "water.h"

#include <cstdio>
#include <functional>

#include "bench_common.h"
#include "caustix/common/cli.h"

namespace caustix::bench {

int water_effects(const std::string& cxb, int width, int height, int warmup, int frames, const std::string& csv) {
  auto session = open_scene(cxb);
  if (!session) return cli::fail("caustix-bench", session.error());
  runtime::Renderer& r = *session->renderer;
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
      {"seed 001 all effects", [](L&, C&) {}},
      {"seed 001 all effects, no caustics", [](L&, C& c) { c.method = runtime::CausticsMethod::kNone; }},
      {"- refraction", [](L& l, C&) { l.refraction = false; }},
      {"- reflection", [](L& l, C&) { l.reflection = false; }},
      {"- water colour", [](L& l, C&) { l.colour = false; }},
      {"- glow", [](L& l, C&) { l.glow = false; }},
      {"exact Fresnel", [](L& l, C&) { l.fresnel = runtime::FresnelMode::kExact; }},
      {"steps 1", [](L& l, C&) { l.steps = 1; }},
      {"steps 2", [](L& l, C&) { l.steps = 2; }},
      {"steps 8", [](L& l, C&) { l.steps = 8; }},
      {"steps 16", [](L& l, C&) { l.steps = 16; }},
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
    runtime::WaterLook look;
    runtime::CausticsOptions co = runtime::default_caustics_options(r.scene());
    row.edit(look, co);
    auto t = time_frames(r, co, width, height, warmup, frames, false, look,
                         row.under ? std::optional<Camera>(below) : std::nullopt);
    if (!t) return cli::fail("caustix-bench", t.error());
    char line[512];
    std::snprintf(line, sizeof line, "%s,%s,%dx%d,%.2f,%.2f,%.2f,\"%s\"", r.scene().name.c_str(), row.name.c_str(), width,
                  height, t->median_ms, t->min_ms, static_cast<double>(r.caustics_stats(false).gpu_bytes) / 1e6,
                  renderer.c_str());
    out.row(line);
  }
  return kExitOk;
}

}  // namespace caustix::bench
