// caustix-bench: measurements behind docs/ (not timed tests).
//
//   caustix-bench bake-stages [--repeat N] [--map-size S] [--csv FILE]
//       Per model (sphere, teapot, organic) under flat water: import, frame,
//       position map by the rasteriser and by CGAL ray casting (one ray per
//       texel), depth profile; median of N runs; ray casts per second.
//   caustix-bench table-5-4 [--csv FILE]
//       Seed 000 table 5-4 on our code: smart-slicing planes for 3..28
//       specified planes, for the sphere, the teapot and the organic model.

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "caustix/bake/depth_profile.h"
#include "caustix/formats/frame.h"
#include "caustix/bake/mesh_import.h"
#include "caustix/bake/position_map.h"
#include "caustix/bake/ray_cast.h"
#include "caustix/common/cli.h"
#include "caustix/metrics/image_metrics.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/runtime/renderer.h"

namespace {

using namespace caustix;
using namespace caustix::bake;
using Clock = std::chrono::steady_clock;

struct Model {
  const char* name;
  const char* file;
};
const Model kModels[] = {{"sphere", "sphere.obj"}, {"teapot", "teapot.obj"}, {"organic", "organic.obj"}};

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Refracted direction of a sun 20 degrees from vertical through water n = 1.33.
Vec3d sun_travel(double deg) {
  const double th = deg * 3.14159265358979 / 180;
  return *refract({std::sin(th), -std::cos(th), 0}, {0, 1, 0}, 1 / 1.33);
}

std::vector<Vec3d> to_world(const TriangleMesh& m) {
  std::vector<Vec3d> w;
  for (const auto& p : m.positions) w.push_back({p[0], p[1], p[2]});
  return w;
}

int bake_stages(const std::string& meshes, int repeat, std::uint32_t size, const std::string& csv) {
  std::ofstream out;
  if (!csv.empty()) out.open(csv);
  const std::string header =
      "model,triangles,map_size,threads,import_ms,frame_ms,raster_ms,raycast_ms,profile_ms,level_map_stages_ms,"
      "raycasts_per_s,raster_speedup";
  std::printf("%s\n", header.c_str());
  if (out) out << header << "\n";
  const int threads = tbb::this_task_arena::max_concurrency();
  for (const Model& model : kModels) {
    std::vector<double> imp, frame, raster, cast, profile;
    ImportedMesh mesh;
    for (int r = 0; r < repeat; ++r) {
      auto t = Clock::now();
      auto m = import_mesh(meshes + model.file);
      if (!m) return cli::fail("caustix-bench", m.error());
      imp.push_back(ms_since(t));
      mesh = std::move(*m);
      const auto world = to_world(mesh.mesh);
      LevelMap lm;
      lm.map_size = size;
      t = Clock::now();
      lm.frame = make_frame(sun_travel(20), world, {0, 0, 0});
      frame.push_back(ms_since(t));
      t = Clock::now();
      rasterize_position_map(world, mesh.mesh.triangles, {1, 1, 1}, lm);
      raster.push_back(ms_since(t));
      // The same map by ray casting through CGAL's AABB tree.
      t = Clock::now();
      const RayCaster caster(world, mesh.mesh.triangles, std::vector<std::uint32_t>(mesh.mesh.triangles.size(), 0));
      std::vector<double> depth(std::size_t{size} * size);
      const Vec3d down{-lm.frame.v[0], -lm.frame.v[1], -lm.frame.v[2]};
      tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, size), [&](const auto& rows) {
        for (std::uint32_t row = rows.begin(); row != rows.end(); ++row) {
          for (std::uint32_t col = 0; col < size; ++col) {
            const auto uw = texel_center(lm.frame, size, row, col);
            const auto hit = caster.first_hit(from_frame(lm.frame, {uw[0], lm.frame.half[1] + 1.0, uw[1]}), down);
            depth[std::size_t{row} * size + col] = hit ? *hit : -1;
          }
        }
      });
      cast.push_back(ms_since(t));
      t = Clock::now();
      build_depth_profile(lm, SlicingOptions{}, nullptr);
      profile.push_back(ms_since(t));
    }
    const double stages = median(frame) + median(raster) + median(profile);
    char line[512];
    std::snprintf(line, sizeof line, "%s,%zu,%u,%d,%.2f,%.3f,%.2f,%.2f,%.3f,%.2f,%.0f,%.1f", model.name,
                  mesh.mesh.triangles.size(), size, threads, median(imp), median(frame), median(raster), median(cast),
                  median(profile), stages, double(size) * size / (median(cast) / 1000.0), median(cast) / median(raster));
    std::printf("%s\n", line);
    if (out) out << line << "\n";
  }
  return kExitOk;
}

