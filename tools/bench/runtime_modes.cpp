// caustix-bench's run-time subcommands: they need only the runtime library
// and an OpenGL 4.5 context (Mesa or a GPU), so they also build in a
// CAUSTIX_PARTS=runtime tree for machines without the baker's libraries.
//
//   caustix-bench frames SCENE.cxb [--method M] [--planes N] [--size WxH] ...
//       Milliseconds per frame of the runtime (one CSV line).
//   caustix-bench methods SCENE.cxb [--planes N] [--size WxH]
//       Tipprasert 2006 table 5-5: eq. 2-9 differences between the methods' images.
//   caustix-bench water SCENE.cxb [--size WxH] [--frames N] [--csv FILE]
//       Milliseconds per frame of each water-surface effect (Mihalik 2008).
//   caustix-bench receivers SCENE.cxb [--size WxH] [--frames N]
//       Every receiver lit from every light: the per-pair forward path
//       against the deferred pass over Engine::bind_all() (one CSV line).

#include "runtime_modes.h"

#include <CLI/CLI.hpp>

#include <array>
#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "caustix/common/cli.h"
#include "caustix/metrics/image_metrics.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/sample/receiver_passes.h"
#include "caustix/sample/renderer.h"
#include "bench_common.h"
#include "water.h"

namespace caustix::bench {
namespace {

// The median GPU time of each engine pass over the measured frames, and
// the medians of its pipeline counts (empty where the driver has none),
// one CSV row per pass (appended to `path`, with a header when it is new).
void write_passes(const std::string& path, const std::string& label, const std::string& cxb, const runtime::CausticsOptions& co,
                  int width, int height, const std::vector<runtime::GpuTimes>& gpu, const std::string& renderer) {
  const bool fresh = !std::ifstream(path).good();
  std::ofstream out(path, std::ios::app);
  if (fresh) out << "label,scene,method,size,pass,kind,count,median_ms,vs_invocations,primitives,fs_invocations,cs_invocations,renderer\n";
  const bool statistics = !gpu.empty() && gpu.front().statistics;
  std::vector<std::pair<std::string, bool>> order;
  for (const runtime::GpuTimes& t : gpu) {
    for (const runtime::GpuPassTime& p : t.passes) {
      if (std::find(order.begin(), order.end(), std::pair{p.name, p.compute}) == order.end()) order.emplace_back(p.name, p.compute);
    }
  }
  // counts: the medians of the four pipeline counts, or nothing.
  auto row = [&](const std::string& name, const char* kind, std::uint32_t n, double ms, const std::string& counts) {
    out << label << "," << std::filesystem::path(cxb).filename().string() << "," << runtime::to_string(co.method) << "," << width << "x" << height << ",\"" << name << "\","
        << kind << "," << n << "," << ms << "," << (counts.empty() ? std::string(",,,") : counts) << ",\"" << renderer << "\"\n";
  };
  for (const auto& [name, compute] : order) {
    std::vector<double> ms;
    std::array<std::vector<double>, 4> stats;
    std::uint32_t n = 0;
    for (const runtime::GpuTimes& t : gpu) {
      double sum = 0;
      std::array<double, 4> counted{};
      for (const runtime::GpuPassTime& p : t.passes) {
        if (p.name == name && p.compute == compute) {
          sum += p.ms;
          n = p.count;
          counted = {static_cast<double>(p.vertex_invocations), static_cast<double>(p.primitives), static_cast<double>(p.fragment_invocations),
                     static_cast<double>(p.compute_invocations)};
        }
      }
      ms.push_back(sum);
      for (std::size_t k = 0; k < 4; ++k) stats[k].push_back(counted[k]);
    }
    std::string counts;
    for (std::size_t k = 0; statistics && k < 4; ++k) {
      if (k > 0) counts += ',';
      counts += std::to_string(static_cast<std::uint64_t>(median(stats[k])));
    }
    row(name, compute ? "compute" : "raster", n, median(ms), counts);
  }
  std::vector<double> compute_ms, raster_ms;
  for (const runtime::GpuTimes& t : gpu) {
    compute_ms.push_back(t.compute_ms);
    raster_ms.push_back(t.raster_ms);
  }
  if (!gpu.empty()) {
    row("all compute passes", "compute", 0, median(compute_ms), "");
    row("all raster passes", "raster", 0, median(raster_ms), "");
  }
}

// CausticsOptions::memory_budget when --memory-budget is not given: the
// file's preset's.
constexpr std::uint64_t kPresetBudget = ~std::uint64_t{0};

// Milliseconds per frame of the runtime on a baked scene (one CSV line).
int frames(const std::string& cxb, const runtime::CausticsOptions& co, const runtime::GlassViewOptions& glass_view,
           std::uint32_t glass_size, int width, int height, int warmup, int count, const std::string& label, bool move_light,
           int supersample, const std::string& passes_csv, bool still, const std::string& glass_focus_spectral, std::uint32_t out_of_view) {
  auto session = open_scene(cxb);
  if (!session) return cli::fail("caustix-bench", session.error());
  auto& r = session->renderer;
  runtime::CausticsOptions with_defaults = co;
  if (co.map_size == 0) {  // the file's recorded defaults (RNDR), else the built-in ones
    with_defaults.map_size = runtime::CausticsOptions{}.map_size;
    if (r->scene().render) runtime::apply_render_defaults(with_defaults, *r->scene().render);
  }
  if (co.memory_budget == kPresetBudget) with_defaults.memory_budget = runtime::default_caustics_options(r->scene()).memory_budget;
  if (glass_size > 0) with_defaults.glass_map_size = glass_size;  // explicit wins over the file's
  if (!glass_focus_spectral.empty()) with_defaults.glass_focus_spectral_coarse = glass_focus_spectral == "coarse";
  std::vector<runtime::GpuTimes> gpu;
  auto times = time_frames(*r, with_defaults, width, height, warmup, count, move_light, r->engine().default_water_look(), std::nullopt,
                           glass_view, supersample, passes_csv.empty() ? nullptr : &gpu, still, out_of_view);
  if (!times) return cli::fail("caustix-bench", times.error());
  if (!passes_csv.empty()) write_passes(passes_csv, label, cxb, co, width, height, gpu, session->context->description());
  // The last measured frame's GL calls, before anything else adds to them.
  runtime::CausticsStats cs = r->caustics_stats();
  const runtime::GlCalls calls = cs.gl;
  std::vector<std::string> warnings = std::move(cs.warnings);
  cs = r->caustics_stats(true);
  warnings.insert(warnings.end(), cs.warnings.begin(), cs.warnings.end());
  auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
  // Empty GL-call columns from a build without CAUSTIX_COUNT_GL_CALLS.
  std::string counts = ",,,,";
  if (calls.counted) {
    counts = std::to_string(calls.calls) + "," + std::to_string(calls.syncs) + "," + std::to_string(calls.draws) + "," +
             std::to_string(calls.dispatches) + "," + std::to_string(calls.upload_bytes);
  }
  std::printf("%s,%s,%s,%u,%d,%dx%d,%.2f,%.2f,%llu,%llu,%llu,%.1f,%s,\"%s\",%.1f,%.3f,%.3f\n", label.c_str(), cxb.c_str(),
              runtime::to_string(co.method), co.planes.value_or(0), co.cull ? 1 : 0, width, height, times->median_ms, times->min_ms,
              u(cs.planes_drawn), u(cs.volumes_drawn), u(cs.volumes_total), static_cast<double>(cs.gpu_bytes) / 1e6, counts.c_str(),
              session->context->description().c_str(), static_cast<double>(cs.memory.light_side()) / 1e6, cs.texels.texel * 1e3,
              cs.texels.coarsened);
  for (const std::string& w : warnings) std::fprintf(stderr, "caustix-bench: warning: %s\n", w.c_str());
  return kExitOk;
}

// Tipprasert 2006 table 5-5 on our code: the eq. 2-9 difference between the
// images of smart and uniform slicing, and of level map and volumetric, at
// one plane count (same frame, same time).
int methods(const std::string& cxb, std::uint32_t planes, int width, int height, const std::string& label) {
  auto session = open_scene(cxb);
  if (!session) return cli::fail("caustix-bench", session.error());
  auto& r = session->renderer;
  auto image = [&](runtime::CausticsMethod m) {
    runtime::CausticsOptions co;
    co.method = m;
    if (planes > 0) co.planes = planes;
    sample::FrameParams f;
    f.camera = r->default_camera();
    f.time = 1.0f;
    f.width = width;
    f.height = height;
    f.caustics = co;
    metrics::Image img{width, height, {}};
    if (!r->render(f)) return img;
    const auto rgba = r->read_hdr();
    for (std::size_t i = 0; i < rgba.size(); i += 4) img.rgb.insert(img.rgb.end(), {rgba[i], rgba[i + 1], rgba[i + 2]});
    return img;
  };
  const auto smart = image(runtime::CausticsMethod::kLevelMap);
  const auto uniform = image(runtime::CausticsMethod::kUniform);
  const auto volumetric = image(runtime::CausticsMethod::kVolumetric);
  const auto none = image(runtime::CausticsMethod::kNone);
  std::printf("%s,%s,%u,%.4f,%.4f,%.4f\n", label.c_str(), cxb.c_str(), planes,
              metrics::average_luv_difference(smart, uniform), metrics::average_luv_difference(uniform, volumetric),
              metrics::average_luv_difference(smart, none));
  return kExitOk;
}

// Lighting every receiver from every light (docs/embedding.md):
// ms of the per-pair forward path (bind(object, light) and a draw per
// pair, additive, on a G-buffer's depth) and of the deferred pass
// (bind_all() and one full-screen draw) over the same G-buffer, seen from
// the scene's camera; and ms of update() with the water moving every
// frame (time, and the wave scale toggled, so that still wave lists move
// too) before and after the table exists, with what it copies per frame.
int receivers_cost(const std::string& cxb, int width, int height, int warmup, int count, const std::string& label, bool header) {
  auto session = open_scene(cxb);
  if (!session) return cli::fail("caustix-bench", session.error());
  runtime::Engine& e = session->renderer->engine();
  const SceneDesc& sc = e.scene();
  const Camera cam = sc.camera.value_or(Camera{});
  const auto v3 = [](const Vec3f& v) { return glm::vec3(v[0], v[1], v[2]); };
  const glm::mat4 view_proj =
      glm::perspective(glm::radians(cam.fov_y_deg), static_cast<float>(width) / static_cast<float>(height), cam.near_plane, cam.far_plane) *
      glm::lookAt(v3(cam.position), v3(cam.target), v3(cam.up));
  auto passes = sample::ReceiverPasses::create(e, width, height);
  if (!passes) return cli::fail("caustix-bench", passes.error());
  runtime::FrameUpdate f;
  f.caustics = e.default_options();
  int frame = 0;
  auto median_ms = [&](auto&& step) -> Result<double> {
    std::vector<double> ms;
    for (int i = 0; i < warmup + count; ++i) {
      glFinish();
      const auto t = Clock::now();
      if (Status st = step(); !st) return st.error();
      glFinish();
      if (i >= warmup) ms.push_back(ms_since(t));
    }
    return median(ms);
  };
  auto update = [&]() {
    ++frame;
    f.time = static_cast<float>(frame) / 30.0f;
    e.set_wave_scale(frame % 2 ? 1.0f : 0.999f);
    return e.update(f);
  };
  auto update_ms = median_ms(update);
  if (!update_ms) return cli::fail("caustix-bench", update_ms.error());
  if (Status st = e.bind_all(); !st) return cli::fail("caustix-bench", st.error());
  auto update_table_ms = median_ms(update);
  if (!update_table_ms) return cli::fail("caustix-bench", update_table_ms.error());
  const runtime::CausticsStats st = e.stats();
  sample::ReceiverPasses& p = **passes;
  if (Status s = p.draw_gbuffer(view_proj); !s) return cli::fail("caustix-bench", s.error());
  auto per_pair_ms = median_ms([&]() { return p.shade_per_pair(view_proj); });
  auto deferred_ms = median_ms([&]() { return p.shade_deferred(); });
  if (!per_pair_ms || !deferred_ms) return cli::fail("caustix-bench", (per_pair_ms ? deferred_ms : per_pair_ms).error());
  if (header) {
    std::printf("label,scene,size,receivers,lights,per_pair_ms,deferred_ms,update_ms,update_with_table_ms,table_mb,"
                "table_copied_mb_per_frame,table_copies_per_frame,renderer\n");
  }
  std::printf("%s,%s,%dx%d,%zu,%zu,%.3f,%.3f,%.3f,%.3f,%.2f,%.2f,%u,\"%s\"\n", label.c_str(),
              std::filesystem::path(cxb).filename().string().c_str(), width, height, p.receivers(), sc.lights.size(), *per_pair_ms,
              *deferred_ms, *update_ms, *update_table_ms, static_cast<double>(st.memory.receiver_table) / 1048576.0,
              static_cast<double>(st.work.table_copied_bytes) / 1048576.0, st.work.table_copies, session->context->description().c_str());
  return kExitOk;
}

struct RuntimeModes final : Modes {
  std::string glass_method = "table", glass_view = "table";
  std::uint32_t cmap_photons = runtime::CausticMapOptions{}.photons, cmap_size = runtime::CausticMapOptions{}.map_size;
  std::uint32_t cmap_adaptive = runtime::CausticMapOptions{}.adaptive_levels, cmap_budget = runtime::CausticMapOptions{}.photon_budget;
  std::string cxb, method = "levelmap", label = "-", fsize = "640x480", wsize = "640x480", csv, passes_csv;
  float texel = 0.0f;
  double budget_mb = -1.0;
  std::uint32_t planes = 0, csize = 0, gsize = 0, volume_focus = runtime::VolumeOptions{}.focus_grid;
  int warmup = 3, count = 10, wframes = 5, supersample = 1;
  std::uint32_t wavelengths = runtime::CausticsOptions{}.wavelengths;
  bool no_cull = false, header = false, move_light = false, still = false, glass_no_focus = false, glass_focus_box = false,
       cmap_no_focus = false;
  std::uint32_t out_of_view = 0;
  float glass_focus_wide = runtime::CausticsOptions{}.glass_focus_wide;
  std::string glass_focus_spectral, map_batching = "auto";
  std::string volume_refraction = runtime::VolumeOptions{}.surface_refraction ? "surface" : "gradient";
  CLI::App *fr = nullptr, *me = nullptr, *wa = nullptr, *ws = nullptr, *rc = nullptr;
  std::string sim_scene;

