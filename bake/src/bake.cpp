#include "caustix/bake/bake.h"

#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <optional>

#include "caustix/bake/glass_refine.h"
#include "caustix/bake/light_transport.h"
#include "caustix/bake/mesh_import.h"
#include "caustix/bake/scene_json.h"
#include "caustix/bake/texture_import.h"
#include "caustix/common/mesh_topology.h"
#include "caustix/formats/frame.h"
#include "caustix/formats/mesh_decode.h"
#include "caustix/formats/scene.h"

namespace caustix::bake {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Light transport runs inside transparent objects (Iwasaki et al. §3): they must
// bound a solid, wound outward. Returns what is wrong, naming up to five
// edges (0-based vertex indices and the first vertex's position);
// `closed` says whether the surface is closed (no boundary edge);
// `inside_out` that it is a solid wound inside out: closed, manifold,
// consistently wound, its signed volume negative and not a rounding's
// worth of its bounding box (a closed sheet encloses no volume), so that
// reversing every triangle makes it a solid.
struct SolidIssue {
  std::string what;
  bool closed = false;
  bool inside_out = false;
};
std::optional<SolidIssue> closed_solid_issue(const TriangleMesh& mesh) {
  const EdgeCensus c = census_edges(mesh);
  const std::array<std::pair<const std::vector<EdgeCensus::Edge>*, const char*>, 3> kinds{{
      {&c.open, "boundary edge(s) of holes"},
      {&c.inconsistent, "edge(s) whose two triangles are wound inconsistently"},
      {&c.non_manifold, "non-manifold edge(s) (more than two triangles)"}}};
  std::string counts, first;
  for (const auto& [edges, what] : kinds) {
    if (edges->empty()) continue;
    counts += (counts.empty() ? "" : ", ") + std::to_string(edges->size()) + " " + what;
    if (!first.empty()) continue;
    for (std::size_t k = 0; k < std::min<std::size_t>(edges->size(), 5); ++k) {
      const auto& e = (*edges)[k];
      const auto& p = mesh.positions[e.first];
      first += (k ? ", " : "") + std::to_string(e.first) + "-" + std::to_string(e.second) + " at (" + std::to_string(p[0]) +
               ", " + std::to_string(p[1]) + ", " + std::to_string(p[2]) + ")";
    }
    first = std::string("first: ") + first + (edges->size() > 5 ? ", ..." : "");
  }
  if (!counts.empty()) {
    return SolidIssue{"is not a closed, consistently wound mesh: it has " + counts + "; " + first + " (vertex indices, 0-based)", c.open.empty()};
  }
  if (!(c.signed_volume > 0)) {
    std::array<double, 3> lo{}, hi{};
    for (std::size_t k = 0; k < 3; ++k) lo[k] = hi[k] = mesh.positions.empty() ? 0.0 : mesh.positions[0][k];
    for (const auto& p : mesh.positions) {
      for (std::size_t k = 0; k < 3; ++k) lo[k] = std::min<double>(lo[k], p[k]), hi[k] = std::max<double>(hi[k], p[k]);
    }
    const double diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    const bool inside_out = c.signed_volume < -1e-6 * diagonal * diagonal * diagonal;
    return SolidIssue{std::string(inside_out ? "is wound inside out" : "encloses no volume") + " (signed volume " +
                          std::to_string(c.signed_volume) + " m^3 in object space); its triangles must wind counter-clockwise seen from outside",
                      true, inside_out};
  }
  return std::nullopt;
}

// Reverses every triangle's winding. Normals from the file are kept when
// they already point out of the turned solid (an exporter that wrote
// outward normals over reversed triangles) and negated when they point in
// (a modeller's "flip normals" turns both); says which.
std::string turn_outside_out(TriangleMesh& mesh) {
  double agree = 0;
  for (auto& t : mesh.triangles) {
    std::swap(t[1], t[2]);
    if (mesh.normals.size() != mesh.positions.size()) continue;
    const auto &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const std::array<double, 3> n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    for (std::uint32_t i : t) agree += n[0] * mesh.normals[i][0] + n[1] * mesh.normals[i][1] + n[2] * mesh.normals[i][2];
  }
  if (agree >= 0) return "its triangles reversed";
  for (auto& n : mesh.normals) n = {-n[0], -n[1], -n[2]};
  return "its triangles and normals reversed";
}

// The runtime draws in float world coordinates, spaced |x| 2^-23 apart near
// x (10 km: 1 mm). An object smaller than 1000 such spacings loses its shape
// on the GPU; nothing in the file can fix that, so say so.
std::optional<std::string> float_precision_warning(const Object& o, const TriangleMesh& mesh) {
  const std::vector<Vec3d> world = world_points(o.transform, mesh.positions);
  Vec3d lo = world.front(), hi = lo;
  double reach = 0;
  for (const Vec3d& p : world) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
      reach = std::max(reach, std::abs(p[k]));
    }
  }
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const double spacing = reach * std::ldexp(1.0, -23);
  if (!(extent < 1000 * spacing)) return std::nullopt;
  return "object '" + o.name + "' is " + std::to_string(extent) + " m across at " + std::to_string(reach) +
         " m from the origin, where float coordinates are " + std::to_string(spacing) +
         " m apart: the runtime resolves its shape to 1 part in " + std::to_string(static_cast<long long>(extent / spacing)) +
         "; move the scene nearer the origin";
}

}  // namespace

