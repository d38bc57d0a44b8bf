// caustix-bench's baker-side subcommands (full build only: they link the
// baker, CGAL, Embree and OpenImageIO).
//
//   caustix-bench bake-stages [--repeat N] [--map-size S] [--csv FILE]
//       Per model (sphere, teapot, organic) under flat water: import, frame,
//       position map by the rasteriser and by CGAL ray casting (one ray per
//       texel), depth profile; median of N runs; ray casts per second.
//   caustix-bench table-5-4 [--csv FILE]
//       Tipprasert 2006 table 5-4 on our code: smart-slicing planes for 3..28
//       specified planes, for the sphere, the teapot and the organic model.
//   caustix-bench ltt [--resolutions 8,12,...] [--samples N] [--min-cos C] [--normal-bits B] [--csv FILE]
//       Light-transport tables (Iwasaki et al.): per glass mesh (the unit sphere,
//       a 10k-vertex UV sphere, teapot_solid) and grid resolution R, the
//       stored table size, bake time and rays per second, and the look-up
//       error against direct traces at random (vertex, direction) pairs.
//   caustix-bench raycast [--rays N] [--csv FILE]
//       First-hit queries per second and agreement: CGAL's AABB tree (the
//       baker's and caustix-reference's RayCaster) against Embree 3.
//   caustix-bench tradeoff SCENE.json --reference REF.exr [--knobs a,b] [--base PRESET] [--csv FILE]
//       The speed/accuracy sweep of docs/tradeoff.md (tools/bench/tradeoff.h).


#include "bake_modes.h"

#include <CLI/CLI.hpp>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "caustix/bake/depth_profile.h"
#include "caustix/bake/light_transport.h"
#include "caustix/bake/mesh_compress.h"
#include "caustix/bake/mesh_import.h"
#include "caustix/bake/position_map.h"
#include "caustix/bake/ray_cast.h"
#include "caustix/common/cli.h"
#include "caustix/formats/frame.h"
#include "caustix/formats/mesh_decode.h"
#include "bench_common.h"
#include "tradeoff.h"

namespace caustix::bench {
namespace {

using namespace caustix::bake;

struct Model {
  const char* name;
  const char* file;
};
const Model kModels[] = {{"sphere", "sphere.obj"}, {"teapot", "teapot.obj"}, {"organic", "organic.obj"}};


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
  CsvOut out(csv,
      "model,triangles,map_size,threads,import_ms,frame_ms,raster_ms,raycast_ms,profile_ms,level_map_stages_ms,"
      "raycasts_per_s,raster_speedup");
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
    out.row(line);
  }
  return kExitOk;
}

int table_5_4(const std::string& meshes, const std::string& csv) {
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
  CsvOut out(csv, "specified,uniform_planes,sphere,teapot,organic");
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
    out.row(line);
  }
  return kExitOk;
}

// Rays from random points on a sphere around the mesh toward random points
// in its box (most hit, some graze or miss), traced by both engines.
int raycast(const std::string& meshes, int rays, const std::string& csv) {
  CsvOut out(csv,
      "model,triangles,threads,cgal_build_ms,embree_build_ms,cgal_rays_per_s,embree_rays_per_s,embree_speedup,"
      "hit_agreement,max_rel_distance_diff");
  std::vector<ImportedMesh> models;
  for (const Model& model : kModels) {
    auto m = import_mesh(meshes + model.file);
    if (!m) return cli::fail("caustix-bench", m.error());
    models.push_back(std::move(*m));
  }
  for (std::size_t mi = 0; mi < models.size(); ++mi) {
    const TriangleMesh& mesh = models[mi].mesh;
    const auto world = to_world(mesh);
    Vec3d lo = world[0], hi = world[0];
    for (const Vec3d& p : world) {
      for (std::size_t k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    }
    const Vec3d c{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    const double r = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    std::vector<std::pair<Vec3d, Vec3d>> queries;
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < rays; ++i) {
      const double z = 2 * u(rng) - 1, phi = 2 * 3.14159265358979 * u(rng), s = std::sqrt(1 - z * z);
      const Vec3d o{c[0] + r * s * std::cos(phi), c[1] + r * s * std::sin(phi), c[2] + r * z};
      const Vec3d t{lo[0] + (hi[0] - lo[0]) * u(rng), lo[1] + (hi[1] - lo[1]) * u(rng), lo[2] + (hi[2] - lo[2]) * u(rng)};
      Vec3d d{t[0] - o[0], t[1] - o[1], t[2] - o[2]};
      const double n = std::hypot(d[0], d[1], d[2]);
      for (double& x : d) x /= n;
      queries.emplace_back(o, d);
    }
    auto t0 = Clock::now();
    const RayCaster cgal(world, mesh.triangles, std::vector<std::uint32_t>(mesh.triangles.size(), 0));
    const double cgal_build = ms_since(t0);
    t0 = Clock::now();
    const EmbreeCaster embree(world, mesh.triangles);
    const double embree_build = ms_since(t0);
    std::vector<double> a(queries.size()), b(queries.size());
    auto run = [&](auto&& cast, std::vector<double>& dist) {
      const auto t = Clock::now();
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, queries.size()), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          dist[i] = cast(queries[i].first, queries[i].second).value_or(-1.0);
        }
      });
      return static_cast<double>(queries.size()) / (ms_since(t) / 1000.0);
    };
    const double cgal_rate = run([&](const Vec3d& o, const Vec3d& d) { return cgal.first_hit(o, d); }, a);
    const double embree_rate = run(
        [&](const Vec3d& o, const Vec3d& d) {
          const auto hit = embree.first_hit_triangle(o, d);
          return hit ? std::optional<double>(hit->distance) : std::nullopt;
        },
        b);
    std::size_t agree = 0;
    double max_rel = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if ((a[i] < 0) == (b[i] < 0)) ++agree;
      if (a[i] > 0 && b[i] > 0) max_rel = std::max(max_rel, std::fabs(a[i] - b[i]) / r);
    }
    char line[512];
    std::snprintf(line, sizeof line, "%s,%zu,%d,%.2f,%.2f,%.0f,%.0f,%.2f,%.6f,%.3g", kModels[mi].name,
                  mesh.triangles.size(), tbb::this_task_arena::max_concurrency(), cgal_build, embree_build, cgal_rate,
                  embree_rate, embree_rate / cgal_rate, static_cast<double>(agree) / static_cast<double>(a.size()),
                  max_rel);
    out.row(line);
  }
  return kExitOk;
}