  explicit RuntimeModes(CLI::App& app) {
    fr = app.add_subcommand("frames", "ms per frame of the runtime on a baked scene (one CSV line)");
    fr->add_option("scene", cxb, "baked scene (.cxb)")->required();
    fr->add_option("--method", method, "levelmap, uniform, volumetric, splat, none")
        ->check(CLI::IsMember({"levelmap", "uniform", "volumetric", "splat", "none"}))->capture_default_str();
    fr->add_option("--planes", planes, "re-slice with n planes (0: as baked)")->check(CLI::Range(0, 4096));
    fr->add_option("--size", fsize, "image size WxH")->capture_default_str();
    fr->add_option("--warmup", warmup, "frames not measured")->capture_default_str();
    fr->add_option("--frames", count, "frames measured (median reported)")->check(CLI::Range(1, 100000))->capture_default_str();
    fr->add_option("--caustics-size", csize, "caustics map size (default: the file's preset, else 512)")
        ->check(CLI::Range(1, 8192));
    fr->add_option("--texel", texel, "caustics maps' texel, metres (0: the light's largest lit extent / the map size)")
        ->check(CLI::Range(0.0, 1e3));
    fr->add_option("--memory-budget", budget_mb, "the light side's GPU memory budget, MiB (0: none; default: the preset's)")
        ->check(CLI::Range(0.0, 1.0e7));
    fr->add_option("--glass-size", gsize, "glass illumination texture size (default: the file's preset, else 512)")
        ->check(CLI::Range(1, 8192));
    fr->add_flag("--no-cull", no_cull, "draw every volume through every plane, as the thesis did");
    fr->add_option("--map-batching", map_batching, "level maps in batches: auto, always or never (CausticsOptions::map_batching)")
        ->check(CLI::IsMember({"auto", "always", "never"}));
    fr->add_flag("--glass-no-focus", glass_no_focus, "glass (table): no focus windows (docs/glass-focus.md)");
    fr->add_option("--volume-refraction", volume_refraction, "media: surface or gradient (VolumeOptions::surface_refraction)")
        ->check(CLI::IsMember({"surface", "gradient"}))->capture_default_str();
    fr->add_flag("--glass-focus-box", glass_focus_box,
                 "glass (table): focus windows' texels by the box, not the tent (CausticsOptions::glass_focus_tent off, "
                 "docs/temporal.md)");
    fr->add_option("--glass-focus-wide", glass_focus_wide,
                   "glass (table): focus windows' wide triangles, in window texels (0: every triangle clipped; docs/glass-focus.md)")
        ->check(CLI::Range(0.0f, 1e6f))->capture_default_str();
    fr->add_option("--glass-focus-spectral", glass_focus_spectral,
                   "glass (table): dispersive glass's focus windows at half their texels (coarse) or their own (full); default: the "
                   "file's preset, else coarse (docs/glass-focus.md)")
        ->check(CLI::IsMember({"coarse", "full"}));
    fr->add_option("--volume-focus", volume_focus, "media: focus-grid voxels a side (0: none; docs/volume.md)")
        ->check(CLI::Range(0, 128))->capture_default_str();
    fr->add_option("--glass-method", glass_method, "light through glass: table or caustic-map (timofy 2009; mirrors always use caustic maps)")
        ->check(CLI::IsMember({"table", "caustic-map"}))->capture_default_str();
    fr->add_option("--glass-view", glass_view, "the view through glass: table (Iwasaki et al. §3) or nearby (nearby-geometry refraction, timofy 2009)")
        ->check(CLI::IsMember({"table", "nearby"}))->capture_default_str();
    fr->add_option("--cmap-photons", cmap_photons, "caustic maps: photon grid side")->check(CLI::Range(1, 4096))->capture_default_str();
    fr->add_option("--cmap-size", cmap_size, "caustic maps: caustic map side")->check(CLI::Range(16, 4096))->capture_default_str();
    fr->add_option("--cmap-adaptive", cmap_adaptive, "caustic maps: adaptive traversal levels (0: uniform grid)")->check(CLI::Range(0, 8))->capture_default_str();
    fr->add_option("--cmap-budget", cmap_budget, "caustic maps, adaptive: most photons per light")->check(CLI::Range(1, 1 << 24))->capture_default_str();
    fr->add_flag("--cmap-no-focus", cmap_no_focus, "caustic maps: no focus window (docs/caustic-maps.md)");
    fr->add_option("--supersample", supersample, "antialiasing: N x N samples per pixel (the renderer's FrameParams::supersample)")
        ->check(CLI::Range(1, 4))->capture_default_str();
    fr->add_option("--wavelengths", wavelengths, "dispersion: wavelengths traced in a scene with dispersion (docs/dispersion.md)")
        ->check(CLI::Range(1, static_cast<int>(kMaxWavelengths)))->capture_default_str();
    fr->add_option("--label", label, "first CSV column");
    fr->add_flag("--header", header, "print the CSV header first");
    fr->add_flag("--move-light", move_light, "turn the first light every frame (level maps re-derived each frame)");
    fr->add_flag("--still", still, "keep the time at 0 (a paused scene: with a still light nothing changes between frames)");
    fr->add_option("--out-of-view", out_of_view,
                   "N > 0: tell the engine the camera; receivers out of view keep their caustics maps, remade every Nth frame "
                   "(FrameUpdate::out_of_view_interval; 0: off)")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    fr->add_option("--passes", passes_csv,
                   "also time every engine pass on the GPU (timer queries) and append each pass's median ms to this CSV");
    me = app.add_subcommand("methods", "eq. 2-9 differences between methods (one CSV line)");
    me->add_option("scene", cxb, "baked scene (.cxb)")->required();
    me->add_option("--planes", planes, "re-slice with n planes (0: as baked)")->check(CLI::Range(0, 4096));
    me->add_option("--size", fsize, "image size WxH")->capture_default_str();
    me->add_option("--label", label, "first CSV column");
    me->add_flag("--header", header, "print the CSV header first");
    wa = app.add_subcommand("water", "ms per frame of each water-surface effect (Mihalik 2008) and texture size");
    wa->add_option("scene", cxb, "baked scene with water (.cxb)")->required();
    wa->add_option("--size", wsize, "frame size WxH")->capture_default_str();
    wa->add_option("--frames", wframes, "frames measured per setting (median)")->check(CLI::Range(1, 1000))->capture_default_str();
    wa->add_option("--csv", csv, "also write the table as CSV");
    rc = app.add_subcommand("receivers", "every receiver from every light: the per-pair path against bind_all()'s deferred pass (one CSV line)");
    rc->add_option("scene", cxb, "baked scene (.cxb)")->required();
    rc->add_option("--size", fsize, "image size WxH")->capture_default_str();
    rc->add_option("--warmup", warmup, "frames not measured")->capture_default_str();
    rc->add_option("--frames", count, "frames measured (median reported)")->check(CLI::Range(1, 100000))->capture_default_str();
    rc->add_option("--label", label, "first CSV column");
    rc->add_flag("--header", header, "print the CSV header first");
    ws = app.add_subcommand("water-sim", "ms per 60 Hz frame of the interactive water (docs/water-simulation.md) by grid size, and its parts on a scene");
    ws->add_option("scene", sim_scene, "baked scene with water (.cxb); without it only the grid sweep runs");
    ws->add_option("--frames", wframes, "frames measured per row (median)")->check(CLI::Range(1, 10000))->capture_default_str();
    ws->add_option("--csv", csv, "also write the table as CSV");
  }