Result<std::vector<std::string>> prepare_glass_mesh(SceneDesc& scene, std::uint32_t mesh_index, TriangleMesh& mesh,
                                                    const std::string& path) {
  std::vector<std::string> warnings;
  const auto glass = std::find_if(scene.objects.begin(), scene.objects.end(),
                                  [&](const Object& o) { return o.mesh_index == mesh_index && is_transparent(o.role); });
  const bool thin = std::any_of(scene.objects.begin(), scene.objects.end(),
                                [&](const Object& o) { return o.mesh_index == mesh_index && is_thin(o.role); });
  if (glass == scene.objects.end() && !thin) return warnings;
  const auto issue = closed_solid_issue(mesh);
  if (!issue) {
    // A closed solid drawn thin-walled: in glTF, transmission without
    // KHR_materials_volume, which the author may not have meant.
    for (const Object& o : scene.objects) {
      if (o.mesh_index != mesh_index || o.role != Role::kThin) continue;
      warnings.push_back(path + ": transparent object '" + o.name + "' is a closed solid but thin-walled, so it does not bend or "
                         "focus light; to make it solid glass give its glTF material KHR_materials_volume with a "
                         "thicknessFactor > 0 (Blender: the material's Thickness), or in scene.json drop \"thin\"");
    }
    return warnings;
  }
  if (glass == scene.objects.end()) return warnings;  // thin-walled glass needs no solid
  if (issue->inside_out) {
    const std::string how = turn_outside_out(mesh);
    warnings.push_back(path + ": transparent object '" + glass->name + "' " + issue->what + "; baked turned outside out (" + how + ")");
    return warnings;
  }
  if (issue->closed) return make_error(ErrorCode::kInput, path + ": transparent object '" + glass->name + "' " + issue->what);
  for (Object& o : scene.objects) {
    if (o.mesh_index != mesh_index || !is_transparent(o.role)) continue;
    if (o.role == Role::kBoth) {
      return make_error(ErrorCode::kInput, path + ": object '" + o.name + "' (role both) " + issue->what +
                                               "; a thin-walled surface cannot also be a receiver");
    }
    std::string dropped;  // what needs an inside
    if (o.material.absorption != Vec3f{0, 0, 0}) dropped += " absorption";
    if (o.material.dispersion > 0) dropped += " dispersion";
    if (o.material.scattering.scatters()) dropped += " scattering";
    warnings.push_back(path + ": transparent object '" + o.name + "' " + issue->what +
                       "; it bounds no solid, so it is baked thin-walled (light crosses it without bending, with Fresnel and "
                       "tint at each sheet)" +
                       (dropped.empty() ? "" : "; without an inside, ignored:" + dropped));
    o.role = Role::kThin;
    o.material.absorption = {0, 0, 0};
    o.material.dispersion = 0;
    o.material.scattering = Scattering{};
  }
  return warnings;
}