// A UV sphere of radius 1 (`seg` segments x `rings` rings, poles shared,
// exact normals), as assets/meshes/generate.py sphere() makes it.
TriangleMesh uv_sphere(std::uint32_t seg, std::uint32_t rings) {
  TriangleMesh m;
  const double pi = 3.14159265358979323846;
  auto add = [&](double th, double ph) {
    const Vec3f p{static_cast<float>(std::sin(th) * std::cos(ph)), static_cast<float>(std::cos(th)),
                  static_cast<float>(std::sin(th) * std::sin(ph))};
    m.positions.push_back(p);
    m.normals.push_back(p);
  };
  add(0, 0);
  for (std::uint32_t r = 1; r < rings; ++r) {
    for (std::uint32_t s = 0; s < seg; ++s) add(pi * r / rings, 2 * pi * s / seg);
  }
  add(pi, 0);
  const auto ring = [&](std::uint32_t r, std::uint32_t s) { return 1 + (r - 1) * seg + s % seg; };
  const auto south = static_cast<std::uint32_t>(m.positions.size() - 1);
  for (std::uint32_t s = 0; s < seg; ++s) {
    m.triangles.push_back({0, ring(1, s + 1), ring(1, s)});
    for (std::uint32_t r = 1; r + 1 < rings; ++r) {
      m.triangles.push_back({ring(r, s), ring(r, s + 1), ring(r + 1, s + 1)});
      m.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r + 1, s)});
    }
    m.triangles.push_back({south, ring(rings - 1, s), ring(rings - 1, s + 1)});
  }
  return m;
}

struct ErrorStats {
  double max = 0, p99 = 0, p50 = 0, mean = 0, over_5 = 0;  // over_5: fraction above 5
};
ErrorStats stats(std::vector<double> v) {
  ErrorStats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.max = v.back();
  s.p99 = v[std::min(v.size() - 1, v.size() * 99 / 100)];
  s.p50 = v[v.size() / 2];
  for (double x : v) {
    s.mean += x / static_cast<double>(v.size());
    s.over_5 += x > 5 ? 1.0 / static_cast<double>(v.size()) : 0.0;
  }
  return s;
}