int table_5_4(const std::string& meshes, const std::string& csv) {
  std::ofstream out;
  if (!csv.empty()) out.open(csv);
  std::vector<LevelMap> maps;
  for (const Model& model : kModels) {
    auto m = import_mesh(meshes + model.file);
    if (!m) return cli::fail("caustix-bench", m.error());
    const auto world = to_world(m->mesh);
    LevelMap lm;
    lm.map_size = 512;
    lm.frame = make_frame({0, -1, 0}, world, {0, 0, 0});  // light from straight above, as in ch. 5
    rasterize_position_map(world, m->mesh.triangles, {1, 1, 1}, lm);
    maps.push_back(std::move(lm));
  }
  const std::string header = "specified,uniform_planes,sphere,teapot,organic";
  std::printf("%s\n", header.c_str());
  if (out) out << header << "\n";
  for (std::uint32_t n = 3; n <= 28; ++n) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%u,%u", n, n + 1);
    std::string line = buf;
    for (LevelMap& lm : maps) {
      SlicingOptions o;
      o.planes = n;
      o.levels = 64;
      build_depth_profile(lm, o, nullptr);
      std::snprintf(buf, sizeof buf, ",%zu", lm.smart_planes.size());
      line += buf;
    }
    std::printf("%s\n", line.c_str());
    if (out) out << line << "\n";
  }
  return kExitOk;
}

// A baked scene loaded into a headless context and a renderer.
struct Session {
  std::unique_ptr<runtime::HeadlessContext> context;
  std::unique_ptr<runtime::Renderer> renderer;
};
Result<Session> open_scene(const std::string& cxb) {
  auto scene = runtime::load_scene_file(cxb);
  if (!scene) return scene.error();
  auto ctx = runtime::HeadlessContext::create();
  if (!ctx) return ctx.error();
  auto r = runtime::Renderer::create(*scene);
  if (!r) return r.error();
  return Session{std::move(*ctx), std::move(*r)};
}

// Milliseconds per frame of the runtime on a baked scene, median of
// `frames` after `warmup` frames; the animation advances 1/30 s per frame.
int frames(const std::string& cxb, const runtime::CausticsOptions& co, int width, int height, int warmup, int count,
           const std::string& label, bool move_light) {
  auto session = open_scene(cxb);
  if (!session) return cli::fail("caustix-bench", session.error());
  auto& r = session->renderer;
  auto& ctx = session->context;
  runtime::FrameParams f{r->default_camera(), 0.0f, width, height, co};
  std::vector<double> ms;
  for (int i = 0; i < warmup + count; ++i) {
    f.time = static_cast<float>(i) / 30.0f;
    const auto t = Clock::now();
    if (move_light && !r->scene().lights.empty()) {
      // Turn the first light 2 degrees about the vertical each frame: its
      // level maps are re-derived on the GPU every frame.
      Light l = r->scene().lights[0];
      const float c = std::cos(0.0349f), sn = std::sin(0.0349f);
      const float x = l.direction[0], z = l.direction[2];
      l.direction[0] = c * x - sn * z;
      l.direction[2] = sn * x + c * z;
      if (Status st = r->set_light(0, l); !st) return cli::fail("caustix-bench", st.error());
    }
    if (Status st = r->render(f); !st) return cli::fail("caustix-bench", st.error());
    r->finish();
    if (i >= warmup) ms.push_back(ms_since(t));
  }
  const runtime::CausticsStats cs = r->caustics_stats();
  std::printf("%s,%s,%s,%u,%d,%dx%d,%.2f,%.2f,%llu,%llu,%llu,%.1f,\"%s\"\n", label.c_str(), cxb.c_str(),
              runtime::to_string(co.method), co.planes.value_or(0), co.cull ? 1 : 0, width, height, median(ms),
              *std::min_element(ms.begin(), ms.end()), static_cast<unsigned long long>(cs.planes_drawn),
              static_cast<unsigned long long>(cs.volumes_drawn), static_cast<unsigned long long>(cs.volumes_total),
              static_cast<double>(cs.gpu_bytes) / 1e6, ctx->description().c_str());
  return kExitOk;
}

