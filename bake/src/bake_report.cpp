// The bake report: what was baked, what was skipped and why, and where the
// time went.

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>

#include "caustix/bake/bake.h"

namespace caustix::bake {
namespace {

nlohmann::ordered_json vec(const Vec3f& v) { return {v[0], v[1], v[2]}; }

const char* slicing_name(Slicing s) { return s == Slicing::kSmart ? "smart" : "uniform"; }

const LevelMap* find_map(const BakeResult& r, std::uint32_t object, std::uint32_t light) {
  for (const LevelMap& m : r.level_maps.maps) {
    if (m.object == object && m.light == light) return &m;
  }
  return nullptr;
}

std::uint32_t empty_levels(const LevelMap& m) {
  return static_cast<std::uint32_t>(std::count(m.histogram.begin(), m.histogram.end(), 0u));
}

}  // namespace

std::string report_json(const BakeResult& r, const BakeOptions& opt) {
  nlohmann::ordered_json j;
  j["status"] = "ok";
  j["bytes"] = r.cxb.size();
  const auto& so = opt.level_maps.slicing;
  j["options"] = {{"position_bits", opt.draco.position_bits},
                  {"normal_bits", opt.draco.normal_bits},
                  {"draco_speed", opt.draco.speed},
                  {"planes", so.planes},
                  {"epsilon", so.epsilon ? nlohmann::ordered_json(*so.epsilon) : nlohmann::ordered_json(nullptr)},
                  {"levels", so.levels},
                  {"slicing", slicing_name(so.slicing)},
                  {"map_size", opt.level_maps.map_size},
                  {"water_grid_scale", opt.water_grid_scale}};
  if (r.scene.water) j["water_cells"] = r.scene.water->cells;
  j["meshes"] = nlohmann::ordered_json::array();
  for (const auto& m : r.meshes) {
    j["meshes"].push_back({{"path", m.path}, {"vertices", m.vertices}, {"triangles", m.triangles},
                           {"raw_bytes", m.raw_bytes}, {"draco_bytes", m.draco_bytes},
                           {"max_position_error", m.max_position_error},
                           {"max_world_error_m", m.max_world_error},
                           {"normals_from_file", m.normals_from_file}});
  }
  j["level_maps"] = nlohmann::ordered_json::array();
  for (const PairReport& p : r.level_maps.pairs) {
    nlohmann::ordered_json e;
    e["object"] = r.scene.objects[p.object].name;
    e["light"] = p.light;
    e["baked"] = p.baked;
    if (!p.baked) {
      e["skipped_because"] = p.reason;
    } else if (const LevelMap* m = find_map(r, p.object, p.light)) {
      const BoundingFrame& f = m->frame;
      e["frame"] = {{"origin", {f.origin[0], f.origin[1], f.origin[2]}},
                    {"U", vec(f.u)}, {"V", vec(f.v)}, {"W", vec(f.w)},
                    {"size", {2 * f.half[0], 2 * f.half[1], 2 * f.half[2]}},
                    {"symmetric_size_eq_4_3", vec(f.symmetric_size)}};
      e["map_size"] = m->map_size;
      e["covered_texels"] = p.covered_texels;
      e["depth_precision_m"] = p.depth_precision_m;
      e["histogram"] = m->histogram;
      e["empty_levels"] = empty_levels(*m);
      e["sub_boxes"] = nlohmann::ordered_json::array();
      for (const SubBox& b : m->sub_boxes) e["sub_boxes"].push_back({b.first_level, b.last_level});
      e["epsilon_m"] = m->epsilon;
      e["planes_uniform"] = m->uniform_planes.size();
      e["planes_smart"] = m->smart_planes.size();
      e["slicing"] = slicing_name(m->slicing);
      e["ms"] = {{"frame", p.ms_frame}, {"position_map", p.ms_position_map}, {"profile", p.ms_profile}};
      if (!p.warning.empty()) e["warning"] = p.warning;
    }
    j["level_maps"].push_back(e);
  }
  j["glass_refine"] = {{"crease_deg", opt.glass_refine.crease_deg},
                       {"flat_deg", opt.glass_refine.flat_deg},
                       {"max_edge_fraction", opt.glass_refine.max_edge},
                       {"max_turn_deg", opt.glass_refine.max_turn_deg},
                       {"meshes", nlohmann::ordered_json::array()}};
  for (const MeshStats& m : r.meshes) {
    if (!m.glass_refine) continue;
    const GlassRefineReport& g = *m.glass_refine;
    j["glass_refine"]["meshes"].push_back(
        {{"path", m.path}, {"vertices_in", g.vertices_in}, {"vertices_out", g.vertices_out},
         {"triangles_in", g.triangles_in}, {"triangles_out", g.triangles_out}, {"crease_edges", g.crease_edges},
         {"crease_vertices", g.crease_vertices}, {"flat_triangles_in", g.flat_triangles}, {"edges_split", g.edges_split},
         {"curved_edges_split", g.curved_edges_split}, {"max_turn_in", g.max_turn_in}, {"max_turn_out", g.max_turn_out},
         {"rounds", g.rounds}, {"max_edge", g.max_edge_m}, {"longest_flat_edge_in", g.longest_flat_edge_in},
         {"longest_flat_edge_out", g.longest_flat_edge_out}, {"stopped_at_vertex_limit", g.stopped_at_vertex_limit}});
  }
  j["transport"] = {{"resolution", opt.transport.resolution}, {"max_bounces", opt.transport.max_bounces}, {"bits", opt.transport.bits}, {"wavelengths", opt.transport.wavelengths},
                    {"rays", opt.transport.rays == RayEngine::kCgal ? "cgal" : "embree"}, {"switches", opt.transport.switches}, {"tables", nlohmann::ordered_json::array()}};
  for (const TransportReport& t : r.transport) {
    j["transport"]["tables"].push_back(
        {{"object", r.scene.objects[t.object].name}, {"wavelength_nm", t.wavelength_nm}, {"vertices", t.vertices}, {"entries", t.entries},
         {"leaving", t.leaving}, {"trapped", t.trapped}, {"occluded", t.occluded}, {"internally_reflected", t.reflected},
         {"switch_edges", t.switch_edges}, {"rays", t.rays}, {"seconds", t.seconds}, {"rays_per_second", t.seconds > 0 ? static_cast<double>(t.rays) / t.seconds : 0.0},
         {"raw_bytes", t.raw_bytes}, {"stored_bytes", t.stored_bytes},
         {"max_exit_position_error_m", t.position_error_m}, {"max_exit_direction_error_deg", t.direction_error_rad * 180.0 / 3.14159265358979}});
  }
  // Objects drawing another's tables, by name: {"copy": "source"}.
  j["transport"]["shared"] = nlohmann::ordered_json::object();
  for (const Object& o : r.scene.objects) {
    if (o.tables_from) j["transport"]["shared"][o.name] = r.scene.objects[*o.tables_from].name;
  }
  j["index_grids"] = {{"resolution", opt.index_grid.resolution}, {"blur", opt.index_grid.blur},
                      {"octree_epsilon", opt.index_grid.epsilon}, {"grids", nlohmann::ordered_json::array()}};
  for (const IndexGridReport& g : r.index_grids) {
    j["index_grids"]["grids"].push_back({{"object", r.scene.objects[g.object].name}, {"size", g.size}, {"voxel_m", g.voxel},
                                         {"stored_bytes", g.stored_bytes}, {"uniform_fraction", g.uniform_fraction},
                                         {"mean_step_voxels", g.mean_step}});
  }
  j["seconds"] = {{"import", r.seconds_import},
                  {"compress", r.seconds_compress},
                  {"level_maps", r.seconds_level_maps},
                  {"transport_tables", r.seconds_transport},
                  {"index_grids", r.seconds_index_grids},
                  {"oriented_boxes", r.level_maps.seconds_boxes},
                  {"reach_tests", r.level_maps.seconds_shadow_tests},
                  {"write", r.seconds_write}};
  j["peak_memory_bytes"] = r.peak_memory_bytes;
  j["warnings"] = r.warnings;
  return j.dump(2) + "\n";
}

std::string failure_report_json(const std::string& scene_path, const Error& error, int exit_code, const BakeLog& log) {
  nlohmann::ordered_json j;
  j["status"] = "failed";
  j["scene"] = scene_path;
  j["error"] = error.message;
  j["exit_code"] = exit_code;
  j["stages_done"] = nlohmann::ordered_json::array();
  for (const auto& [stage, seconds] : log.stages_done) j["stages_done"].push_back({{"stage", stage}, {"seconds", seconds}});
  j["failed_in"] = {{"stage", log.stage}, {"item", log.item}};
  j["warnings"] = log.warnings;
  return j.dump(2) + "\n";
}

std::string report_text(const BakeResult& r) {
  std::ostringstream s;
  char line[512];
  for (const auto& m : r.meshes) {
    std::snprintf(line, sizeof line, "  mesh %-36s %7u vertices %7u triangles  raw %8llu B  draco %7llu B  max error %.3g m%s\n",
                  m.path.c_str(), m.vertices, m.triangles, static_cast<unsigned long long>(m.raw_bytes),
                  static_cast<unsigned long long>(m.draco_bytes), m.max_world_error,
                  m.normals_from_file ? "" : "  (normals computed)");
    s << line;
  }
  for (const PairReport& p : r.level_maps.pairs) {
    const std::string& name = r.scene.objects[p.object].name;
    if (!p.baked) {
      s << "  level map " << name << " / light " << p.light << ": skipped, " << p.reason << "\n";
      continue;
    }
    const LevelMap* m = find_map(r, p.object, p.light);
    if (!m) continue;
    const BoundingFrame& f = m->frame;
    std::snprintf(line, sizeof line,
                  "  level map %s / light %u: V = (%.4f, %.4f, %.4f), frame %.3f x %.3f x %.3f m "
                  "(symmetric eq. 4-3: %.3f x %.3f x %.3f m)\n"
                  "    %u^2 map, %llu texels covered, depth precision %.3g m; %u of %zu levels empty; "
                  "planes: uniform %zu, smart %zu (eps %.4g m, %s in use); %.1f + %.1f + %.1f ms\n",
                  name.c_str(), p.light, f.v[0], f.v[1], f.v[2], 2 * f.half[0], 2 * f.half[1], 2 * f.half[2],
                  f.symmetric_size[0], f.symmetric_size[1], f.symmetric_size[2], m->map_size,
                  static_cast<unsigned long long>(p.covered_texels), p.depth_precision_m, empty_levels(*m),
                  m->histogram.size(), m->uniform_planes.size(), m->smart_planes.size(), m->epsilon,
                  slicing_name(m->slicing), p.ms_frame, p.ms_position_map, p.ms_profile);
    s << line;
    // The depth profile as a bar chart: at most 32 rows (levels merged),
    // level 0 (nearest the light) first; '.' marks an empty row.
    const std::size_t levels = m->histogram.size();
    const std::size_t rows = std::min<std::size_t>(levels, 32);
    std::vector<std::uint64_t> bins(rows, 0);
    for (std::size_t l = 0; l < levels; ++l) bins[l * rows / levels] += m->histogram[l];
    const std::uint64_t peak = std::max<std::uint64_t>(1, *std::max_element(bins.begin(), bins.end()));
    for (std::size_t b = 0; b < rows; ++b) {
      const auto width = static_cast<std::size_t>((bins[b] * 50 + peak - 1) / peak);
      std::snprintf(line, sizeof line, "    %6zu-%-6zu |%s%s %llu\n", b * levels / rows, (b + 1) * levels / rows - 1,
                    std::string(width, '#').c_str(), bins[b] == 0 ? "." : "", static_cast<unsigned long long>(bins[b]));
      s << line;
    }
  }
  std::map<std::uint32_t, std::uint32_t> copies;  // per table's object, the objects that use it too
  for (const Object& o : r.scene.objects) {
    if (o.tables_from) ++copies[*o.tables_from];
  }
  for (const TransportReport& t : r.transport) {
    if (copies.count(t.object) && t.wavelength_nm == 0) {
      std::snprintf(line, sizeof line, "  light-transport tables of '%s' also drawn by %u more objects\n", r.scene.objects[t.object].name.c_str(),
                    copies[t.object]);
      s << line;
    }
    std::snprintf(line, sizeof line,
                  "  light-transport table '%s'%s: %u vertices x %llu directions, %llu leave, %llu trapped, %llu occluded, "
                  "%llu after internal reflection or re-entry, %llu class switches; %.2f M rays in %.2f s (%.2f M rays/s); %llu B raw -> %llu B stored\n",
                  r.scene.objects[t.object].name.c_str(),
                  t.wavelength_nm > 0 ? (" at " + std::to_string(static_cast<int>(std::lround(t.wavelength_nm))) + " nm").c_str() : "",
                  t.vertices,
                  static_cast<unsigned long long>(t.vertices ? t.entries / t.vertices : 0),
                  static_cast<unsigned long long>(t.leaving), static_cast<unsigned long long>(t.trapped),
                  static_cast<unsigned long long>(t.occluded), static_cast<unsigned long long>(t.reflected),
                  static_cast<unsigned long long>(t.switch_edges), static_cast<double>(t.rays) * 1e-6, t.seconds, t.seconds > 0 ? static_cast<double>(t.rays) * 1e-6 / t.seconds : 0.0,
                  static_cast<unsigned long long>(t.raw_bytes), static_cast<unsigned long long>(t.stored_bytes));
    s << line;
  }
  for (const IndexGridReport& g : r.index_grids) {
    std::snprintf(line, sizeof line,
                  "  index grid '%s': %u x %u x %u voxels of %.4g m, %llu B stored; octree: %.1f %% of voxels in wider "
                  "nodes, mean step %.2f voxels\n",
                  r.scene.objects[g.object].name.c_str(), g.size[0], g.size[1], g.size[2], g.voxel,
                  static_cast<unsigned long long>(g.stored_bytes), 100.0 * g.uniform_fraction, g.mean_step);
    s << line;
  }
  std::snprintf(line, sizeof line,
                "  time: import %.3f s, compress %.3f s, level maps %.3f s (oriented boxes %.3f s, reach tests %.3f s), "
                "transport tables %.3f s, index grids %.3f s, write %.3f s\n",
                r.seconds_import, r.seconds_compress, r.seconds_level_maps, r.level_maps.seconds_boxes,
                r.level_maps.seconds_shadow_tests, r.seconds_transport, r.seconds_index_grids, r.seconds_write);
  s << line;
  std::snprintf(line, sizeof line, "  peak memory: %.1f MiB\n", static_cast<double>(r.peak_memory_bytes) / (1 << 20));
  s << line;
  return s.str();
}

}  // namespace caustix::bake