namespace {

// Shared work: a mesh whose imported content (after refinement)
// and Draco stream equal an earlier mesh's is dropped and its objects draw
// the earlier one, as exporters duplicate a mesh for every copy of an
// object (glTF meshes that are not instanced, one OBJ per object). Returns
// a note per mesh dropped.
std::vector<std::string> merge_identical_meshes(SceneDesc& scene, std::vector<std::string>& paths, std::vector<TriangleMesh>& meshes,
                                                std::vector<std::vector<std::uint8_t>>& streams, std::vector<MeshStats>& stats) {
  const auto same = [&](std::size_t a, std::size_t b) {
    const TriangleMesh &x = meshes[a], &y = meshes[b];
    return streams[a] == streams[b] && x.positions == y.positions && x.triangles == y.triangles && x.normals == y.normals && x.uvs == y.uvs && x.colors == y.colors;
  };
  std::vector<std::string> notes;
  std::vector<std::uint32_t> to(meshes.size());
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const auto twin = std::find_if(kept.begin(), kept.end(), [&](std::size_t k) { return same(k, i); });
    if (twin == kept.end()) {
      to[i] = static_cast<std::uint32_t>(kept.size());
      kept.push_back(i);
      continue;
    }
    to[i] = to[*twin];
    notes.push_back(paths[i] + ": the same mesh as " + paths[*twin] + "; stored once");
  }
  if (kept.size() == meshes.size()) return notes;
  for (Object& o : scene.objects) o.mesh_index = to[o.mesh_index];
  const auto keep = [&](auto& v) {
    std::remove_reference_t<decltype(v)> out;
    for (std::size_t k : kept) out.push_back(std::move(v[k]));
    v = std::move(out);
  };
  keep(scene.meshes);
  keep(paths);
  keep(meshes);
  keep(streams);
  keep(stats);
  return notes;
}

// The process's peak resident set (Linux reports kilobytes).
std::uint64_t peak_resident_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;
}

std::string mib(std::uint64_t bytes) { return std::to_string((bytes + (1u << 19)) >> 20) + " MiB"; }

// The option that makes a stage cheaper, for a budget's message.
std::string knob_for(const std::string& stage) {
  if (stage == "light-transport tables") return "--ltt-resolution (or --ltt-wavelengths, or --preset fast)";
  if (stage == "level maps") return "--map-size or --planes";
  if (stage == "index grids") return "--volume-res";
  if (stage == "meshes") return "--glass-edge (coarser glass refinement), or simplify the mesh";
  return "nothing here";
}