// Table size and look-up error against grid resolution (docs/glass-tables.md).
int ltt(const std::string& meshes, const std::vector<std::uint32_t>& resolutions, int samples, double min_cos,
        int normal_bits, const std::string& csv) {
  struct GlassMesh {
    std::string name;
    TriangleMesh mesh;
  };
  std::vector<GlassMesh> glass;
  for (const char* file : {"sphere.obj", "teapot_solid.obj"}) {
    auto m = import_mesh(meshes + file);
    if (!m) return cli::fail("caustix-bench", m.error());
    glass.push_back({std::string(file, std::strlen(file) - 4), std::move(m->mesh)});
  }
  glass.insert(glass.begin() + 1, GlassMesh{"sphere_10k", uv_sphere(144, 70)});
  for (GlassMesh& g : glass) {  // the baker tables the Draco-decoded mesh (quantised normals)
    DracoOptions draco;
    draco.normal_bits = normal_bits;
    auto stream = encode_draco(g.mesh, draco);
    if (!stream) return cli::fail("caustix-bench", stream.error());
    auto decoded = decode_draco(*stream, describe_mesh(g.mesh, draco));
    if (!decoded) return cli::fail("caustix-bench", decoded.error());
    g.mesh = std::move(*decoded);
  }
  Material glass_material;
  glass_material.ior = 1.5f;
  CsvOut out(csv,
      "mesh,vertices,resolution,interpolation,stored_bytes,bytes_per_vertex,mb_per_10k_vertices,bake_s,rays_per_s,"
      "lookups,dir_err_max_deg,dir_err_p99_deg,dir_err_p50_deg,dir_err_mean_deg,dir_err_over_5deg_pct,exit_err_max,exit_err_p99,t_err_max,t_err_p99");
  for (const GlassMesh& g : glass) {
    bake::TransportOptions opt;
    const TransportTracer tracer(glass_material, g.mesh, opt.max_bounces);
    // The same (vertex, direction) pairs for every resolution: directions
    // uniform over the part of the vertex's hemisphere with cos >= min_cos,
    // where the exact path leaves the object.
    struct Sample {
      std::uint32_t vertex;
      Dir3 normal, to_light;
      TransportEntry exact;
    };
    std::vector<Sample> pairs;
    std::mt19937_64 rng(1234);
    std::uniform_real_distribution<double> u(0, 1);
    while (pairs.size() < static_cast<std::size_t>(samples)) {
      const auto v = static_cast<std::uint32_t>(rng() % g.mesh.positions.size());
      const Dir3 n{g.mesh.normals[v][0], g.mesh.normals[v][1], g.mesh.normals[v][2]};
      Dir3 t, b;
      tangent_frame(n, t, b);
      const double z = min_cos + (1 - min_cos) * u(rng), phi = 2 * 3.14159265358979323846 * u(rng);
      const double r = std::sqrt(std::max(0.0, 1 - z * z));
      const Dir3 l{r * std::cos(phi), r * std::sin(phi), z};
      const Dir3 w{l[0] * t[0] + l[1] * b[0] + l[2] * n[0], l[0] * t[1] + l[1] * b[1] + l[2] * n[1],
                   l[0] * t[2] + l[1] * b[2] + l[2] * n[2]};
      const TransportEntry exact = tracer.trace(v, w);
      if (exact.status == TransportStatus::kLeaves) pairs.push_back({v, n, w, exact});
    }
    for (std::uint32_t res : resolutions) {
      opt.resolution = res;
      bake::TransportReport report;
      const LightTransportTable table = trace_transport_table(0, glass_material, g.mesh, opt, &report);
      const std::size_t stored = encode_transport_table(table).size();
      for (Interpolation mode : {Interpolation::kBilinear, Interpolation::kBicubic}) {
        std::vector<double> dir_err, exit_err, t_err;
        for (const Sample& s : pairs) {
          const TransportEntry got = lookup(table, s.vertex, s.normal, s.to_light, mode);
          const Dir3& a = s.exact.direction;
          const Dir3& d = got.direction;
          const double c = got.status == TransportStatus::kLeaves ? a[0] * d[0] + a[1] * d[1] + a[2] * d[2] : -1.0;
          dir_err.push_back(std::acos(std::clamp(c, -1.0, 1.0)) * 180 / 3.14159265358979323846);
          exit_err.push_back(std::hypot(s.exact.exit[0] - got.exit[0], s.exact.exit[1] - got.exit[1], s.exact.exit[2] - got.exit[2]));
          t_err.push_back(std::fabs(s.exact.transmittance - got.transmittance));
        }
        const ErrorStats de = stats(dir_err), ee = stats(exit_err), te = stats(t_err);
        const double per_vertex = static_cast<double>(stored) / table.vertex_count;
        char line[512];
        std::snprintf(line, sizeof line, "%s,%u,%u,%s,%zu,%.1f,%.2f,%.3f,%.0f,%zu,%.4f,%.4f,%.4f,%.4f,%.2f,%.5f,%.5f,%.5f,%.5f",
                      g.name.c_str(), table.vertex_count, res, to_string(mode), stored, per_vertex, per_vertex * 1e4 / 1e6,
                      report.seconds, static_cast<double>(report.rays) / report.seconds, pairs.size(), de.max, de.p99,
                      de.p50, de.mean, 100 * de.over_5, ee.max, ee.p99, te.max, te.p99);
        out.row(line);
      }
    }
  }
  return kExitOk;
}