  bool chosen() const override { return *fr || *me || *wa || *ws || *rc; }

  int run() override {
    if (*ws) return water_sim_cost(sim_scene, wframes, csv);
    int w = 0, h = 0;
    if (!cli::parse_size(*wa ? wsize : fsize, w, h)) {
      return cli::fail("caustix-bench", make_error(ErrorCode::kUsage, "bad --size"));
    }
    if (*wa) return water_effects(cxb, w, h, 1, wframes, csv);
    if (*rc) return receivers_cost(cxb, w, h, warmup, count, label, header);
    if (*me) {
      if (header) std::printf("label,scene,planes,eq29_smart_vs_uniform,eq29_uniform_vs_volumetric,eq29_smart_vs_none\n");
      return methods(cxb, planes, w, h, label);
    }
    if (header) {
      std::printf("label,scene,method,planes,cull,size,median_ms,min_ms,planes_drawn,primitives_drawn,volumes_total,gpu_mb,"
                  "gl_calls,gl_syncs,draws,dispatches,upload_bytes,renderer,light_side_mb,texel_mm,coarsened\n");
    }
    runtime::CausticsOptions co;
    co.method = *runtime::parse_method(method);
    if (planes > 0) co.planes = planes;
    co.cull = !no_cull;
    co.map_batching = map_batching == "always" ? runtime::MapBatching::kAlways
                    : map_batching == "never"  ? runtime::MapBatching::kNever
                                               : runtime::MapBatching::kAuto;
    co.glass_focus = !glass_no_focus;
    co.glass_focus_wide = glass_focus_wide;
    co.glass_focus_tent = !glass_focus_box;
    co.volume.focus_grid = volume_focus;
    co.volume.surface_refraction = volume_refraction == "surface";
    co.map_size = csize;
    co.texel_size = texel;
    co.memory_budget = budget_mb >= 0 ? static_cast<std::uint64_t>(budget_mb * 1048576.0) : kPresetBudget;
    co.glass_method = *runtime::parse_glass_method(glass_method);
    co.caustic_map.photons = cmap_photons;
    co.caustic_map.map_size = cmap_size;
    co.caustic_map.adaptive_levels = cmap_adaptive;
    co.caustic_map.photon_budget = cmap_budget;
    co.caustic_map.focus = !cmap_no_focus;
    co.wavelengths = wavelengths;
    runtime::GlassViewOptions gv;
    gv.method = *runtime::parse_glass_view(glass_view);
    return frames(cxb, co, gv, gsize, w, h, warmup, count, label, move_light, supersample, passes_csv, still, glass_focus_spectral, out_of_view);
  }
};

}  // namespace

std::unique_ptr<Modes> add_runtime_modes(CLI::App& app) { return std::make_unique<RuntimeModes>(app); }

}  // namespace caustix::bench