// What the bake says while it runs (BakeObserver): each warning as it is
// found, kept in the result too; progress calls serialised across the
// tracing threads. And its budgets (BakeOptions::max_seconds,
// max_memory_bytes), checked at every progress step: past one, progress()
// returns false and error() says where and what to lower.
class Voice {
 public:
  Voice(const BakeOptions& options, std::vector<std::string>& warnings)
      : observer_(options.observer), max_seconds_(options.max_seconds), max_memory_(options.max_memory_bytes),
        warnings_(warnings) {}
  void warn(std::string w) {
    if (observer_.warning) {
      const std::lock_guard<std::mutex> lock(mutex_);
      observer_.warning(w);
    }
    warnings_.push_back(std::move(w));
  }
  // False once the bake is past a budget.
  bool progress(const std::string& stage, const std::string& item, double fraction) {
    if (observer_.progress) {
      const std::lock_guard<std::mutex> lock(mutex_);
      // Threads report out of order: a stage's fraction never goes back.
      if (stage != stage_) {
        stage_ = stage;
        fraction_ = 0.0;
      }
      fraction_ = std::max(fraction_, std::clamp(fraction, 0.0, 1.0));
      observer_.progress(stage, item, fraction_);
    }
    return within_budget(stage, item);
  }
  // False (and error() set) when the bake is past a budget, or would be
  // with `more_bytes` allocated.
  bool within_budget(const std::string& stage, const std::string& item, std::uint64_t more_bytes = 0) {
    if (stopped_) return false;
    std::string over;
    const double seconds = seconds_since(start_);
    if (max_seconds_ > 0 && seconds > max_seconds_) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "it ran %.1f s, past --max-seconds %g", seconds, max_seconds_);
      over = buf;
    } else if (max_memory_ > 0) {
      const std::uint64_t peak = peak_resident_bytes();
      if (peak + more_bytes > max_memory_) {
        over = more_bytes > 0 ? "it would hold " + mib(peak + more_bytes) + " (" + mib(more_bytes) + " more), past --max-memory " + mib(max_memory_)
                              : "its memory reached " + mib(peak) + ", past --max-memory " + mib(max_memory_);
      }
    }
    if (over.empty()) return true;
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!stopped_) {
      reason_ = "stopped in the " + stage + " stage" + (item.empty() ? "" : " at '" + item + "'") + ": " + over + "; lower " +
                knob_for(stage) + ", or raise the budget";
      stopped_ = true;
    }
    return false;
  }
  Error error() const { return make_error(ErrorCode::kBudget, reason_); }

 private:
  const BakeObserver& observer_;
  const double max_seconds_;
  const std::uint64_t max_memory_;
  const Clock::time_point start_ = Clock::now();
  std::vector<std::string>& warnings_;
  std::mutex mutex_;
  std::atomic<bool> stopped_{false};
  std::string reason_;
  std::string stage_;  // the last progress call's, and its fraction
  double fraction_ = 0.0;
};

}  // namespace

