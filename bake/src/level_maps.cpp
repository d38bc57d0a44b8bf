#include "caustix/bake/level_maps.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "caustix/formats/frame.h"
#include "caustix/bake/object_box.h"
#include "caustix/bake/position_map.h"
#include "caustix/bake/ray_cast.h"

namespace caustix::bake {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// At most `n` points spread evenly over the list (deterministic sampling).
std::vector<Vec3d> sample(const std::vector<Vec3d>& pts, std::size_t n) {
  if (pts.size() <= n) return pts;
  std::vector<Vec3d> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(pts[i * pts.size() / n]);
  return out;
}

constexpr std::size_t kReachSamples = 512;

// The box's axes through the transform's rotation, orthonormalised
// (right-handed).
std::array<Vec3d, 3> turned_axes(const Mat4f& t, const ObjectBox& box) {
  std::array<Vec3d, 3> a{};
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      a[i][k] = double{t[k]} * box.axes[i][0] + double{t[4 + k]} * box.axes[i][1] + double{t[8 + k]} * box.axes[i][2];
    }
  }
  const auto dot = [](const Vec3d& x, const Vec3d& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
  const auto unit = [&](Vec3d v) {
    const double n = std::sqrt(dot(v, v));
    for (double& c : v) c /= n;
    return v;
  };
  a[0] = unit(a[0]);
  const double along = dot(a[1], a[0]);
  for (std::size_t k = 0; k < 3; ++k) a[1][k] -= along * a[0][k];
  a[1] = unit(a[1]);
  const Vec3d c{a[0][1] * a[1][2] - a[0][2] * a[1][1], a[0][2] * a[1][0] - a[0][0] * a[1][2], a[0][0] * a[1][1] - a[0][1] * a[1][0]};
  a[2] = c;  // right-handed, as oriented_box's, also through a mirroring transform (the same box)
  return a;
}

// The tightest box along the given orthonormal axes holding the points.
ObjectBox box_along(const std::array<Vec3d, 3>& axes, const std::vector<Vec3d>& pts) {
  ObjectBox box;
  for (std::size_t i = 0; i < 3; ++i) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Vec3d& p : pts) {
      const double d = p[0] * axes[i][0] + p[1] * axes[i][1] + p[2] * axes[i][2];
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    box.half[i] = static_cast<float>((hi - lo) / 2);
    for (std::size_t k = 0; k < 3; ++k) {
      box.axes[i][k] = static_cast<float>(axes[i][k]);
      box.center[k] += (hi + lo) / 2 * axes[i][k];
    }
  }
  return box;
}

}  // namespace

