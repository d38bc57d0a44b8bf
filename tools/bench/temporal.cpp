// caustix-bench temporal: does the picture hold still when the light, the
// water or an object moves a little? A stack of irradiance (or in-scatter)
// images is rendered with the motion advancing one step a frame, and again
// at half the step; metrics::temporal_stats says how much of the change
// between frames is smooth (rho halves with the step) and how large the
// jumps of flux, peak and focus power are (docs/temporal.md).
//
//   caustix-bench temporal SCENE.cxb --motion light|water|object --step S
//       [--receiver NAME --region x0,z0,x1,z1 | --inscatter --region x0,y0,x1,y1]
//       [--frames N] [--size N] [--pixel-samples N] [--method M] [--glass-method G] [--glass-focus-box]
//       [--object NAME] [--time T] [--focus-radius R] [--write-frames DIR] [--label L] [--header]

#include "temporal.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "caustix/common/cli.h"
#include "caustix/metrics/temporal.h"
#include "caustix/sample/image_output.h"
#include "caustix/sample/motion.h"
#include "caustix/sample/renderer.h"
#include "bench_common.h"

namespace caustix::bench {
namespace {

struct Motion {
  std::string kind;    // light, water, object
  std::string object;  // for "object"
  double step = 0;     // degrees (light), seconds (water), metres (object)
};

struct Request {
  std::string cxb, receiver;
  bool inscatter = false;
  std::array<double, 4> region{-1, -1, 1, 1};
  int frames = 12, size = 160, pixel_samples = 2;
  double time = 0, focus_radius = 0.01;
  runtime::CausticsOptions caustics;
  bool set_method = false, set_glass_method = false;
  bool glass_no_focus = false, glass_focus_box = false, cmap_no_focus = false;
  int volume_focus = -1;  // media focus grid; -1: the file's
  std::string volume_refraction;  // media: surface or gradient; empty: the default
  std::string write_frames;  // a folder for the stacks' images; empty: none
};

// The stack of frames 0..n-1 with the motion at k * step (sample::render_stack).
Result<std::vector<metrics::Image>> stack(sample::Renderer& r, const Request& q, const Motion& m, double step) {
  sample::StackRequest sq;
  sq.receiver = q.receiver;
  sq.inscatter = q.inscatter;
  for (int i = 0; i < 4; ++i) sq.region[static_cast<std::size_t>(i)] = static_cast<float>(q.region[static_cast<std::size_t>(i)]);
  sq.frames = q.frames;
  sq.size = q.size;
  sq.pixel_samples = q.pixel_samples;
  sq.time = q.time;
  sq.caustics = q.caustics;
  const sample::Motion motion{m.kind == "light"   ? sample::MotionKind::kLight
                              : m.kind == "water" ? sample::MotionKind::kWater
                                                  : sample::MotionKind::kObject,
                              m.object};
  auto frames = sample::render_stack(r, sq, motion, step);
  if (!frames) return make_error(frames.error().code, q.cxb + ": " + frames.error().message);
  std::vector<metrics::Image> out;
  for (sample::StackFrame& f : *frames) out.push_back({f.width, f.height, std::move(f.rgb)});
  return out;
}

int temporal(Request q, const Motion& m, const std::string& label) {
  auto session = open_scene(q.cxb);
  if (!session) return cli::fail("caustix-bench", session.error());
  auto& r = *session->renderer;
  runtime::CausticsOptions co = runtime::default_caustics_options(r.scene());
  if (q.set_method) co.method = q.caustics.method;
  if (q.set_glass_method) co.glass_method = q.caustics.glass_method;
  if (q.glass_no_focus) co.glass_focus = false;
  if (q.glass_focus_box) co.glass_focus_tent = false;
  if (q.cmap_no_focus) co.caustic_map.focus = false;
  if (q.volume_focus >= 0) co.volume.focus_grid = static_cast<std::uint32_t>(q.volume_focus);
  if (!q.volume_refraction.empty()) co.volume.surface_refraction = q.volume_refraction == "surface";
  q.caustics = co;
  if (!q.inscatter && q.receiver.empty()) {
    return cli::fail("caustix-bench", make_error(ErrorCode::kUsage, "temporal: --receiver or --inscatter"));
  }
  const std::optional<std::array<double, 4>> region = q.region;
  metrics::TemporalStats at[2];
  for (int half = 0; half < 2; ++half) {
    auto frames = stack(r, q, m, half ? 0.5 * m.step : m.step);
    if (!frames) return cli::fail("caustix-bench", frames.error());
    at[half] = metrics::temporal_stats(*frames, region, q.focus_radius);
    if (!q.write_frames.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(q.write_frames, ec);
      for (std::size_t k = 0; k < frames->size(); ++k) {
        const metrics::Image& f = (*frames)[k];
        const std::string path = q.write_frames + "/" + (half ? "half_" : "step_") + std::to_string(k) + ".exr";
        if (auto st = sample::write_float_image(path, f.width, f.height, 3, f.rgb); !st.ok()) return cli::fail("caustix-bench", st.error());
      }
    }
  }
  auto pct = [](double v) { return 100.0 * v; };
  std::printf("%s,%s,%s,%s,%s,%g,%d,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,\"%s\"\n", label.c_str(),
              std::filesystem::path(q.cxb).filename().string().c_str(),
              q.inscatter ? "media" : runtime::to_string(q.caustics.method), runtime::to_string(q.caustics.glass_method),
              m.kind.c_str(), m.step, q.frames, at[0].rho, at[1].rho, at[0].rho > 0 ? at[1].rho / at[0].rho : 0.0,
              pct(at[0].flux_jump), pct(at[1].flux_jump), pct(at[0].peak_jump), pct(at[1].peak_jump),
              pct(at[0].focus_jump.value_or(0)), pct(at[1].focus_jump.value_or(0)), pct(at[0].peak_second), pct(at[1].peak_second),
              session->context->description().c_str());
  return 0;
}

class TemporalMode : public Modes {
 public:
  explicit TemporalMode(CLI::App& app) {
    cmd_ = app.add_subcommand("temporal",
                              "frame-to-frame stability: rho and the jumps of flux, peak and focus as the light, the water or an "
                              "object moves by a step and by half of it (one CSV line; docs/temporal.md)");
    cmd_->add_option("scene", q_.cxb, "baked scene (.cxb)")->required();
    cmd_->add_option("--motion", m_.kind, "what moves: light (the first light turns about z), water (time), object (along x)")
        ->check(CLI::IsMember({"light", "water", "object"}))
        ->required();
    cmd_->add_option("--step", m_.step, "per frame: degrees (light), seconds (water) or metres (object)")->required();
    cmd_->add_option("--object", m_.object, "--motion object: the object's name");
    cmd_->add_option("--receiver", q_.receiver, "irradiance images of this receiver");
    cmd_->add_flag("--inscatter", q_.inscatter, "in-scatter images of the scene's media instead (--region is x0,y0,x1,y1)");
    cmd_->add_option("--region", region_, "world rectangle x0,z0,x1,z1 (--inscatter: x0,y0,x1,y1)")->capture_default_str();
    cmd_->add_option("--frames", q_.frames, "frames per stack")->check(CLI::Range(3, 1000))->capture_default_str();
    cmd_->add_option("--size", q_.size, "image side in pixels")->check(CLI::Range(8, 4096))->capture_default_str();
    cmd_->add_option("--pixel-samples", q_.pixel_samples, "samples per pixel axis")->check(CLI::Range(1, 16))->capture_default_str();
    cmd_->add_option("--time", q_.time, "animation time of frame 0 (seconds)")->capture_default_str();
    cmd_->add_option("--focus-radius", q_.focus_radius, "focus power within this radius of the followed focus (metres)")
        ->check(CLI::Range(0.0, 100.0))
        ->capture_default_str();
    cmd_->add_option("--method", method_, "water caustics: levelmap, uniform, volumetric, splat, none (default: the file's)")
        ->check(CLI::IsMember({"levelmap", "uniform", "volumetric", "splat", "none"}));
    cmd_->add_option("--glass-method", glass_method_, "light through glass: table or caustic-map (default: the file's)")
        ->check(CLI::IsMember({"table", "caustic-map"}));
    cmd_->add_flag("--glass-no-focus", q_.glass_no_focus, "glass (table): no focus windows (docs/glass-focus.md)");
    cmd_->add_flag("--glass-focus-box", q_.glass_focus_box,
                   "glass (table): focus windows' texels by the box, not the tent (CausticsOptions::glass_focus_tent off)");
    cmd_->add_flag("--cmap-no-focus", q_.cmap_no_focus, "caustic maps: no focus window (docs/caustic-maps.md)");
    cmd_->add_option("--volume-focus", q_.volume_focus, "media: focus-grid voxels a side (0: none; default: the file's)")
        ->check(CLI::Range(0, 128));
    cmd_->add_option("--volume-refraction", q_.volume_refraction, "media: surface or gradient (VolumeOptions::surface_refraction)")
        ->check(CLI::IsMember({"surface", "gradient"}));
    cmd_->add_option("--write-frames", q_.write_frames, "write both stacks' images to this folder (step_K.exr, half_K.exr)");
    cmd_->add_option("--label", label_, "first CSV column");
    cmd_->add_flag("--header", header_, "print the CSV header first");
  }
  bool chosen() const override { return cmd_->parsed(); }
  int run() override {
    std::array<double, 4> rg{};
    char comma[3] = {};
    std::istringstream in(region_);
    if (!(in >> rg[0] >> comma[0] >> rg[1] >> comma[1] >> rg[2] >> comma[2] >> rg[3]) || comma[0] != ',' || comma[1] != ',' ||
        comma[2] != ',' || !(rg[2] > rg[0]) || !(rg[3] > rg[1])) {
      return cli::fail("caustix-bench", make_error(ErrorCode::kUsage, "bad --region '" + region_ + "'"));
    }
    if (!std::isfinite(m_.step) || m_.step == 0) return cli::fail("caustix-bench", make_error(ErrorCode::kUsage, "--step must be finite and not 0"));
    if (m_.kind == "object" && m_.object.empty()) return cli::fail("caustix-bench", make_error(ErrorCode::kUsage, "--motion object needs --object"));
    q_.region = rg;
    if (!method_.empty()) {
      q_.caustics.method = *runtime::parse_method(method_);
      q_.set_method = true;
    }
    if (!glass_method_.empty()) {
      q_.caustics.glass_method = *runtime::parse_glass_method(glass_method_);
      q_.set_glass_method = true;
    }
    if (header_) {
      std::printf("label,scene,method,glass_method,motion,step,frames,rho,rho_half,rho_ratio,flux_jump_pct,flux_jump_half_pct,"
                  "peak_jump_pct,peak_jump_half_pct,focus_jump_pct,focus_jump_half_pct,peak_second_pct,peak_second_half_pct,renderer\n");
    }
    return temporal(q_, m_, label_);
  }

 private:
  CLI::App* cmd_ = nullptr;
  Request q_;
  Motion m_;
  std::string region_ = "-1,-1,1,1", method_, glass_method_, label_ = "-";
  bool header_ = false;
};

}  // namespace

std::unique_ptr<Modes> add_temporal_mode(CLI::App& app) { return std::make_unique<TemporalMode>(app); }

}  // namespace caustix::bench
