#include "tradeoff.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <optional>

#include "bench_common.h"
#include "caustix/bake/bake.h"
#include "caustix/bake/presets.h"
#include "caustix/bake/scene_json.h"
#include "caustix/common/cli.h"
#include "caustix/metrics/image_metrics.h"
#include "caustix/sample/image_output.h"

namespace caustix::bench {
namespace {

struct Setting {
  bake::BakeOptions bake;
  runtime::CausticsOptions caustics;
};

struct Knob {
  const char* name;
  std::vector<double> values;
  bool glass_only;  // only scenes with transparent objects
  bool water_only;  // only scenes with water (level maps)
  std::function<void(Setting&, double)> apply;
  bool media_only = false;  // only in-scatter references (Pfeuti; docs/volume.md)
  bool caster_only = false;  // only scenes with glass or mirrors (image-space caustic maps)
  bool dispersion_only = false;  // only scenes with dispersion
};

// Caustic maps (timofy 2009) draw glass from here on; mirrors always use them.
runtime::CausticMapOptions& caustic_maps(Setting& s) {
  s.caustics.glass_method = runtime::GlassMethod::kCausticMap;
  return s.caustics.caustic_map;
}

// Each knob's values bracket its default (balanced) on both sides.
const std::vector<Knob>& knobs() {
  static const std::vector<Knob> k{
      {"planes", {2, 4, 8, 16, 32, 64, 128}, false, true,
       [](Setting& s, double v) { s.bake.level_maps.slicing.planes = static_cast<std::uint32_t>(v); }},
      {"epsilon", {0.001, 0.003, 0.01, 0.03, 0.1, 0.3}, false, true,
       [](Setting& s, double v) { s.bake.level_maps.slicing.epsilon = v; }},
      {"levels", {1, 4, 16, 64, 256, 1024}, false, true,
       [](Setting& s, double v) { s.bake.level_maps.slicing.levels = static_cast<std::uint32_t>(v); }},
      {"map-size", {64, 128, 256, 512, 1024, 2048}, false, true,
       [](Setting& s, double v) { s.bake.level_maps.map_size = static_cast<std::uint32_t>(v); }},
      {"caustics-size", {128, 256, 512, 1024, 2048}, false, true,
       [](Setting& s, double v) { s.caustics.map_size = static_cast<std::uint32_t>(v); }},
      {"water-grid", {0.25, 0.5, 1, 2, 4}, false, true, [](Setting& s, double v) { s.bake.water_grid_scale = v; }},
      // Another method: photon splatting (Mihalik 2008 ch. 8) at P x P photons per map.
      {"splat-photons", {256, 512, 1024, 2048}, false, true,
       [](Setting& s, double v) {
         s.caustics.method = runtime::CausticsMethod::kSplat;
         s.caustics.photons = static_cast<std::uint32_t>(v);
       }},
      {"ltt-resolution", {8, 12, 16, 20, 24, 32}, true, false,
       [](Setting& s, double v) { s.bake.transport.resolution = static_cast<std::uint32_t>(v); }},
      {"glass-turn", {0, 10, 5, 2.5}, true, false,
       [](Setting& s, double v) { s.bake.glass_refine.max_turn_deg = v; }},
      {"glass-size", {128, 256, 512, 1024, 2048}, true, false,
       [](Setting& s, double v) { s.caustics.glass_map_size = static_cast<std::uint32_t>(v); }},
      // The glass focus window's texels by the tent (1) or by the box (0).
      {"glass-focus-tent", {1, 0}, false, false, [](Setting& s, double v) { s.caustics.glass_focus_tent = v != 0; }},
      // Media (Pfeuti): judged on in-scatter images.
      {"volume-grid", {16, 32, 64, 128}, false, false,
       [](Setting& s, double v) { s.caustics.volume.grid = static_cast<std::uint32_t>(v); }, true},
      {"volume-photons", {64, 128, 256, 512, 1024}, false, false,
       [](Setting& s, double v) { s.caustics.volume.photons = static_cast<std::uint32_t>(v); }, true},
      {"volume-step", {0.25, 0.5, 1, 2}, false, false, [](Setting& s, double v) { s.caustics.volume.step = static_cast<float>(v); }, true},
      {"octree", {1, 0}, false, false, [](Setting& s, double v) { s.caustics.volume.octree = v != 0; }, true},
      {"surface-refraction", {0, 1}, false, false,
       [](Setting& s, double v) { s.caustics.volume.surface_refraction = v != 0; }, true},
      {"octree-eps", {0, 0.003, 0.01, 0.03, 0.1}, false, false,
       [](Setting& s, double v) { s.bake.index_grid.epsilon = static_cast<float>(v); }, true},
      {"volume-res", {32, 64, 128}, false, false,
       [](Setting& s, double v) { s.bake.index_grid.resolution = static_cast<std::uint32_t>(v); }, true},
      {"focus-grid", {0, 16, 32, 64, 96, 128}, false, false,
       [](Setting& s, double v) { s.caustics.volume.focus_grid = static_cast<std::uint32_t>(v); }, true},
      {"view-step", {0.25, 0.5, 1, 2}, false, false,
       [](Setting& s, double v) { s.caustics.volume.view_step = static_cast<float>(v); }, true},
      // Image-space caustic maps (docs/caustic-maps.md).
      {"glass-method", {0, 1}, true, false,
       [](Setting& s, double v) { s.caustics.glass_method = v != 0 ? runtime::GlassMethod::kCausticMap : runtime::GlassMethod::kTable; }},
      {"cmap-photons", {128, 256, 512, 1024}, false, false,
       [](Setting& s, double v) { caustic_maps(s).photons = static_cast<std::uint32_t>(v); }, false, true},
      {"cmap-size", {256, 512, 1024, 2048}, false, false,
       [](Setting& s, double v) { caustic_maps(s).map_size = static_cast<std::uint32_t>(v); }, false, true},
      {"cmap-sigma", {0, 0.5, 1, 2}, false, false,
       [](Setting& s, double v) { caustic_maps(s).splat_sigma = static_cast<float>(v); }, false, true},
      // The caustic map's focus window: 1 on, 0 off.
      {"cmap-focus", {1, 0}, false, false, [](Setting& s, double v) { caustic_maps(s).focus = v != 0; }, false, true},
      {"cmap-iterations", {1, 2, 4, 10}, false, false,
       [](Setting& s, double v) { caustic_maps(s).iterations = static_cast<std::uint32_t>(v); }, false, true},
      // Adaptive caustic maps over a 1024^2 grid, 4 levels, this many photons.
      {"cmap-budget", {4096, 16384, 65536, 262144}, false, false,
       [](Setting& s, double v) {
         runtime::CausticMapOptions& c = caustic_maps(s);
         c.photons = 1024;
         c.adaptive_levels = 4;
         c.photon_budget = static_cast<std::uint32_t>(v);
       },
       false, true},
      // Dispersion (docs/dispersion.md): wavelengths the caustic
      // maps and a dispersive water's passes trace.
      {"wavelengths", {1, 2, 4, 8, 16, 32}, false, false,
       [](Setting& s, double v) {
         s.caustics.glass_method = runtime::GlassMethod::kCausticMap;
         s.caustics.wavelengths = static_cast<std::uint32_t>(v);
       },
       false, false, true},
      // Dispersive glass through its light-transport tables: the wavelengths
      // traced, and the tables baked at other wavelengths to interpolate
      // between (caustix-bake --ltt-wavelengths; 0: n_d only, no fringes).
      {"table-wavelengths", {1, 2, 4, 8, 16}, true, false,
       [](Setting& s, double v) {
         s.caustics.glass_method = runtime::GlassMethod::kTable;
         s.caustics.wavelengths = static_cast<std::uint32_t>(v);
       },
       false, false, true},
      {"ltt-wavelengths", {0, 2, 4, 8}, true, false,
       [](Setting& s, double v) {
         s.caustics.glass_method = runtime::GlassMethod::kTable;
         s.bake.transport.wavelengths = static_cast<std::uint32_t>(v);
       },
       false, false, true},
      // Variance shadow maps' filter width (texels); 0: PCF.
      {"vsm-filter", {0, 1, 5, 21}, false, false,
       [](Setting& s, double v) {
         s.caustics.shadows.filter = v > 0 ? runtime::ShadowFilter::kVsm : runtime::ShadowFilter::kPcf;
         if (v > 0) s.caustics.shadows.vsm_filter = static_cast<std::uint32_t>(v);
       }},
      {"position-bits", {8, 10, 12, 14, 16}, false, false,
       [](Setting& s, double v) { s.bake.draco.position_bits = static_cast<int>(v); }},
      {"normal-bits", {8, 10, 12, 14, 16}, false, false,
       [](Setting& s, double v) { s.bake.draco.normal_bits = static_cast<int>(v); }},
  };
  return k;
}

Setting from_preset(const bake::Preset& p) {
  Setting s{p.options, {}};
  runtime::apply_render_defaults(s.caustics, *p.options.render);
  return s;
}

struct Reference {
  metrics::Image image;
  std::array<double, 4> region{};
  std::string receiver;  // empty: an in-scatter image (x0, y0, x1, y1)
  float time = 0;
  double noise = 0;
};

Result<Reference> load_reference(const std::string& path) {
  auto img = sample::read_rgb_image(path);
  if (!img) return img.error();
  Reference r;
  r.receiver = img->attribute("caustix:receiver");
  const auto region = img->region();
  const bool inscatter = img->attribute("caustix:image") == "inscatter";
  if ((r.receiver.empty() && !inscatter) || !region) {
    return make_error(ErrorCode::kInput, path + ": neither an irradiance image (caustix:receiver) nor an in-scatter image, or no caustix:region");
  }
  r.region = *region;
  r.time = std::strtof(img->attribute("caustix:time").c_str(), nullptr);
  r.noise = std::strtod(img->attribute("caustix:relative_noise").c_str(), nullptr);
  r.image = {img->width, img->height, std::move(img->rgb)};
  return r;
}

}  // namespace

std::vector<std::string> tradeoff_knobs() {
  std::vector<std::string> names;
  for (const Knob& k : knobs()) names.push_back(k.name);
  names.push_back("presets");
  return names;
}

int tradeoff(const TradeoffRequest& q) {
  auto fail = [](const Error& e) { return cli::fail("caustix-bench", e); };
  auto ref = load_reference(q.reference_path);
  if (!ref) return fail(ref.error());
  const bake::Preset* base = bake::find_preset(q.base);
  if (!base) return fail(make_error(ErrorCode::kUsage, "no preset '" + q.base + "'"));
  auto context = runtime::HeadlessContext::create();
  if (!context) return fail(context.error());

  CsvOut out(q.csv, "scene,receiver,knob,value,water_cells,bake_s,cxb_bytes,frame_ms,frame_min_ms,media_ms,march_ms,gpu_mb,eq29,rel_l1,rms,"
       "flux_ratio,peak_px,peak_m,peak_ratio,focus_1cm,focus_2cm,reference_noise,renderer");

  // One row: bake with the setting (the baker's own timing), load the bytes,
  // render the reference's image, then time beauty frames.
  auto evaluate = [&](const std::string& knob, const std::string& value, const Setting& s) -> Status {
    const auto t0 = Clock::now();
    auto baked = bake::bake_scene(q.scene_path, s.bake);
    if (!baked) return baked.error();
    const double bake_s = ms_since(t0) / 1000.0;
    auto scene = runtime::load_scene(baked->cxb.data(), baked->cxb.size());
    if (!scene) return scene.error();
    auto renderer = sample::Renderer::create(*scene);
    if (!renderer) return renderer.error();
    metrics::Image judged;
    if (ref->receiver.empty()) {
      sample::InscatterRequest iq;
      iq.x0 = static_cast<float>(ref->region[0]);
      iq.y0 = static_cast<float>(ref->region[1]);
      iq.x1 = static_cast<float>(ref->region[2]);
      iq.y1 = static_cast<float>(ref->region[3]);
      iq.width = ref->image.width;
      iq.height = ref->image.height;
      iq.time = ref->time;
      iq.caustics = s.caustics;
      iq.pixel_samples = std::min(q.pixel_samples, 4);
      auto img = (*renderer)->render_inscatter(iq);
      if (!img) return img.error();
      judged = {img->width, img->height, std::move(img->rgb)};
    } else {
    sample::IrradianceRequest ir;
    ir.receiver = ref->receiver;
    ir.x0 = static_cast<float>(ref->region[0]);
    ir.z0 = static_cast<float>(ref->region[1]);
    ir.x1 = static_cast<float>(ref->region[2]);
    ir.z1 = static_cast<float>(ref->region[3]);
    ir.width = ref->image.width;
    ir.height = ref->image.height;
    ir.time = ref->time;
    ir.caustics = s.caustics;
    ir.pixel_samples = q.pixel_samples;
    auto img = (*renderer)->render_irradiance(ir);
    if (!img) return img.error();
    judged = {img->width, img->height, std::move(img->rgb)};
    }
    const metrics::Comparison c = metrics::compare(judged, ref->image, ref->region);
    auto times = time_frames(**renderer, s.caustics, q.frame_width, q.frame_height, q.warmup, q.frames);
    if (!times) return times.error();
    // What the media cost in a frame: the same frames without them; of
    // which the light side (photon marching and resolve: Engine::update
    // with and without them, to glFinish, every light set again before each
    // update so that its light side is redone as when it moves), the rest
    // being the viewing pass.
    double media_ms = 0, march_ms = 0;
    if ((*renderer)->engine().has_media()) {
      runtime::CausticsOptions off = s.caustics;
      off.volume.enabled = false;
      auto plain = time_frames(**renderer, off, q.frame_width, q.frame_height, q.warmup, q.frames);
      if (!plain) return plain.error();
      media_ms = times->median_ms - plain->median_ms;
      auto update_ms = [&](const runtime::CausticsOptions& co) -> Result<double> {
        std::vector<double> ms;
        runtime::Engine& engine = (*renderer)->engine();
        for (int i = 0; i < q.warmup + q.frames; ++i) {
          for (std::uint32_t li = 0; li < engine.scene().lights.size(); ++li) {
            if (Status st = engine.set_light(li, engine.scene().lights[li]); !st) return st.error();
          }
          const auto t = Clock::now();
          if (Status st = engine.update(runtime::FrameUpdate{0.0f, co}); !st) return st.error();
          (*renderer)->finish();
          if (i >= q.warmup) ms.push_back(ms_since(t));
        }
        return median(ms);
      };
      auto on = update_ms(s.caustics);
      if (!on) return on.error();
      auto without = update_ms(off);
      if (!without) return without.error();
      march_ms = *on - *without;
    }
    const runtime::CausticsStats cs = (*renderer)->caustics_stats(false);
    std::string cells = "-";
    if (scene->desc.water) cells = std::to_string(scene->desc.water->cells[0]) + "x" + std::to_string(scene->desc.water->cells[1]);
    // The focal columns: empty for an in-scatter image (no
    // ground region) or where the reference has no power there.
    const auto focal = [](const std::optional<double>& v) {
      char b[32] = "";
      if (v) std::snprintf(b, sizeof b, "%.4f", *v);
      return std::string(b);
    };
    const std::string f1 = ref->receiver.empty() ? "" : focal(c.focus_1cm), f2 = ref->receiver.empty() ? "" : focal(c.focus_2cm);
    char line[1024];
    std::snprintf(line, sizeof line, "%s,%s,%s,%s,%s,%.3f,%zu,%.2f,%.2f,%.2f,%.2f,%.2f,%.4f,%.4f,%.4f,%.4f,%.2f,%.4f,%.4f,%s,%s,%.4f,\"%s\"",
                  scene->desc.name.c_str(), ref->receiver.empty() ? "(in-scatter)" : ref->receiver.c_str(), knob.c_str(),
                  value.c_str(), cells.c_str(), bake_s, baked->cxb.size(), times->median_ms, times->min_ms, media_ms, march_ms,
                  static_cast<double>(cs.gpu_bytes) / 1e6, c.eq29,
                  c.rel_l1, c.rms, c.flux_ratio, c.peak_error_px, c.peak_error_m.value_or(0), c.peak_ratio, f1.c_str(), f2.c_str(),
                  ref->noise,
                  context->get()->description().c_str());
    out.row(line);
    return Status::success();
  };

  // What the scene has decides which knobs apply.
  auto doc = bake::load_scene(q.scene_path);
  if (!doc) return fail(doc.error());
  const bool has_water = doc->scene.water.has_value();
  const bool has_glass = std::any_of(doc->scene.objects.begin(), doc->scene.objects.end(),
                                     [](const Object& o) { return is_transparent(o.role); });
  const bool has_casters = has_glass || std::any_of(doc->scene.objects.begin(), doc->scene.objects.end(),
                                                    [](const Object& o) { return is_mirror(o.role); });

  const std::vector<std::string> wanted = q.knobs.empty() ? tradeoff_knobs() : q.knobs;
  for (const std::string& name : wanted) {
    if (name == "presets") {
      for (const bake::Preset& p : bake::presets()) {
        if (Status st = evaluate("preset", p.name, from_preset(p)); !st) return fail(st.error());
      }
      continue;
    }
    const Knob* knob = nullptr;
    for (const Knob& k : knobs()) knob = name == k.name ? &k : knob;
    if (!knob) return fail(make_error(ErrorCode::kUsage, "unknown knob '" + name + "'"));
    const bool inscatter = ref->receiver.empty();
    if (q.knobs.empty() && knob->media_only != inscatter) continue;  // in-scatter references sweep the media's knobs
    if ((knob->glass_only && !has_glass) || (knob->water_only && !has_water) || (knob->media_only && !inscatter) ||
        (knob->caster_only && !has_casters) || (knob->dispersion_only && !scene_disperses(doc->scene))) {
      std::fprintf(stderr, "caustix-bench: %s does not apply to %s (skipped)\n", knob->name, q.scene_path.c_str());
      continue;
    }
    for (double v : knob->values) {
      Setting s = from_preset(*base);
      knob->apply(s, v);
      char value[32];
      std::snprintf(value, sizeof value, "%g", v);
      if (Status st = evaluate(knob->name, value, s); !st) return fail(st.error());
    }
  }
  return kExitOk;
}

}  // namespace caustix::bench