Result<LevelMapStage> bake_level_maps(const SceneDesc& scene, const std::vector<TriangleMesh>& meshes,
                                      const LevelMapOptions& opt, const std::function<void(double)>& progress) {
  LevelMapStage out;
  const std::size_t n_obj = scene.objects.size();
  std::vector<std::vector<Vec3d>> world(n_obj);
  for (std::size_t i = 0; i < n_obj; ++i) world[i] = world_points(scene.objects[i].transform, meshes[scene.objects[i].mesh_index].positions);

  // Oriented boxes for culling (CGAL), one per object. Objects that draw
  // one mesh through a rotation, translation and uniform scale (copies of a
  // ball) share the orientation of the mesh's own box: the optimiser, 0.35 s
  // for an 8 k-vertex ball, runs once per mesh in object space,
  // and each object's box is fitted to its own points along those axes.
  auto t0 = Clock::now();
  out.boxes.resize(n_obj);
  std::vector<std::uint32_t> copies(meshes.size(), 0);
  for (const Object& o : scene.objects) copies[o.mesh_index] += is_similarity(o.transform) ? 1 : 0;
  std::vector<std::size_t> shared_meshes;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    if (copies[m] > 1) shared_meshes.push_back(m);
  }
  std::vector<ObjectBox> mesh_box(meshes.size());
  tbb::parallel_for(std::size_t{0}, shared_meshes.size(), [&](std::size_t k) {
    const std::size_t m = shared_meshes[k];
    mesh_box[m] = oriented_box(world_points(Mat4f{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, meshes[m].positions));
  });
  tbb::parallel_for(std::size_t{0}, n_obj, [&](std::size_t i) {
    const Object& o = scene.objects[i];
    out.boxes[i] = copies[o.mesh_index] > 1 && is_similarity(o.transform) ? box_along(turned_axes(o.transform, mesh_box[o.mesh_index]), world[i])
                                                                          : oriented_box(world[i]);
    out.boxes[i].object = static_cast<std::uint32_t>(i);
  });
  out.seconds_boxes = std::chrono::duration<double>(Clock::now() - t0).count();

  // Every (receiver, light) pair, with the reason it needs no level map.
  struct Job {
    std::uint32_t object, light;
    LightDirection dir;
  };
  std::vector<Job> jobs;
  for (std::uint32_t oi = 0; oi < n_obj; ++oi) {
    const Object& o = scene.objects[oi];
    if (!is_receiver(o.role)) continue;
    double min_y = world[oi][0][1], max_y = min_y;
    for (const auto& p : world[oi]) {
      min_y = std::min(min_y, p[1]);
      max_y = std::max(max_y, p[1]);
    }
    const Vec3d origin{o.transform[12], o.transform[13], o.transform[14]};
    for (std::uint32_t li = 0; li < scene.lights.size(); ++li) {
      PairReport rep;
      rep.object = oi;
      rep.light = li;
      std::string why;
      if (!scene.water) {
        rep.reason = "no water in the scene (level maps serve water caustics; glass uses light-transport tables)";
      } else if (min_y >= scene.water->level) {
        rep.reason = "entirely above the water";
      } else if (auto d = light_direction(scene.lights[li], scene.water, origin, min_y, max_y, &why)) {
        jobs.push_back(Job{oi, li, *d});
        rep.baked = true;  // provisional: the reach tests below may still skip it
      } else {
        rep.reason = why;
      }
      out.pairs.push_back(rep);
    }
  }

  // Reach: trace sampled receiver points back toward the light (along V) to
  // the water plane; they must land on the water grid and not be blocked by
  // another opaque object on the way.
  t0 = Clock::now();
  std::vector<Vec3d> all_pos;
  std::vector<std::array<std::uint32_t, 3>> all_tris;
  std::vector<std::uint32_t> owner;
  for (std::uint32_t i = 0; i < n_obj; ++i) {
    if (transmits(scene.objects[i].role)) continue;  // glass does not cast plain shadows
    const auto base = static_cast<std::uint32_t>(all_pos.size());
    all_pos.insert(all_pos.end(), world[i].begin(), world[i].end());
    for (const auto& t : meshes[scene.objects[i].mesh_index].triangles) {
      all_tris.push_back({base + t[0], base + t[1], base + t[2]});
      owner.push_back(i);
    }
  }
  std::vector<std::string> skip_reason(jobs.size()), coverage(jobs.size());
  // Progress: each pair's reach test, then its map.
  std::atomic<std::size_t> steps{0};
  const auto step = [&] {
    const std::size_t s = ++steps;
    if (progress) progress(double(s) / double(2 * jobs.size()));
  };
  if (!jobs.empty()) {
    const RayCaster occluders(all_pos, all_tris, owner);
    tbb::parallel_for(std::size_t{0}, jobs.size(), [&](std::size_t j) {
      step();  // counted as it starts: the test returns early in several places
      const Job& job = jobs[j];
      const Vec3d v{-job.dir.travel[0], -job.dir.travel[1], -job.dir.travel[2]};
      const Water& w = *scene.water;
      // Scale for the ray offset that keeps a sample off its own surface.
      const ObjectBox& b = out.boxes[job.object];
      const double scale = 1e-6 * std::max({double{b.half[0]}, double{b.half[1]}, double{b.half[2]}, 1e-3});
      bool on_grid = false, lit = false;
      for (const Vec3d& p : sample(world[job.object], kReachSamples)) {
        if (p[1] >= w.level || v[1] <= 0) {  // above the water: reached directly
          on_grid = lit = true;
          break;
        }
        const double s = (w.level - p[1]) / v[1];
        const double x = p[0] + s * v[0], z = p[2] + s * v[2];
        if (x < w.extent[0] || x > w.extent[2] || z < w.extent[1] || z > w.extent[3]) continue;
        on_grid = true;
        const Vec3d o{p[0] + scale * v[0], p[1] + scale * v[1], p[2] + scale * v[2]};
        const auto hit = occluders.first_hit(o, v, job.object);
        if (!hit || *hit > s) {
          lit = true;
          break;
        }
      }
      if (!on_grid) skip_reason[j] = "no refracted ray from the water grid reaches it";
      else if (!lit) skip_reason[j] = "fully shadowed by other objects";
      if (!on_grid || !lit || v[1] <= 0) return;
      // The grid's coverage: a receiver's vertex under the water,
      // facing the light, whose refracted ray back toward the light (flat
      // water) leaves the water grid before reaching the surface, and
      // meets nothing on the way (so it is no shadow anyway), lies in a
      // strip the water's light never reaches. The ray's horizontal run
      // past each edge is how far the grid must overhang there (an affine
      // function of the point: its largest value over a mesh is at a vertex).
      const Object& obj = scene.objects[job.object];
      const std::vector<Vec3d> normals = world_normals(obj.transform, meshes[obj.mesh_index].normals);
      std::array<double, 4> need{0, 0, 0, 0};  // past x0, z0, x1, z1
      Vec3d centre{0, 0, 0};
      for (const Vec3d& p : world[job.object]) {
        for (std::size_t c = 0; c < 3; ++c) centre[c] += p[c] / static_cast<double>(world[job.object].size());
      }
      std::size_t facing = 0, dark = 0;
      const double tol = 1e-6 * std::max({double{w.extent[2] - w.extent[0]}, double{w.extent[3] - w.extent[1]}, 1e-3});
      for (std::size_t k = 0; k < world[job.object].size() && k < normals.size(); ++k) {
        const Vec3d& p = world[job.object][k];
        const Vec3d& n = normals[k];
        if (p[1] >= w.level || n[0] * v[0] + n[1] * v[1] + n[2] * v[2] <= 0) continue;
        ++facing;
        const double s = (w.level - p[1]) / v[1];
        const double x = p[0] + s * v[0], z = p[2] + s * v[2];
        const std::array<double, 4> past{w.extent[0] - x, w.extent[1] - z, x - w.extent[2], z - w.extent[3]};
        if (*std::max_element(past.begin(), past.end()) <= tol) continue;
        // From just inside the receiver: a vertex on a wall's foot (a pool's
        // floor edge) would otherwise start its ray on the wall's plane and
        // pass behind it.
        const Vec3d q{p[0] + 1e-4 * (centre[0] - p[0]), p[1] + 1e-4 * (centre[1] - p[1]), p[2] + 1e-4 * (centre[2] - p[2])};
        const Vec3d o{q[0] + scale * v[0], q[1] + scale * v[1], q[2] + scale * v[2]};
        if (const auto hit = occluders.first_hit(o, v, std::numeric_limits<std::uint32_t>::max()); hit && *hit < s) continue;
        ++dark;
        for (std::size_t e = 0; e < 4; ++e) need[e] = std::max(need[e], past[e]);
      }
      if (dark == 0) return;
      static constexpr const char* kEdge[4] = {"-x", "-z", "+x", "+z"};
      std::string sides;
      for (std::size_t e = 0; e < 4; ++e) {
        if (need[e] <= tol) continue;
        char buf[96];
        std::snprintf(buf, sizeof buf, "%s%.3g m on %s", sides.empty() ? "" : ", ", need[e], kEdge[e]);
        sides += buf;
      }
      coverage[j] = "the water grid does not reach far enough: " + std::to_string(dark) + " of its " + std::to_string(facing) +
                    " lit vertices under the water get none of this light, whose refracted rays would cross the water's "
                    "surface outside the grid (a dark strip along the receiver's edge); extend the water's extent by " +
                    sides + " (docs/scene-format.md, water)";
    });
  }
  out.seconds_shadow_tests = std::chrono::duration<double>(Clock::now() - t0).count();

  // Frames, position maps and depth profiles, in parallel over pairs; each
  // result has its own slot, so the output does not depend on scheduling.
  std::vector<LevelMap> maps(jobs.size());
  std::vector<PairReport> reports(jobs.size());
  tbb::parallel_for(std::size_t{0}, jobs.size(), [&](std::size_t j) {
    if (!skip_reason[j].empty()) {
      step();
      return;
    }
    const Job& job = jobs[j];
    const Object& o = scene.objects[job.object];
    const TriangleMesh& mesh = meshes[o.mesh_index];
    PairReport& rep = reports[j];
    LevelMap& m = maps[j];
    m.object = job.object;
    m.light = job.light;
    m.map_size = opt.map_size;
    auto t = Clock::now();
    m.frame = make_frame(job.dir.travel, world[job.object], {o.transform[12], o.transform[13], o.transform[14]});
    rep.ms_frame = ms_since(t);
    t = Clock::now();
    rasterize_position_map(world[job.object], mesh.triangles, o.material.albedo, m);
    rep.ms_position_map = ms_since(t);
    t = Clock::now();
    build_depth_profile(m, opt.slicing, &rep.warning);
    rep.ms_profile = ms_since(t);
    for (std::uint16_t q : m.depth) rep.covered_texels += q != kEmptyDepth ? 1 : 0;
    rep.depth_precision_m = depth_precision(m.frame);
    step();
  });

  // Merge in (object, light) order.
  std::size_t j = 0;
  for (PairReport& rep : out.pairs) {
    if (!rep.baked) continue;
    if (!skip_reason[j].empty()) {
      rep.baked = false;
      rep.reason = skip_reason[j];
    } else {
      PairReport& r = reports[j];
      rep.ms_frame = r.ms_frame;
      rep.ms_position_map = r.ms_position_map;
      rep.ms_profile = r.ms_profile;
      rep.covered_texels = r.covered_texels;
      rep.depth_precision_m = r.depth_precision_m;
      rep.warning = r.warning;
      if (!coverage[j].empty()) rep.warning += (rep.warning.empty() ? "" : "; ") + coverage[j];
      out.maps.push_back(std::move(maps[j]));
    }
    ++j;
  }
  return out;
}

}  // namespace caustix::bake