Result<BakeResult> bake_scene(const std::string& scene_path, const BakeOptions& options) {
  BakeResult out;
  Voice voice(options, out.warnings);
  if (!voice.progress("scene", scene_path, 0.0)) return voice.error();
  auto doc = load_scene(scene_path, options.default_light);
  if (!doc) return doc.error();
  out.inputs = doc->inputs;
  for (const std::string& w : doc->warnings) voice.warn(w);
  SceneDesc& scene = doc->scene;
  scene.render = options.render;
  if (scene.water && options.water_grid_scale != 1.0) {
    const auto before = scene.water->cells;
    for (std::uint32_t& c : scene.water->cells) {
      c = static_cast<std::uint32_t>(std::clamp(std::lround(c * options.water_grid_scale), 1L, long{kMaxWaterCells}));
    }
    // Said: a coarser grid shows its triangles' seams in the caustics.
    char note[200];
    std::snprintf(note, sizeof note, "the water grid is %u x %u cells, scene.json's %u x %u times %g (--water-grid-scale%s%s)",
                  scene.water->cells[0], scene.water->cells[1], before[0], before[1], options.water_grid_scale,
                  options.render ? "; preset " : "", options.render ? options.render->preset.c_str() : "");
    out.notes.push_back(note);
  }

  // Receivers' textures' images, each read once (formats/scene.h TextureImage).
  std::vector<std::optional<std::uint32_t>> image_index(doc->images.size());
  std::vector<bool> used(doc->images.size(), false);
  for (const Object& o : scene.objects) for_each_texture(o.material, [&](const MapTexture& t) { used[t.image] = true; });
  for (std::size_t i = 0; i < doc->images.size(); ++i) {
    const ImageSource& src = doc->images[i];
    if (!used[i]) continue;
    if (!src.path.empty()) out.inputs.push_back(src.path);
    auto image = read_texture(src, options.max_texture_size);
    if (!image && !src.fall_back) return image.error();
    if (!image) {
      voice.warn(image.error().message + "; its receivers are drawn with their base colour factor");
      continue;
    }
    image_index[i] = static_cast<std::uint32_t>(scene.images.size());
    scene.images.push_back(std::move(*image));
  }
  for (Object& o : scene.objects) {
    for_each_texture_slot(o.material, [&](std::optional<MapTexture>& t) {
      if (t && image_index[t->image]) t->image = *image_index[t->image];
      else t.reset();
    });
  }

  if (!voice.progress("scene", scene_path, 1.0)) return voice.error();  // read, with its textures

  std::vector<std::vector<std::uint8_t>> draco_streams;
  std::vector<TriangleMesh> meshes;
  for (std::size_t i = 0; i < doc->mesh_paths.size(); ++i) {
    const std::string& path = doc->mesh_paths[i];
    if (!voice.progress("meshes", path, double(i) / double(doc->mesh_paths.size()))) return voice.error();
    auto t0 = Clock::now();
    Result<ImportedMesh> imported = doc->imported[i] ? std::move(*doc->imported[i]) : import_mesh(path);
    if (!imported) return imported.error();
    if (!doc->imported[i]) out.inputs.push_back(path);
    for (const auto& w : imported->warnings) voice.warn(path + ": " + w);
    TriangleMesh& mesh = imported->mesh;
    if (mesh.positions.size() > kMaxMeshVertices) {
      return make_error(ErrorCode::kInput, path + ": " + std::to_string(mesh.positions.size()) +
                                               " vertices exceeds the limit of " + std::to_string(kMaxMeshVertices));
    }
    // Light transport runs inside transparent objects (Iwasaki et al. §3): their
    // meshes must bound a solid, and are refined to what the table needs.
    // One that bounds none (a pane, a shade: an open surface) is baked
    // thin-walled, as glTF would draw it, and said so.
    std::optional<GlassRefineReport> refined;
    auto thin = prepare_glass_mesh(scene, static_cast<std::uint32_t>(i), mesh, path);
    if (!thin) return thin.error();
    for (std::string& w : *thin) voice.warn(std::move(w));
    const auto glass = std::find_if(scene.objects.begin(), scene.objects.end(),
                                    [&](const Object& o) { return o.mesh_index == i && is_transparent(o.role); });
    if (glass != scene.objects.end()) {
      GlassRefineOptions ro = options.glass_refine;
      const std::uint64_t r = options.transport.resolution;
      ro.max_vertices = static_cast<std::uint32_t>(std::min<std::uint64_t>(kMaxTransportEntries / (r * r), kMaxMeshVertices));
      refined.emplace();
      mesh = refine_transparent_mesh(mesh, ro, &*refined);
      if (refined->changed()) out.notes.push_back(path + ": " + describe_refinement(*refined, ro));
    }
    out.seconds_import += seconds_since(t0);

    // Texture coordinates travel only for receivers textured through them;
    // everything else pays nothing for them.
    const bool wants_uvs = std::any_of(scene.objects.begin(), scene.objects.end(), [&](const Object& o) {
      bool uv = false;
      for_each_texture(o.material, [&](const MapTexture& t) { uv = uv || t.projection == TextureProjection::kUv; });
      return o.mesh_index == i && uv;
    });
    if (!wants_uvs) mesh.uvs.clear();
    // Vertex colours likewise, for receivers only (they tint the base colour).
    const bool wants_colors = std::any_of(scene.objects.begin(), scene.objects.end(), [&](const Object& o) {
      return o.mesh_index == i && o.role == Role::kReceiver;
    });
    if (!wants_colors) mesh.colors.clear();
    if (wants_uvs && mesh.uvs.size() != mesh.positions.size()) {
      return make_error(ErrorCode::kInput, path + ": the mesh has no texture coordinates for its textures; give the textures "
                                                 "\"projection\": \"box\" (tiles in metres) or export the mesh with UVs (glTF TEXCOORD_0)");
    }
    t0 = Clock::now();
    auto stream = encode_draco(mesh, options.draco);
    if (!stream) return Error{stream.error().code, path + ": " + stream.error().message};
    out.seconds_compress += seconds_since(t0);

    MeshInfo& info = scene.meshes[i];
    std::string source = std::move(info.source);
    info = describe_mesh(mesh, options.draco);
    info.source = std::move(source);

    MeshStats st;
    st.path = path;
    st.vertices = info.vertex_count;
    st.triangles = info.triangle_count;
    st.raw_bytes = mesh.positions.size() * 24 + mesh.triangles.size() * 12;
    st.draco_bytes = stream->size();
    st.max_position_error = position_error_bound(info.bounds_min, info.bounds_max, options.draco.position_bits);
    st.normals_from_file = imported->normals_from_file;
    st.glass_refine = refined;
    out.meshes.push_back(st);
    draco_streams.push_back(std::move(*stream));
    meshes.push_back(std::move(imported->mesh));
  }

  if (options.share) {
    for (std::string& note : merge_identical_meshes(scene, doc->mesh_paths, meshes, draco_streams, out.meshes)) out.notes.push_back(std::move(note));
  }
  if (auto issue = validate_scene(scene)) {
    return make_error(ErrorCode::kInput, scene_path + ": " + issue->pointer + ": " + issue->message);
  }
  for (const Object& o : scene.objects) {
    if (auto w = float_precision_warning(o, meshes[o.mesh_index])) voice.warn(*w);
    double scale = 0;
    for (std::size_t c = 0; c < 3; ++c) {
      scale = std::max(scale, std::hypot(double{o.transform[c * 4]}, double{o.transform[c * 4 + 1]}, double{o.transform[c * 4 + 2]}));
    }
    MeshStats& st = out.meshes[o.mesh_index];
    st.max_world_error = std::max(st.max_world_error, st.max_position_error * scale);
  }
  // Said, so that the runtime's change of method for such glass is not silent.
  const auto inside = receiver_inside_glass(scene);
  for (std::size_t g = 0; g < inside.size(); ++g) {
    if (!inside[g]) continue;
    voice.warn("receiver '" + scene.objects[*inside[g]].name + "' lies inside transparent object '" + scene.objects[g].name +
               "' (its bounding box): the light-transport tables never reach it, so the runtime lights that glass "
               "by caustic maps whatever the glass method");
  }
  if (!voice.progress("meshes", "", 1.0)) return voice.error();
  auto t0 = Clock::now();
  if (!voice.progress("level maps", "", 0.0)) return voice.error();
  auto stage = bake_level_maps(scene, meshes, options.level_maps, [&](double f) { voice.progress("level maps", "", f); });
  if (!stage) return stage.error();
  out.level_maps = std::move(*stage);
  for (const PairReport& p : out.level_maps.pairs) {
    if (!p.warning.empty()) {
      voice.warn("object '" + scene.objects[p.object].name + "', light " + std::to_string(p.light) + ": " + p.warning);
    }
  }
  out.seconds_level_maps = seconds_since(t0);
  if (!voice.progress("level maps", "", 1.0)) return voice.error();

  // Light-transport tables (Iwasaki et al. §3), one per transparent object, over
  // the decoded mesh: the runtime indexes the table by the vertices it
  // draws, which Draco's edgebreaker has reordered.
  t0 = Clock::now();
  if (const std::uint32_t k = options.transport.wavelengths; k == 1 || k > kMaxTransportWavelengths) {
    return make_error(ErrorCode::kUsage, "transport wavelengths must be 0 or 2.." + std::to_string(kMaxTransportWavelengths) +
                                             ", got " + std::to_string(k));
  }
  std::vector<LightTransportTable> tables, spectral;
  std::vector<TransportReport> spectral_reports;
  std::map<std::uint32_t, TriangleMesh> glass_meshes;  // decoded, by mesh index (the index grids use them too)
  // Objects that can use an earlier object's tables do (Object::tables_from).
  for (std::uint32_t oi = 0; oi < scene.objects.size() && options.share; ++oi) {
    for (std::uint32_t j = 0; j < oi && !scene.objects[oi].tables_from; ++j) {
      if (can_share_tables(scene.objects[j], scene.objects[oi])) scene.objects[oi].tables_from = j;
    }
  }
  std::size_t table_count = 0, tables_done = 0;  // for the progress
  for (const Object& o : scene.objects) {
    if (is_transparent(o.role) && !o.tables_from) {
      table_count += 1 + (o.material.dispersion > 0 ? transport_wavelengths(options.transport.wavelengths).size() : 0);
    }
  }
  // One table, or nothing when a budget stopped it (voice.error()).
  const auto trace = [&](std::uint32_t oi, const TriangleMesh& mesh, TransportReport* rep, float nm) -> std::optional<LightTransportTable> {
    const Object& o = scene.objects[oi];
    const std::string item = nm > 0 ? o.name + " at " + std::to_string(static_cast<int>(std::lround(nm))) + " nm" : o.name;
    const auto said = [&](double f) { return voice.progress("light-transport tables", item, (double(tables_done) + f) / double(table_count)); };
    const std::uint64_t bytes = std::uint64_t{16} * mesh.positions.size() * options.transport.resolution * options.transport.resolution;
    if (!said(0.0) || !voice.within_budget("light-transport tables", item, bytes)) return std::nullopt;
    LightTransportTable t = trace_transport_table(oi, o.material, mesh, options.transport, rep, nm, said);
    ++tables_done;
    if (!voice.within_budget("light-transport tables", item)) return std::nullopt;
    return t;
  };
  for (std::uint32_t oi = 0; oi < scene.objects.size(); ++oi) {
    const Object& o = scene.objects[oi];
    if (!is_transparent(o.role)) continue;
    const std::string& path = doc->mesh_paths[o.mesh_index];
    if (!glass_meshes.count(o.mesh_index)) {
      auto decoded = decode_draco(draco_streams[o.mesh_index], scene.meshes[o.mesh_index]);
      if (!decoded) return Error{ErrorCode::kInternal, path + ": " + decoded.error().message};
      glass_meshes.emplace(o.mesh_index, std::move(*decoded));
    }
    if (o.tables_from) {
      scene.objects[oi].material.spectral_tables = scene.objects[*o.tables_from].material.spectral_tables;
      continue;
    }
    const TriangleMesh& mesh = glass_meshes.at(o.mesh_index);
    const std::uint64_t r = options.transport.resolution, entries = mesh.positions.size() * r * r;
    if (entries > kMaxTransportEntries) {
      return make_error(ErrorCode::kInput, path + ": transparent object '" + o.name + "': its light-transport table would hold " +
                                               std::to_string(mesh.positions.size()) + " vertices x " + std::to_string(r) +
                                               "^2 directions = " + std::to_string(entries) + " entries, above the limit of " +
                                               std::to_string(kMaxTransportEntries) + " (1 GiB); lower --ltt-resolution, raise --glass-edge or simplify the mesh");
    }
    TransportReport rep;
    auto table = trace(oi, mesh, &rep, 0.0f);
    if (!table) return voice.error();
    tables.push_back(std::move(*table));
    out.transport.push_back(rep);
    // Dispersive glass: the same table at more wavelengths.
    if (o.material.dispersion > 0 && options.transport.wavelengths == 0) {
      voice.warn("transparent object '" + o.name + "' disperses, but --ltt-wavelengths 0 bakes its light-transport "
                 "table at n_d only: its caustics from the tables have no colour fringes");
    }
    if (o.material.dispersion > 0) {
      for (const float nm : transport_wavelengths(options.transport.wavelengths)) {
        auto at_nm = trace(oi, mesh, &rep, nm);
        if (!at_nm) return voice.error();
        spectral.push_back(std::move(*at_nm));
        spectral_reports.push_back(rep);
        ++scene.objects[oi].material.spectral_tables;
      }
    }
  }
  // LTTS after every LTTB, by object and wavelength (as decode_scene wants).
  for (LightTransportTable& t : spectral) tables.push_back(std::move(t));
  out.transport.insert(out.transport.end(), spectral_reports.begin(), spectral_reports.end());
  out.seconds_transport = seconds_since(t0);
  if (table_count > 0 && !voice.progress("light-transport tables", "", 1.0)) return voice.error();

  // Index grids for media (Pfeuti), one per transparent object, only when
  // something scatters: a scene without media pays nothing for them.
  t0 = Clock::now();
  std::vector<IndexGrid> grids;
  const bool scatters = scene_scatters(scene);
  const auto glass_count = static_cast<double>(std::count_if(scene.objects.begin(), scene.objects.end(), [](const Object& o) { return is_transparent(o.role); }));
  for (std::uint32_t oi = 0, g = 0; oi < scene.objects.size() && scatters; ++oi) {
    const Object& o = scene.objects[oi];
    if (!is_transparent(o.role)) continue;
    const double done = double(g++);
    if (!voice.progress("index grids", o.name, done / glass_count)) return voice.error();
    const TriangleMesh& mesh = glass_meshes.at(o.mesh_index);
    const std::uint64_t voxels = index_grid_voxels(mesh, options.index_grid);
    if (voxels > kMaxIndexGridVoxels) {
      return make_error(ErrorCode::kInput, doc->mesh_paths[o.mesh_index] + ": transparent object '" + o.name +
                                               "': its index grid would hold " + std::to_string(voxels) +
                                               " voxels at --volume-res " + std::to_string(options.index_grid.resolution) +
                                               ", above the limit of " + std::to_string(kMaxIndexGridVoxels) +
                                               " (384 MiB); lower --volume-res");
    }
    // The index around the object: the water's when the object lies below
    // the water at rest, else air's.
    double top = -1e300;
    for (const Vec3d& w : world_points(o.transform, mesh.positions)) top = std::max(top, w[1]);
    const float outside = scene.water && top < scene.water->level ? scene.water->ior : 1.0f;
    grids.push_back(voxelize_index(oi, mesh, o.material.ior, outside, options.index_grid,
                                   [&](double f) { return voice.progress("index grids", o.name, (done + f) / glass_count); }));
    if (!voice.within_budget("index grids", o.name)) return voice.error();
    IndexGridReport rep;
    rep.object = oi;
    rep.size = grids.back().size;
    rep.voxel = grids.back().voxel;
    double wide = 0, width = 0;
    for (std::uint8_t lv : grids.back().level) {
      wide += lv > 0 ? 1 : 0;
      width += double(1u << lv);
    }
    rep.uniform_fraction = wide / double(grids.back().voxels());
    rep.mean_step = width / double(grids.back().voxels());
    out.index_grids.push_back(rep);
  }
  out.seconds_index_grids = seconds_since(t0);
  if (scatters && !glass_meshes.empty() && !voice.progress("index grids", "", 1.0)) return voice.error();

  t0 = Clock::now();
  if (!voice.progress("write", "", 0.0)) return voice.error();
  out.cxb = encode_scene(scene, draco_streams, out.level_maps.maps, out.level_maps.boxes, tables, grids);
  if (!tables.empty() || !grids.empty()) {  // chunk sizes for the report (reading back is cheaper than encoding twice)
    auto c = cxb::read_container(out.cxb.data(), out.cxb.size());
    if (!c) return Error{ErrorCode::kInternal, "re-reading the baked file: " + c.error().message};
    auto ltt = c->find(cxb::kTagTransport);
    const auto ltts = c->find(cxb::kTagSpectralTransport);
    ltt.insert(ltt.end(), ltts.begin(), ltts.end());  // the reports' order
    for (std::size_t k = 0; k < ltt.size() && k < out.transport.size(); ++k) out.transport[k].stored_bytes = c->payload(ltt[k]).size();
    const auto igrd = c->find(cxb::kTagIndexGrid);
    for (std::size_t k = 0; k < igrd.size() && k < out.index_grids.size(); ++k) out.index_grids[k].stored_bytes = c->payload(igrd[k]).size();
  }
  out.seconds_write = seconds_since(t0);
  if (!voice.progress("write", "", 1.0)) return voice.error();
  out.peak_memory_bytes = peak_resident_bytes();
  out.scene = std::move(scene);
  return out;
}

}  // namespace caustix::bake
