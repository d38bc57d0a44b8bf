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
#include "caustix/bake/frame.h"
#include "caustix/bake/mesh_import.h"
#include "caustix/bake/position_map.h"
#include "caustix/bake/ray_cast.h"
#include "caustix/common/cli.h"

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
  if (auto rc = cli::parse(app, "caustix-bench", argc, argv)) return *rc;
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
  if (*stages) return bake_stages(meshes, repeat, size, csv);
  return table_5_4(meshes, csv);
}
