#pragma once
// The bake pipeline: scene.json -> import and validate meshes -> Draco ->
// .cxb bytes. Pure function of its inputs (no clocks, no paths of the
// machine in the output): the same inputs give byte-identical bytes.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "caustix/bake/glass_refine.h"
#include "caustix/bake/index_grid.h"
#include "caustix/bake/level_maps.h"
#include "caustix/bake/light_transport.h"
#include "caustix/bake/mesh_compress.h"
#include "caustix/common/status.h"

namespace caustix::bake {

// What a bake says while it runs; either may be empty.
struct BakeObserver {
  // Each warning as soon as it is found (BakeResult::warnings keeps them
  // too), so that a bake that fails or is stopped later has said them.
  std::function<void(const std::string& warning)> warning;
  // A stage ("scene": reading it and its textures, "meshes": importing,
  // refining and compressing them, "level maps", "light-transport tables",
  // "index grids", "write") on an item (a mesh's path, an object's name, or
  // empty) at `fraction` of the stage done, in [0, 1], never decreasing
  // within a stage; 1 when the stage ends. Called one at a time (the bake
  // serialises the calls its worker threads make), from any of its threads.
  std::function<void(const std::string& stage, const std::string& item, double fraction)> progress;
};

struct BakeOptions {
  DracoOptions draco;
  LevelMapOptions level_maps;
  TransportOptions transport;
  // Index grids of transparent objects, baked only for scenes that scatter.
  IndexGridOptions index_grid;
  // Meshes of transparent objects are refined for the transport table
  // (bake/glass_refine.h) before compression.
  GlassRefineOptions glass_refine;
  // Multiplies scene.json's water grid cells on each axis (rounded, kept in
  // 1..kMaxWaterCells): the runtime's caustics cost is linear in the grid's
  // triangles (docs/tradeoff.md).
  double water_grid_scale = 1.0;
  // Albedo textures larger than this many texels a side are filtered down
  // to fit (bake/texture_import.h).
  std::uint32_t max_texture_size = 2048;
  // Runtime defaults to record in the .cxb (RNDR chunk; presets set them).
  std::optional<RenderDefaults> render;
  // Shared work: meshes with the same content after import are
  // stored once, and solid transparent objects on one mesh with the same
  // IOR, dispersion and absorption use one set of light-transport tables
  // (Object::tables_from, the LTTR chunk), whatever their transforms.
  // False: every object gets its own, as before (files a reader that
  // predates LTTR reads).
  bool share = true;
  // A glTF file without lights gets the default rig (load_scene): a sun
  // and the daylight sky, said in a warning. False: it stays dark.
  bool default_light = true;
  // Not part of the bake's inputs: what it says while it runs, and budgets
  // (0: none). Past either the bake stops with an ErrorCode::kBudget
  // error naming the stage, the object and the option to lower. Checked at
  // every progress step (a light-transport table's every 1 %); memory is the
  // process's peak resident set, and also checked before a light-transport
  // table is allocated, against its size.
  BakeObserver observer;
  double max_seconds = 0;
  std::uint64_t max_memory_bytes = 0;
};

struct MeshStats {
  std::string path;
  std::uint32_t vertices = 0;
  std::uint32_t triangles = 0;
  std::uint64_t raw_bytes = 0;    // float32 positions + normals + uint32 indices
  std::uint64_t draco_bytes = 0;
  double max_position_error = 0;  // bound in the mesh's own units (object space)
  // The same bound in metres in the world: the largest over the objects
  // drawing the mesh, through their transforms' largest scale (a quantized
  // glTF mesh's integer units under a 1e-5 node scale).
  double max_world_error = 0;
  bool normals_from_file = false;
  std::optional<GlassRefineReport> glass_refine;  // meshes of transparent objects
};

struct IndexGridReport {
  std::uint32_t object = 0;
  std::array<std::uint32_t, 3> size{};
  double voxel = 0;             // metres, object space
  std::uint64_t stored_bytes = 0;
  double uniform_fraction = 0;  // voxels in octree nodes wider than one voxel
  double mean_step = 0;         // mean node width over the voxels, in voxels
};

struct BakeResult {
  std::vector<std::uint8_t> cxb;
  SceneDesc scene;                  // as baked (for reports)
  std::vector<MeshStats> meshes;
  std::vector<std::string> warnings;
  std::vector<std::string> notes;   // what the bake did to the input, said unless --quiet
  std::vector<std::string> inputs;  // every file read (for --depfile)
  LevelMapStage level_maps;         // maps moved into the .cxb; reports kept
  std::vector<TransportReport> transport;  // one per table traced (an object sharing another's has none)
  std::vector<IndexGridReport> index_grids;  // scenes that scatter: one per transparent object
  double seconds_import = 0, seconds_compress = 0, seconds_level_maps = 0, seconds_transport = 0, seconds_index_grids = 0,
         seconds_write = 0;
  std::uint64_t peak_memory_bytes = 0;  // the process's peak resident set at the end (for reports)
};

Result<BakeResult> bake_scene(const std::string& scene_path, const BakeOptions& options);

// Transparent objects drawing `mesh` (scene.meshes[mesh_index], read from
// `path`):
// - when it is open -- it has boundary edges: a pane, a shade, so it bounds
//   no solid -- they become thin-walled (Role::kThin), as glTF would draw
//   them, losing what needs an inside (absorption, dispersion, scattering);
//   a warning per object so changed;
// - when it is a closed, consistently wound solid turned inside out, its
//   triangles (and normals that point in) are reversed; a warning;
// - when it is a closed solid drawn thin-walled (glTF transmission without
//   KHR_materials_volume), a warning per object saying how to make it solid.
// A closed mesh that is not a solid (wound inconsistently, non-manifold,
// enclosing no volume: a modelling error in a solid), or an open one on a
// "both" object, is an error naming the object. caustix-bake and
// caustix-reference apply it alike.
Result<std::vector<std::string>> prepare_glass_mesh(SceneDesc& scene, std::uint32_t mesh_index, TriangleMesh& mesh,
                                                    const std::string& path);

// The bake report: JSON (--report) and a readable summary with a bar chart of
// each depth profile (-v).
std::string report_json(const BakeResult& result, const BakeOptions& options);

// What a bake that failed had done, for its --report: the
// stages it finished with their seconds, the stage and item it was in, and
// the warnings it had said.
struct BakeLog {
  std::vector<std::pair<std::string, double>> stages_done;
  std::string stage, item;
  std::vector<std::string> warnings;
};
std::string failure_report_json(const std::string& scene_path, const Error& error, int exit_code, const BakeLog& log);
std::string report_text(const BakeResult& result);

}  // namespace caustix::bake