struct BakeModes final : Modes {
  std::string meshes = std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/", csv;
  int repeat = 5, threads = 0;
  std::uint32_t size = 512;
  std::vector<std::uint32_t> resolutions{6, 8, 10, 12, 14, 16, 20, 24, 32};
  int samples = 4000;
  double min_cos = 0.3;
  int normal_bits = DracoOptions{}.normal_bits;
  int rays = 1'000'000;
  TradeoffRequest tq;
  std::string tsize = "640x480";
  CLI::App *stages = nullptr, *table = nullptr, *lt = nullptr, *ray_cmd = nullptr, *tr = nullptr;

  explicit BakeModes(CLI::App& app) {
    app.add_option("--meshes", meshes, "folder with sphere.obj, teapot.obj, organic.obj")->capture_default_str();
    app.add_option("--threads", threads, "worker threads, 0 = all cores")->check(CLI::Range(0, 1024));
    stages = app.add_subcommand("bake-stages", "level-map bake time per stage");
    stages->add_option("--repeat", repeat, "runs per model (median reported)")->check(CLI::Range(1, 1000))->capture_default_str();
    stages->add_option("--map-size", size, "position map size")->check(CLI::Range(1, 8192))->capture_default_str();
    stages->add_option("--csv", csv, "also write the table as CSV");
    table = app.add_subcommand("table-5-4", "specified vs actual planes under smart slicing");
    table->add_option("--csv", csv, "also write the table as CSV");
    lt = app.add_subcommand("ltt", "light-transport table size and look-up error against grid resolution");
    lt->add_option("--resolutions", resolutions, "grid resolutions R")->delimiter(',')->check(CLI::Range(2, 128));
    lt->add_option("--samples", samples, "random look-ups per mesh")->check(CLI::Range(1, 10000000))->capture_default_str();
    lt->add_option("--min-cos", min_cos, "smallest cosine between direction and vertex normal")
        ->check(CLI::Range(0.0, 1.0))->capture_default_str();
    lt->add_option("--normal-bits", normal_bits, "Draco normal quantisation of the glass meshes")
        ->check(CLI::Range(6, 30))->capture_default_str();
    lt->add_option("--csv", csv, "also write the table as CSV");
    ray_cmd = app.add_subcommand("raycast", "first-hit queries per second: CGAL AABB tree against Embree 3");
    ray_cmd->add_option("--rays", rays, "rays per model")->check(CLI::Range(1, 100'000'000))->capture_default_str();
    ray_cmd->add_option("--csv", csv, "also write the table as CSV");
    tr = app.add_subcommand("tradeoff", "cost and error against a reference, one knob at a time, and the presets");
    tr->add_option("scene", tq.scene_path, "scene description (scene.json)")->required();
    tr->add_option("--reference", tq.reference_path,
                   "caustix-reference irradiance image (EXR): receiver, region, size and time are taken from it")
        ->required();
    tr->add_option("--knobs", tq.knobs, "knobs to sweep (default: all that apply, then the presets)")
        ->delimiter(',')->check(CLI::IsMember(tradeoff_knobs()));
    tr->add_option("--base", tq.base, "preset each sweep starts from")->capture_default_str();
    tr->add_option("--size", tsize, "beauty frame size for ms per frame")->capture_default_str();
    tr->add_option("--warmup", tq.warmup, "frames not measured")->check(CLI::Range(0, 1000))->capture_default_str();
    tr->add_option("--frames", tq.frames, "frames measured (median)")->check(CLI::Range(1, 1000))->capture_default_str();
    tr->add_option("--pixel-samples", tq.pixel_samples,
                   "point samples per pixel and axis of the judged irradiance image (the reference's pixels are box "
                   "averages)")
        ->check(CLI::Range(1, 16))->capture_default_str();
    tr->add_option("--csv", tq.csv, "also write the rows as CSV");
  }

  bool chosen() const override { return *stages || *table || *lt || *ray_cmd || *tr; }

  int run() override {
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
    if (*stages) return bake_stages(meshes, repeat, size, csv);
    if (*ray_cmd) return raycast(meshes, rays, csv);
    if (*lt) return ltt(meshes, resolutions, samples, min_cos, normal_bits, csv);
    if (*tr) {
      if (!cli::parse_size(tsize, tq.frame_width, tq.frame_height)) {
        return cli::fail("caustix-bench", make_error(ErrorCode::kUsage, "bad --size"));
      }
      return tradeoff(tq);
    }
    return table_5_4(meshes, csv);
  }
};

}  // namespace

std::unique_ptr<Modes> add_bake_modes(CLI::App& app) { return std::make_unique<BakeModes>(app); }

}  // namespace caustix::bench