// Seed 000 table 5-5 on our code: the eq. 2-9 difference between the
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
    runtime::FrameParams f{r->default_camera(), 1.0f, width, height, co};
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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"caustix-bench: measurements for docs/"};
  app.require_subcommand(1);
  std::string meshes = std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/", csv;
  int repeat = 5, threads = 0;
  std::uint32_t size = 512;
  app.add_option("--meshes", meshes, "folder with sphere.obj, teapot.obj, organic.obj")->capture_default_str();
  app.add_option("--threads", threads, "worker threads, 0 = all cores")->check(CLI::Range(0, 1024));
  auto* stages = app.add_subcommand("bake-stages", "level-map bake time per stage");
  stages->add_option("--repeat", repeat, "runs per model (median reported)")->check(CLI::Range(1, 1000))->capture_default_str();
  stages->add_option("--map-size", size, "position map size")->check(CLI::Range(1, 8192))->capture_default_str();
  stages->add_option("--csv", csv, "also write the table as CSV");
  auto* table = app.add_subcommand("table-5-4", "specified vs actual planes under smart slicing");
  table->add_option("--csv", csv, "also write the table as CSV");
  std::string cxb, method = "levelmap", label = "-", fsize = "640x480";
  std::uint32_t planes = 0;
  int warmup = 3, count = 10;
  bool no_cull = false, header = false;
  auto* fr = app.add_subcommand("frames", "ms per frame of the runtime on a baked scene (one CSV line)");
  fr->add_option("scene", cxb, "baked scene (.cxb)")->required();
  fr->add_option("--method", method, "levelmap, uniform, volumetric, none")
      ->check(CLI::IsMember({"levelmap", "uniform", "volumetric", "none"}))->capture_default_str();
  fr->add_option("--planes", planes, "re-slice with n planes (0: as baked)")->check(CLI::Range(0, 4096));
  fr->add_option("--size", fsize, "image size WxH")->capture_default_str();
  fr->add_option("--warmup", warmup, "frames not measured")->capture_default_str();
  fr->add_option("--frames", count, "frames measured (median reported)")->check(CLI::Range(1, 100000))->capture_default_str();
  std::uint32_t csize = 512;
  fr->add_option("--caustics-size", csize, "caustics map size")->check(CLI::Range(1, 8192))->capture_default_str();
  fr->add_flag("--no-cull", no_cull, "draw every volume through every plane, as the thesis did");
  fr->add_option("--label", label, "first CSV column");
  fr->add_flag("--header", header, "print the CSV header first");
  bool move_light = false;
  fr->add_flag("--move-light", move_light, "turn the first light every frame (level maps re-derived each frame)");
  auto* me = app.add_subcommand("methods", "eq. 2-9 differences between methods (one CSV line)");
  me->add_option("scene", cxb, "baked scene (.cxb)")->required();
  me->add_option("--planes", planes, "re-slice with n planes (0: as baked)")->check(CLI::Range(0, 4096));
  me->add_option("--size", fsize, "image size WxH")->capture_default_str();
  me->add_option("--label", label, "first CSV column");
  me->add_flag("--header", header, "print the CSV header first");
  if (auto rc = cli::parse(app, "caustix-bench", argc, argv)) return *rc;
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
  if (*stages) return bake_stages(meshes, repeat, size, csv);
  if (*me) {
    if (header) std::printf("label,scene,planes,eq29_smart_vs_uniform,eq29_uniform_vs_volumetric,eq29_smart_vs_none\n");
    int w = 0, h = 0;
    if (!cli::parse_size(fsize, w, h)) return cli::fail("caustix-bench", make_error(ErrorCode::kUsage, "bad --size"));
    return methods(cxb, planes, w, h, label);
  }
  if (*fr) {
    if (header) {
      std::printf("label,scene,method,planes,cull,size,median_ms,min_ms,planes_drawn,primitives_drawn,volumes_total,gpu_mb,renderer\n");
    }
    runtime::CausticsOptions co;
    co.method = *runtime::parse_method(method);
    if (planes > 0) co.planes = planes;
    co.cull = !no_cull;
    co.map_size = csize;
    int w = 0, h = 0;
    if (!cli::parse_size(fsize, w, h)) return cli::fail("caustix-bench", make_error(ErrorCode::kUsage, "bad --size"));
    return frames(cxb, co, w, h, warmup, count, label, move_light);
  }
  return table_5_4(meshes, csv);
}
