#include "caustics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>
#include <tuple>

#include "caustix/formats/frame.h"
#include "caustix/formats/slicing.h"
#include "gl_state.h"
#include "pass_timer.h"
#include "readback.h"
#include "shader_text.h"

namespace caustix::runtime {
namespace {

constexpr std::uint32_t kTileTexels = 8;  // position-map texels per depth tile side
// Most primitives one map may list: 4 M ((volume, plane) pairs; 288 MB with
// their geometry).
constexpr std::uint64_t kMaxPrimitives = 4u << 20;
constexpr GLsizeiptr kPrimitiveBytes = 64;  // four vec4, caustics_geometry.comp
constexpr GLsizeiptr kListBytes = 8;        // a (volume, plane) pair
// The planes buffer: a 16-byte header (count, depth range, widest window;
// caustics_plan.comp) and (offset, eps) per plane.
constexpr GLsizeiptr kPlanesHeader = 16;
constexpr GLsizeiptr kPlanesBytes = kPlanesHeader + 8 * GLsizeiptr{kMaxPlanes};
// What each map's counters contribute to a frame's read-back slot:
// command words 8..10 (listed, overflow, drawn) and the plane count.
constexpr std::size_t kCounterBytes = 16;
// A map's command buffer (caustics_fixup.comp): the draw, the geometry
// dispatch, the counters.
constexpr GLsizeiptr kCommandBytes = 44;
// A batch's command buffer (Impl::Batch; caustics_batch.glsl's layout):
// from kBatchCounts each map's count of entries, overflow and entries
// drawn, a cache line apart (a run's first map's also holds the run's
// cull dispatch, kBatchCullDispatch on), then each map's draw, 16 bytes.
constexpr GLintptr kBatchCounts = 64;
constexpr GLsizeiptr kBatchCountBytes = 64;
constexpr GLintptr kBatchCullDispatch = 16;
constexpr GLsizeiptr kBatchDrawBytes = 16;
constexpr GLsizeiptr kBatchBytesPerMap = kBatchCountBytes + kBatchDrawBytes;
// The cull's water rectangles (caustics_rects.comp): the water's bounds,
// then per map its dispatch and its rectangle.
constexpr GLsizeiptr kRectsHeader = 32;
constexpr GLsizeiptr kRectBytes = 32;
// MapBatching::kAuto: fewer maps of a batch drawn in an update than this
// are drawn one by one (batching them saves a few calls).
constexpr std::size_t kBatchMinMaps = 8;
// A list sized from a measured count keeps this much headroom for the
// counts of the frames until the next measurement arrives.
constexpr double kHeadroom = 1.25;
constexpr std::uint64_t kMinCapacity = 1024;
// The budget coarsens the texels in steps of 2^(1/4), at most 2^13 times
// (every map is at its smallest long before).
constexpr int kMaxCoarsenSteps = 52;

// With the texel from map_size, a map has at least this share of map_size
// a side unless the budget needs its texels: a small receiver's outline,
// terminator and folds stay as sharp in a view that comes close as with
// map_size. Against the traced reference (docs/caustics.md, "Texels by
// need and the memory budget"): a 1 m sphere under sphere_waves' sine wave
// at 9.4 mm pixels, fold pixels 5.6 % at 512^2, 5.7 % at 256^2, 8.2 % at
// 128^2 (its need at the floor's texel); default's block at 256^2, 5.7 ->
// 7.5 %. So every map keeps map_size until the budget asks, but no map
// keeps more than kLeastOverNeed times its need a side: the sphere's and
// the block's 512^2 are 4x theirs, while a pebble beside the floor
// (need 24) takes 96^2 rather than 512^2, whatever room the budget leaves.
constexpr double kLeastShare = 1.0;
constexpr double kLeastOverNeed = 4.0;

// The sides a caustics map may take: 16 * 2^(k/2) rounded up to a
// multiple of 8 (16, 24, 32, 48, 64, 96, 128, 184, 256, 368, 512, ...), so
// that a receiver or a light moving a little keeps its map's size (a new
// size is a new texture, and a step in the picture).
std::uint32_t ladder_side(double need) {
  static const std::vector<std::uint32_t> ladder = [] {
    std::vector<std::uint32_t> l;
    for (int k = 0; l.empty() || l.back() < kMaxRuntimeMapSize; ++k) {
      const double v = std::ceil(16.0 * std::pow(2.0, k / 2.0) / 8.0) * 8.0;
      l.push_back(std::min(static_cast<std::uint32_t>(v), kMaxRuntimeMapSize));
    }
    return l;
  }();
  for (const std::uint32_t side : ladder) {
    if (side >= need) return side;
  }
  return ladder.back();
}

// What a map's reference planes were made from: rebuilt when any changes.
struct PlanKey {
  bool smart = true;
  std::uint32_t pieces = 0;   // uniform slicing: n pieces
  double epsilon = 0;         // smart slicing: eps asked
  double height = 0;          // h, the frame's extent along V
  std::uint64_t profile = 0;  // the depth profile's version (0: as baked)
  bool operator==(const PlanKey&) const = default;
};

// What a list sized for one plan serves: a change here means the count
// must be measured again before it is trusted (a warm-up read-back).
struct ListKey {
  bool pairs = true, cull = true;
  bool smart = true;
  std::uint32_t pieces = 0;
  double epsilon = 0;
  std::uint32_t map_size = 0;  // coarser texels widen the footprints the cull lists
  bool operator==(const ListKey&) const = default;
};

struct MapGpu {
  LevelMap* lm = nullptr;
  // R32F at lm->map_size: a view of its layer of the light's array of
  // position maps of that size (Impl::PositionArrays).
  gl::Texture position_map;
  std::uint32_t position_layer = 0;
  // RGBA32F at caustics_size: irradiance on the plane and its direction
  // (caustics_geometry.comp); a view of layer `layer` of its batch's array
  // (Impl::arrange).
  gl::Texture caustics;
  gl::Framebuffer fbo;
  std::uint32_t caustics_size = 0;
  std::uint32_t layer = 0;
  bool batched = false;  // its batch holds a window depth for it (texture_bytes)
  // Texels by need (Impl::plan_texels): the side its caustics map takes at
  // its next draw; 0 where the water's light cannot reach it now (then it
  // holds no map and binds the black texture).
  std::uint32_t planned_side = 0;
  // Its last draw's windows pass wrote the presence (caustics_windows.frag).
  bool windows_presence = false;
  // Drawn alone (not in a batch): the windows pass's depth, which plane's
  // window each texel's surface lies in, and surface, the texel's depth
  // (the mean frame V of its samples, R16, as a position code) that the
  // draw follows the beams to (caustics_windows.frag), at
  // caustics_size. `windows_made`: the planes and side they were made for,
  // in these textures or in its batch's layer, whichever the map was
  // last drawn with. The pass runs again only when those change (the
  // planes' key holds the position map's version) or the textures were
  // remade; until then the depth, the surface and the presence in the
  // map's alpha stay.
  gl::Texture window_depth, window_surface;
  std::uint32_t window_size = 0;
  std::optional<std::pair<PlanKey, std::uint32_t>> windows_made;
  bool planned = false;
  bool unlit = false;  // its light no longer reaches it through the water (rederive_map)
  // The depth profile: the baked histogram, re-made on the GPU after a
  // light or the receiver moves (then its planes are planned there too).
  gl::Buffer histogram;
  std::uint64_t profile = 0;  // 0: lm's (CPU) histogram is current; else re-derived on the GPU
  bool default_epsilon = true;  // lm->epsilon is h / (2 n): it follows h when the frame changes
  // Planes in use: the header and planes (caustics_plan.comp's layout) at
  // this offset of Impl::all_planes, planned from `plan`; on the CPU too where
  // it knows the histogram.
  GLintptr planes_offset = 0;
  std::optional<PlanKey> plan;
  std::optional<std::vector<ReferencePlane>> cpu_planes;
  float self_tolerance = 0;
  gl::Texture depth_tiles;  // RG32F min/max frame V per tile: a view, as position_map's
  gl::Framebuffer position_fbo;  // run-time re-derivation (its depth: Impl::position_depth)
  gl::Buffer command;
  // Entries its list needs (Impl::list, shared). Measured with a read-back
  // the first time a map is drawn with a plan (warm-up), then sized from
  // counts read asynchronously (gl::ReadbackRing): a frame that overflows
  // draws the entries that fit and says so (CausticsStats).
  std::uint64_t capacity = 0;
  std::optional<ListKey> measured;
  std::uint64_t quiet_polls = 0;  // read-backs in a row that found the list over-sized
  bool rederive = false;          // its light or receiver moved: re-derive before the next draw
  // Volumetric baseline: receiver slices and illumination per plane.
  gl::Texture slices, illumination;
  std::uint32_t slice_count = 0, slice_size = 0;
  // Dispersion (a water that disperses, several wavelengths traced): the
  // sum over wavelengths and the RGB colour texture (caustics_accumulate).
  gl::Texture spectral_sum, color;
  std::uint32_t spectral_size = 0;
  bool spectral = false;  // the last update traced several wavelengths: `color` is valid
  std::uint64_t gpu_bytes = 0;
  // Out of the camera's view (CausticsEngine::begin_frame): kept through
  // updates of its light that would have remade it.
  bool stale = false;
};

// A map of a batch as its shaders read it (caustics_batch.glsl's
// CausticsMap, std430).
struct BatchMap {
  glm::vec4 origin, u, v, w, half_size, texel;
  glm::uvec4 ints, list;
};
static_assert(sizeof(BatchMap) == 8 * 16, "BatchMap must match caustics_batch.glsl's CausticsMap");

// Position-map texels per caustics texel, and the samples per axis the
// caustics shaders take of them in a caustics texel (up to 4 x 4 where it
// is coarser than the position map's).
std::pair<float, int> texel_sampling(const MapGpu& m) {
  const float scale = static_cast<float>(m.lm->map_size) / static_cast<float>(m.caustics_size);
  return {scale, static_cast<int>(std::clamp(std::ceil(scale), 1.0f, 4.0f))};
}

// GPU bytes per texel of a map's own textures: the caustics map and its
// mips; where the water disperses, the sum over wavelengths and the RGB
// texture with mips; for the volumetric baseline, a slice and an
// illumination texel per plane.
double bytes_per_texel(const MapGpu& m, const CausticsOptions& o, bool spectral) {
  double b = 16.0 * 4.0 / 3.0;
  // The level-map methods' window depth and surface: its batch's layer, or
  // its own drawn alone.
  if (o.method == CausticsMethod::kLevelMap || o.method == CausticsMethod::kUniform) b += 4.0;
  if (spectral) b += 16.0 + 16.0 * 4.0 / 3.0;
  if (o.method == CausticsMethod::kVolumetric) {
    const std::size_t planes = m.cpu_planes ? m.cpu_planes->size() : m.lm->planes_requested;
    b += 17.0 * static_cast<double>(planes);
  }
  return b;
}

// The plan of map `m` for the options: which slicing, and its n or eps.
PlanKey plan_key(const MapGpu& m, const CausticsOptions& o) {
  const LevelMap& lm = *m.lm;
  PlanKey k;
  k.smart = o.method == CausticsMethod::kLevelMap;
  k.height = 2.0 * lm.frame.half[1];
  k.profile = m.profile;
  const double h = k.height;
  if (!k.smart) {
    k.pieces = o.planes ? *o.planes
             : o.epsilon ? static_cast<std::uint32_t>(std::clamp(std::ceil(h / (2.0 * *o.epsilon)), 1.0, 4096.0))
                         : lm.planes_requested;
  } else {
    k.epsilon = o.epsilon ? double{*o.epsilon}
              : o.planes ? h / (2.0 * *o.planes)
              : m.default_epsilon ? h / (2.0 * lm.planes_requested)
                                  : double{lm.epsilon};
  }
  return k;
}

glm::vec3 v3(const Vec3f& v) { return {v[0], v[1], v[2]}; }

void set_frame(const gl::Program& p, const BoundingFrame& f) {
  p.set("u_origin", glm::vec3(static_cast<float>(f.origin[0]), static_cast<float>(f.origin[1]), static_cast<float>(f.origin[2])));
  p.set("u_U", v3(f.u));
  p.set("u_V", v3(f.v));
  p.set("u_W", v3(f.w));
  p.set("u_half", v3(f.half));
}

}  // namespace

struct CausticsEngine::Impl {
  const WaterSurface* water = nullptr;
  std::vector<MapGpu> maps;
  gl::Texture black;  // 1 x 1 RGBA32F zero: the caustics of a receiver without a map
  // The plan of texels (plan_texels): the other effects' light-side
  // memory told at begin_frame, the budget's coarsening step (kept while
  // it holds), what the stats say and the warnings not yet handed out.
  std::uint64_t other_bytes = 0;
  int coarsen_step = 0;
  CausticsTexels texels;
  std::vector<std::string> warnings;
  int warned_step = 0;
  bool warned_over = false;
  gl::Program prepare, cull, fixup, geometry, levelmap, windows, volumetric, slab, combine, presence, profile, accumulate, plan, rects;
  // The same passes for a batch of maps (caustics_batch.glsl), where the
  // driver can choose a layer from the vertex shader.
  gl::Program cull_batch, fixup_batch, geometry_batch, levelmap_batch, windows_batch;
  bool layered = false;   // GL_ARB_shader_viewport_layer_array
  bool software = false;  // a software rasteriser (MapBatching::kAuto)
  // Every map's planes, map after map at planes_stride bytes (kPlanesBytes
  // rounded up to the shader-storage offset alignment).
  gl::Buffer all_planes;
  GLintptr planes_stride = 0;
  void bind_planes(const MapGpu& m) const {
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 7, all_planes.get(), m.planes_offset, kPlanesBytes);
  }
  // The position maps and their depth tiles of one light and one size, a
  // map to a layer; each map's textures are views of its layer.
  struct PositionArrays {
    gl::Texture positions, tiles;
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, PositionArrays> position_arrays;  // by (light, position-map side)
  // A batch: the caustics maps of one light, one side and one
  // position-map side, a layer each of one array (arrange), drawn
  // together when the method and the driver allow (draw_batch).
  using BatchKey = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>;  // light, side, position-map side
  struct Batch {
    gl::Texture caustics;              // RGBA32F with mips, a layer per member
    std::vector<std::size_t> members;  // map indices, in layer order
    gl::Texture window_depth;          // the windows pass's, a layer per member
    gl::Texture window_surface;        // and its surface's mean frame V (R16 code), a layer per member
    gl::Framebuffer fbo;               // caustics and window_depth, layered
    // Each map's counts and draw commands (kBatchCounts).
    gl::Buffer command;
    gl::Buffer maps;                 // the maps drawn (caustics_batch.glsl's CausticsMap)
    std::size_t maps_capacity = 0;   // maps `command` and `maps` have room for
  };
  std::map<BatchKey, Batch> batches;
  // Kept to reuse their storage: the maps of a batch drawn now, what its
  // shaders read of them and its runs of maps (draw_batch), and the maps
  // by batch (arrange).
  std::vector<std::size_t> batch_drawn;
  std::vector<BatchMap> batch_info;
  std::vector<std::pair<std::size_t, std::size_t>> batch_runs;
  std::vector<std::pair<BatchKey, std::size_t>> arranged;
  gl::Texture position_depth;  // the position maps' re-derivation (rederive_map), shared
  std::uint32_t position_depth_size = 0;
  gl::Program splat_photon, splat_points;
  // Photon splatting (one set, reused map after map): the photon texture,
  // the vertex buffer it is copied into, and the points' vertex array.
  gl::Texture photon_texture;
  gl::Framebuffer photon_fbo;
  gl::Buffer photon_vbo;
  gl::VertexArray photon_vao;
  std::uint32_t photon_size = 0;
  gl::Buffer refracted, flux;
  // The cull's part of the water grid per map (caustics_rects.comp): the
  // water's bounds, then two uvec4 a map; the maps' world boxes it reads.
  gl::Buffer cull_rects, rect_boxes;
  std::size_t rects_capacity = 0;  // maps they have room for
  std::vector<glm::vec4> boxes;
  gl::Buffer list, primitives;  // every map's, one after the other
  std::uint64_t allocated = 0;  // entries they hold
  gl::VertexArray empty_vao;
  std::function<void(std::uint32_t)> draw_object;
  std::function<glm::mat4(std::uint32_t)> model_of;
  CausticsStats stats;  // the counts known on the CPU, of the last frame that drew maps
  bool counted_this_frame = false;
  // This frame's objects out of the camera's view (begin_frame; empty:
  // none), the updates among which such a map is remade once, and the
  // maps kept so this frame.
  std::vector<bool> out_of_view;
  std::uint32_t out_of_view_interval = 1;
  std::uint32_t maps_out_of_view = 0;
  bool hidden(const MapGpu& m) const { return m.lm->object < out_of_view.size() && out_of_view[m.lm->object]; }
  // update_light's per-map flags, kept to reuse their storage: re-derived
  // this update, and drawn this update.
  std::vector<bool> moved, draws;
  // The maps' GPU counters (list lengths, overflow, planes) come back
  // through `readback` a few frames late; `drawn` remembers which maps
  // each frame in flight drew (map, its list's generation).
  gl::ReadbackRing readback;
  std::uint64_t frame = 0;
  std::map<std::uint64_t, std::vector<std::pair<std::size_t, std::uint64_t>>> drawn;
  std::vector<std::uint64_t> generation;  // per map: bumped when its list is measured again
  std::uint64_t profiles = 0;             // depth profiles made on the GPU so far
  gl::Buffer plan_scratch;                // caustics_plan.comp's sub-box lengths
  GLsizeiptr plan_scratch_words = 0;
  // What each light's maps were made from, and per light how many times
  // its position maps were re-derived.
  MadeFrom<LightInputs> made;
  std::vector<std::uint64_t> positions_made;
  bool slot_open = false;  // this frame's read-back slot
  struct GpuCounts {
    std::uint64_t frame = 0;  // 0: none yet
    std::uint64_t volumes_drawn = 0, planes_drawn = 0;
    bool overflowed = false;
  } gpu_counts;

  // Re-derives the frame, position map and depth profile of map m for the
  // lights' and objects' current state (see caustics.h).
  void rederive_map(MapGpu& m, const std::vector<Light>& lights, const std::optional<Water>& water,
                    const std::vector<std::vector<std::array<double, 3>>>& world);

  // Map i's counters of this frame into the frame's read-back slot: its
  // list's need, overflow and entries drawn (the three words at `words`
  // of `command`: 8..10 of its own for a map drawn alone) and its plane
  // count.
  void read_counters_later(std::size_t i, GLuint command, GLintptr words) {
    if (!slot_open) slot_open = readback.begin();
    if (!slot_open) return;  // every slot in flight: this frame goes uncounted
    readback.copy(command, words, kCounterBytes * i, 12);
    readback.copy(all_planes.get(), maps[i].planes_offset, kCounterBytes * i + 12, 4);
    drawn[frame].emplace_back(i, generation[i]);
  }

  // The counters of every frame whose copies have landed: the latest
  // become the stats, and each list is sized from its count.
  void poll() {
    readback.poll([&](std::uint64_t tag, const std::uint8_t* data) {
      const auto it = drawn.find(tag);
      if (it == drawn.end()) return;
      GpuCounts c;
      c.frame = tag;
      for (const auto& [i, gen] : it->second) {
        std::uint32_t w[4];
        std::memcpy(w, data + kCounterBytes * i, sizeof w);
        c.volumes_drawn += w[2];
        c.overflowed = c.overflowed || w[1] != 0;
        c.planes_drawn += w[3];
        // What was drawn then misses pieces: remade at the next update,
        // with the list grown (a still scene would keep it otherwise).
        if (w[1] != 0) made.forget(maps[i].lm->light);
        if (gen != generation[i]) continue;  // a list since measured again
        size_list(maps[i], w[0]);
      }
      gpu_counts = c;
      drawn.erase(it);
    });
  }

  // The plane set in use follows the method (smart or uniform), the
  // run-time overrides and the depth profile; planned again only when one
  // of them changes. Where the CPU knows the histogram (as baked) it plans
  // them as the baker did (formats/slicing.h); after a re-derivation the
  // histogram is on the GPU and so are the planes (caustics_plan.comp),
  // with no read-back.
  void plan_planes(MapGpu& m, const CausticsOptions& o) {
    const PlanKey key = plan_key(m, o);
    if (m.plan == key) return;
    const LevelMap& lm = *m.lm;
    // A point further behind the first surface than any window (or two
    // depth quanta) is self-shadowed.
    const float quanta = static_cast<float>(4.0 * lm.frame.half[1] / kDepthQuantum);
    if (!key.smart || m.profile == 0) {
      std::vector<ReferencePlane> planes =
          !key.smart                   ? uniform_planes(key.height, key.pieces)
          : !o.planes && !o.epsilon    ? lm.smart_planes
                                       : smart_planes(key.height, static_cast<std::uint32_t>(lm.histogram.size()), lm.sub_boxes,
                                                      key.epsilon, nullptr);
      std::vector<float> packed(4 + 2 * planes.size());
      float lo = 1e30f, hi = -1e30f, widest = 0;
      for (std::size_t k = 0; k < planes.size(); ++k) {
        packed[4 + 2 * k] = planes[k].offset;
        packed[5 + 2 * k] = planes[k].epsilon;
        lo = std::min(lo, planes[k].offset - planes[k].epsilon);
        hi = std::max(hi, planes[k].offset + planes[k].epsilon);
        widest = std::max(widest, planes[k].epsilon);
      }
      const auto count = static_cast<std::uint32_t>(planes.size());
      std::memcpy(&packed[0], &count, 4);
      packed[1] = lo;
      packed[2] = hi;
      packed[3] = widest;
      glNamedBufferSubData(all_planes.get(), m.planes_offset, static_cast<GLsizeiptr>(packed.size() * 4), packed.data());
      m.self_tolerance = std::max(widest, quanta);
      m.cpu_planes = std::move(planes);
    } else {
      const gl::TimedPass timed("level maps: plan", gl::PassKind::kCompute);
      const auto levels = static_cast<GLsizeiptr>(lm.histogram.size());
      if (plan_scratch_words < 2 * levels + 2) {
        plan_scratch = gl::make_buffer();
        plan_scratch_words = 2 * levels + 2;
        glNamedBufferStorage(plan_scratch.get(), 4 * plan_scratch_words, nullptr, 0);
      }
      glClearNamedBufferData(plan_scratch.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, plan_scratch.get());
      plan.use();
      plan.set("u_levels", static_cast<unsigned>(lm.histogram.size()));
      glProgramUniform1d(plan.id(), plan.loc("u_height"), key.height);
      glProgramUniform1d(plan.id(), plan.loc("u_epsilon"), key.epsilon);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, m.histogram.get());
      bind_planes(m);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      glDispatchCompute(1, 1, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      // Smart windows are at most eps wide (eq. 4-22 rounds the count up).
      m.self_tolerance = std::max(static_cast<float>(key.epsilon), quanta);
      m.cpu_planes.reset();
    }
    m.plan = key;
  }

  // The list and primitive buffers, which the maps share (each map, or run
  // of a batch's maps, is drawn before the next is culled): as large as the
  // largest map's capacity,
  // grown when one grew, re-made smaller when that is less than half.
  void ensure_list() {
    std::uint64_t want = 0;
    for (const MapGpu& m : maps) want = std::max(want, m.capacity);
    if (allocated >= want && allocated <= 2 * want) return;
    list = gl::make_buffer();
    glNamedBufferStorage(list.get(), static_cast<GLsizeiptr>(want) * kListBytes, nullptr, 0);
    primitives = gl::make_buffer();
    glNamedBufferStorage(primitives.get(), static_cast<GLsizeiptr>(want) * kPrimitiveBytes, nullptr, 0);
    allocated = want;
  }

  // A list length `listed` measured for map `i` (from a read-back of any
  // age): grow at once when it nears the capacity; shrink when it has
  // stayed far below for a while.
  static void size_list(MapGpu& m, std::uint64_t listed) {
    std::uint64_t& capacity = m.capacity;
    std::uint64_t& quiet_polls = m.quiet_polls;
    const auto want = std::clamp<std::uint64_t>(static_cast<std::uint64_t>(std::ceil(static_cast<double>(listed) * kHeadroom)),
                                                kMinCapacity, kMaxPrimitives);
    if (static_cast<double>(listed) * 1.1 > static_cast<double>(capacity)) {
      capacity = std::max(capacity, want);
      quiet_polls = 0;
    } else if (2 * want < capacity) {
      if (++quiet_polls >= 30) {
        capacity = want;
        quiet_polls = 0;
      }
    } else {
      quiet_polls = 0;
    }
  }

  // The caustics maps of `light` as layers of arrays, one per batch (the
  // maps of one side and one position-map side): a batch whose maps
  // changed gets a new array, into which each map that keeps its side
  // brings its texels (every level), and each map a view of its layer.
  // Batches no map is left in go. A map not drawn now keeps the side it
  // has until it is.
  void arrange(std::uint32_t light, const std::vector<bool>& drawing) {
    arranged.clear();
    for (std::size_t i = 0; i < maps.size(); ++i) {
      const MapGpu& m = maps[i];
      if (m.lm->light != light || m.planned_side == 0) continue;
      const std::uint32_t side = drawing[i] || !m.caustics.get() ? m.planned_side : m.caustics_size;
      arranged.emplace_back(BatchKey{light, side, m.lm->map_size}, i);
    }
    std::sort(arranged.begin(), arranged.end());
    // Nothing to do (the steady frame) when every batch of the light has
    // these maps already.
    bool same = true;
    std::size_t groups = 0;
    for (std::size_t a = 0; a < arranged.size() && same; ++groups) {
      std::size_t e = a;
      while (e < arranged.size() && arranged[e].first == arranged[a].first) ++e;
      const auto b = batches.find(arranged[a].first);
      same = b != batches.end() && b->second.caustics.get() && b->second.members.size() == e - a &&
             std::equal(b->second.members.begin(), b->second.members.end(), arranged.begin() + static_cast<std::ptrdiff_t>(a),
                        [](std::size_t i, const auto& p) { return i == p.second; });
      a = e;
    }
    const auto light_batches = static_cast<std::size_t>(
        std::count_if(batches.begin(), batches.end(), [&](const auto& b) { return std::get<0>(b.first) == light; }));
    if (same && groups == light_batches) return;
    std::map<BatchKey, std::vector<std::size_t>> want;
    for (const auto& [key, i] : arranged) want[key].push_back(i);
    std::erase_if(batches, [&](const auto& b) { return std::get<0>(b.first) == light && !want.contains(b.first); });
    for (auto& [key, members] : want) {
      Batch& b = batches[key];
      if (b.members == members && b.caustics.get()) continue;
      const std::uint32_t side = std::get<1>(key);
      // A mip chain, so that casting a fine caustics map onto a receiver
      // seen from afar averages it instead of aliasing (averaging keeps the
      // mean irradiance).
      GLsizei levels = 1;
      while ((side >> levels) > 0) ++levels;
      gl::Texture array = gl::make_texture(GL_TEXTURE_2D_ARRAY);
      const auto size = static_cast<GLsizei>(side);
      glTextureStorage3D(array.get(), levels, GL_RGBA32F, size, size, static_cast<GLsizei>(members.size()));
      for (std::size_t layer = 0; layer < members.size(); ++layer) {
        MapGpu& m = maps[members[layer]];
        if (m.caustics.get() && m.caustics_size == side) {
          for (GLint level = 0; level < levels; ++level) {
            const GLsizei s = std::max(size >> level, 1);
            glCopyImageSubData(m.caustics.get(), GL_TEXTURE_2D, level, 0, 0, 0, array.get(), GL_TEXTURE_2D_ARRAY, level, 0, 0,
                               static_cast<GLint>(layer), s, s, 1);
          }
        }
        m.caustics = gl::make_view(GL_TEXTURE_2D, array.get(), GL_RGBA32F, 0, static_cast<GLuint>(levels), static_cast<GLuint>(layer), 1);
        glTextureParameteri(m.caustics.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTextureParameteri(m.caustics.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(m.caustics.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(m.caustics.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        m.fbo = gl::make_framebuffer();
        glNamedFramebufferTexture(m.fbo.get(), GL_COLOR_ATTACHMENT0, m.caustics.get(), 0);
        m.caustics_size = side;
        m.windows_made.reset();
        m.layer = static_cast<std::uint32_t>(layer);
        m.batched = false;
      }
      b.caustics = std::move(array);
      b.members = members;
      b.window_depth.reset();
      b.window_surface.reset();
      b.fbo.reset();
    }
  }

  // A map's windows' depth (16-bit: the draw compares (k + 1) / 65535
  // exactly, caustics_windows.frag) and surface at its side, drawn alone;
  // a batch has its own (draw_batch).
  static void ensure_windows(MapGpu& m) {
    if (m.window_size == m.caustics_size && m.window_depth.get()) return;
    const auto size = static_cast<GLsizei>(m.caustics_size);
    m.window_size = m.caustics_size;
    m.windows_made.reset();  // what it says was made in its batch's layer
    m.window_depth = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(m.window_depth.get(), 1, GL_DEPTH_COMPONENT16, size, size);
    m.window_surface = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(m.window_surface.get(), 1, GL_R16, size, size);
  }

  // What a map's windows are made for (MapGpu::windows_made): its planes
  // and its side.
  static std::pair<PlanKey, std::uint32_t> windows_key(const MapGpu& m) { return {*m.plan, m.caustics_size}; }

  static void release_windows(MapGpu& m) {
    m.window_depth.reset();
    m.window_surface.reset();
    m.window_size = 0;
    m.windows_made.reset();
  }

  void ensure_slices(MapGpu& m, std::uint32_t count, std::uint32_t size) {
    if (m.slice_count == count && m.slice_size == size && m.slices.get()) return;
    m.slices = gl::make_texture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(m.slices.get(), 1, GL_R8, static_cast<GLsizei>(size), static_cast<GLsizei>(size), static_cast<GLsizei>(count));
    m.illumination = gl::make_texture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(m.illumination.get(), 1, GL_RGBA32F, static_cast<GLsizei>(size), static_cast<GLsizei>(size), static_cast<GLsizei>(count));
    m.slice_count = count;
    m.slice_size = size;
  }

  // Min/max frame V per tile of the position map (for per-plane culling),
  // by profile.comp: one code path at load and after re-derivation.
  void build_depth_tiles(MapGpu& m) {
    const std::uint32_t nt = (m.lm->map_size + kTileTexels - 1) / kTileTexels;
    profile.use();
    profile.set("u_mode", 1);
    profile.set("u_tile", static_cast<int>(kTileTexels));
    profile.set("u_half_v", m.lm->frame.half[1]);
    glBindTextureUnit(0, m.position_map.get());
    glBindImageTexture(0, m.depth_tiles.get(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    glDispatchCompute((nt + 7) / 8, (nt + 7) / 8, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }

  // A map's own textures, which its texels size (bytes_per_texel).
  static std::uint64_t texture_bytes(const MapGpu& m) {
    // RGBA32F and its mips, and its window depth and surface: its
    // batch's layer, or its own drawn alone.
    const std::uint64_t texels = std::uint64_t{m.caustics_size} * m.caustics_size;
    const std::uint64_t cm = texels * 16 * 4 / 3 + (m.batched ? texels * 4 : 0) + std::uint64_t{m.window_size} * m.window_size * 4;
    const std::uint64_t sl = std::uint64_t{m.slice_size} * m.slice_size * m.slice_count * (1 + 16);
    const std::uint64_t spectral = std::uint64_t{m.spectral_size} * m.spectral_size * 16 * 7 / 3;  // sum, colour and its mips
    return cm + sl + spectral;
  }

  // Everything a map holds: its textures and what the bake sized.
  static std::uint64_t bytes_of(const MapGpu& m) {
    const std::uint64_t pm = std::uint64_t{m.lm->map_size} * m.lm->map_size * 2;
    const std::uint64_t tiles = pm / (kTileTexels * kTileTexels) * 2;
    const std::uint64_t profile = 4 * m.lm->histogram.size() + kPlanesBytes;
    return pm + texture_bytes(m) + tiles + profile + static_cast<std::uint64_t>(kCommandBytes);
  }

  // The batches' buffers (their textures are their maps').
  std::uint64_t batch_bytes() const {
    std::uint64_t bytes = 0;
    for (const auto& [key, b] : batches) {
      bytes += b.maps_capacity * (kBatchBytesPerMap + sizeof(BatchMap)) + (b.maps_capacity > 0 ? kBatchCounts : 0);
    }
    return bytes;
  }

  // What the maps share: refracted rays and fluxes, the read-back ring,
  // the splats' photons (one set for every map), the planner's scratch,
  // the lists and the re-derivations' depth.
  std::uint64_t shared_bytes() const {
    return std::uint64_t{16} * water->vertex_count() + std::uint64_t{8} * water->triangle_count() + readback.gpu_bytes() +
           std::uint64_t{32} * photon_size * photon_size + 4 * static_cast<std::uint64_t>(plan_scratch_words) +
           allocated * (kListBytes + kPrimitiveBytes) +
           std::uint64_t{4} * position_depth_size * position_depth_size + 16 + batch_bytes() + 32 + 64 * std::uint64_t{rects_capacity};
  }

  // The larger side of the part of map m's frame (its U-W rectangle) that
  // the water's light can reach: the water grid's rectangle at its level
  // seen along V (the refracted light), grown by a tenth of its larger
  // side for light the waves bend outward, clipped to the frame; 0 where
  // they miss, or where the light no longer reaches the receiver through
  // the water. A point light under the water lights the whole frame.
  double lit_extent(const MapGpu& m, const std::vector<Light>& lights) const {
    const BoundingFrame& f = m.lm->frame;
    if (m.unlit) return 0.0;
    const Water& w = water->water();
    const Light& light = lights[m.lm->light];
    if (light.type != LightType::kDirectional && light.position[1] <= w.level) return 2.0 * std::max(f.half[0], f.half[2]);
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (int c = 0; c < 4; ++c) {
      const double rel[3] = {w.extent[(c & 1) != 0 ? 2 : 0] - f.origin[0], w.level - f.origin[1],
                             w.extent[(c & 2) != 0 ? 3 : 1] - f.origin[2]};
      const double uw[2] = {rel[0] * f.u[0] + rel[1] * f.u[1] + rel[2] * f.u[2], rel[0] * f.w[0] + rel[1] * f.w[1] + rel[2] * f.w[2]};
      for (int k = 0; k < 2; ++k) {
        lo[k] = std::min(lo[k], uw[k]);
        hi[k] = std::max(hi[k], uw[k]);
      }
    }
    const double margin = 0.1 * std::max(double{w.extent[2]} - w.extent[0], double{w.extent[3]} - w.extent[1]);
    const double half[2] = {f.half[0], f.half[2]};
    double side = 0.0;
    for (int k = 0; k < 2; ++k) {
      const double a = std::max(lo[k] - margin, -half[k]), b = std::min(hi[k] + margin, half[k]);
      if (b <= a) return 0.0;
      side = std::max(side, b - a);
    }
    return side;
  }

  // Texels by need under the budget (CausticsOptions::texel_size,
  // memory_budget): per light one texel size in metres -- texel_size, or
  // the largest lit extent of the light's maps over map_size -- and each
  // map the side its frame needs at it (ladder_side), at least
  // kLeastShare of map_size (with the texel from map_size) but not above
  // kLeastOverNeed times its need, and at most map_size (or
  // kMaxRuntimeMapSize with texel_size). Where the light side
  // would then hold more than the budget, it steps down by 2^(1/4) at a
  // time: first that least side, towards the maps' own need (small
  // receivers give up the texels they have beyond the floor's density),
  // then every texel, until the maps fit. Where not even the smallest
  // maps would fit, only the first steps are taken and the stats say so.
  // A step once taken is kept while it fits and the finer one would win
  // back less than two steps, so that the maps do not change size back
  // and forth. Warns once per new step. The sides take effect at each
  // map's next draw.
  void plan_texels(const CausticsOptions& o, const std::vector<Light>& lights) {
    const bool spectral = water_wavelengths(water->water(), o).size() > 1;
    const bool given = o.texel_size > 0.0f;
    const std::uint32_t cap = given ? kMaxRuntimeMapSize : std::max(o.map_size, 1u);
    const double least = given ? 0.0 : kLeastShare * cap;
    // Steps that lower the least side before the texels coarsen: until it
    // is below the smallest map.
    const int least_steps = least > kMinCausticsMapSize ? static_cast<int>(std::ceil(4.0 * std::log2(least / kMinCausticsMapSize))) : 0;
    const int last_step = least_steps + kMaxCoarsenSteps;
    std::vector<double> lit(maps.size()), base(positions_made.size(), given ? double{o.texel_size} : 0.0);
    // The pair lists are sized from counts read back as the maps are
    // drawn, and coarser texels list more pairs (the cull widens each
    // footprint by a texel): room for them to grow by their headroom.
    std::uint64_t fixed = other_bytes + shared_bytes() +
                          static_cast<std::uint64_t>(static_cast<double>(allocated * (kListBytes + kPrimitiveBytes)) * (kHeadroom - 1.0));
    for (std::size_t i = 0; i < maps.size(); ++i) {
      const MapGpu& m = maps[i];
      lit[i] = lit_extent(m, lights);
      if (!given) base[m.lm->light] = std::max(base[m.lm->light], lit[i] / static_cast<double>(cap));
      fixed += bytes_of(m) - texture_bytes(m);
    }
    auto texel_factor = [&](int k) { return std::pow(2.0, std::max(k - least_steps, 0) / 4.0); };
    auto least_at = [&](int k) { return k < least_steps ? least * std::pow(2.0, -k / 4.0) : 0.0; };
    // The maps' sides and bytes at step k.
    auto plan_at = [&](int k, std::vector<std::uint32_t>* sides) {
      const double factor = texel_factor(k), floor_side = least_at(k);
      std::uint64_t bytes = 0;
      for (std::size_t i = 0; i < maps.size(); ++i) {
        const MapGpu& m = maps[i];
        const double texel = base[m.lm->light] * factor;
        std::uint32_t side = 0;
        if (lit[i] > 0.0 && texel > 0.0) {
          const double need = 2.0 * std::max(m.lm->frame.half[0], m.lm->frame.half[2]) / texel;
          side = std::min(cap, ladder_side(std::max(need, std::min(floor_side, kLeastOverNeed * need))));
        }
        bytes += static_cast<std::uint64_t>(static_cast<double>(side) * side * bytes_per_texel(m, o, spectral));
        if (sides) (*sides)[i] = side;
      }
      return bytes;
    };
    int step = 0;
    bool over = false;
    if (o.memory_budget > 0) {
      auto fits = [&](int k) { return fixed + plan_at(k, nullptr) <= o.memory_budget; };
      // The smallest step that fits (the bytes fall as the step grows).
      // Where not even the smallest maps fit, what is over is not theirs
      // (position maps, shadow maps, the other effects): coarsening them
      // would cost the picture and hardly the memory, so only the small
      // receivers' extra texels go.
      over = !fits(last_step);
      int lo = 0, hi = last_step;
      while (lo < hi && !over) {
        const int mid = (lo + hi) / 2;
        if (fits(mid)) {
          hi = mid;
        } else {
          lo = mid + 1;
        }
      }
      step = over ? least_steps : lo;
      if (!over && coarsen_step > step && coarsen_step - step <= 1 && fits(coarsen_step)) step = coarsen_step;
    }
    std::vector<std::uint32_t> sides(maps.size());
    const std::uint64_t bytes = plan_at(step, &sides);
    double finest = 0.0;
    std::uint32_t unreachable = 0;
    for (std::size_t i = 0; i < maps.size(); ++i) {
      maps[i].planned_side = sides[i];
      maps[i].planned = true;
      if (sides[i] == 0) {
        ++unreachable;
      } else {
        const double t = base[maps[i].lm->light];
        finest = finest == 0.0 ? t : std::min(finest, t);
      }
    }
    const double factor = texel_factor(step);
    texels.texel = static_cast<float>(finest * factor);
    texels.coarsened = static_cast<float>(factor);
    texels.least_side = static_cast<std::uint32_t>(std::min<double>(least_at(step), cap));
    texels.unreachable = unreachable;
    texels.budget = o.memory_budget;
    texels.light_side = fixed + bytes;
    texels.over_budget = over;
    if (step > warned_step || (over && !warned_over)) {
      const double mib = 1024.0 * 1024.0;
      char text[640];
      if (over) {
        std::snprintf(text, sizeof text,
                      "caustics maps: the light side holds %.1f MiB besides its caustics maps (position maps, shadow maps, the "
                      "other effects), over the memory budget of %.1f MiB (CausticsOptions::memory_budget): the maps are kept "
                      "at their need (%.1f MiB); a smaller baked position map (caustix-bake --map-size) or fewer lights would fit",
                      static_cast<double>(fixed) / mib, static_cast<double>(o.memory_budget) / mib, static_cast<double>(bytes) / mib);
      } else {
        char sides[64] = "every map at its need";
        if (texels.least_side > 0) std::snprintf(sides, sizeof sides, "small receivers' maps at least %u texels a side", texels.least_side);
        char coarser[96] = "";
        if (factor > 1.0) std::snprintf(coarser, sizeof coarser, ", texels coarsened %.2fx to %.2f mm", factor, finest * factor * 1e3);
        std::snprintf(text, sizeof text,
                      "caustics maps: at %.2f mm texels and at least %.0f texels a side the light side would hold %.1f MiB, over "
                      "the memory budget of %.1f MiB (CausticsOptions::memory_budget): %s%s (%.1f MiB)",
                      finest * 1e3, least, static_cast<double>(fixed + plan_at(0, nullptr)) / mib,
                      static_cast<double>(o.memory_budget) / mib, sides, coarser, static_cast<double>(fixed + bytes) / mib);
      }
      warnings.emplace_back(text);
      warned_step = std::max(warned_step, step);
      warned_over = warned_over || over;
    }
    coarsen_step = step;
  }

  // A map the water's light cannot reach holds no textures.
  static void release_textures(MapGpu& m) {
    m.caustics.reset();
    m.fbo.reset();
    release_windows(m);
    m.caustics_size = 0;
    m.batched = false;
    m.slices.reset();
    m.illumination.reset();
    m.slice_count = m.slice_size = 0;
    m.spectral_sum.reset();
    m.color.reset();
    m.spectral_size = 0;
    m.spectral = false;
  }

  // The light and the water's IOR, for the passes that refract at the water.
  void set_light(const gl::Program& p, const Light& light, float ior) const {
    p.set("u_light_type", static_cast<int>(light.type));
    p.set("u_light_direction", v3(light.direction));
    p.set("u_light_position", v3(light.position));
    p.set("u_light_power", light.type == LightType::kDirectional ? light.irradiance : light.intensity);
    const auto cone = spot_terms(light);
    p.set("u_spot", glm::vec3(cone[0], cone[1], cone[2]));
    p.set("u_ior", ior);
  }

  void ensure_spectral(MapGpu& m) {
    if (m.spectral_size == m.caustics_size && m.color.get()) return;
    const auto size = static_cast<GLsizei>(m.caustics_size);
    GLsizei levels = 1;
    while ((m.caustics_size >> levels) > 0) ++levels;
    m.spectral_sum = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(m.spectral_sum.get(), 1, GL_RGBA32F, size, size);
    m.color = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(m.color.get(), levels, GL_RGBA32F, size, size);
    glTextureParameteri(m.color.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(m.color.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(m.color.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(m.color.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    m.spectral_size = m.caustics_size;
  }

  // One traced wavelength's map (level 0, not yet finished) into the sums
  // over wavelengths (caustics_accumulate.comp); the last writes the sum
  // back into the map.
  void accumulate_wavelength(MapGpu& m, const WavelengthSample& w, bool first, bool last) {
    ensure_spectral(m);
    const gl::TimedPass timed("level maps: wavelength sums", gl::PassKind::kCompute);
    accumulate.use();
    accumulate.set("u_size", static_cast<int>(m.caustics_size));
    accumulate.set("u_rgb", glm::vec3(w.rgb[0], w.rgb[1], w.rgb[2]));
    accumulate.set("u_first", first ? 1 : 0);
    accumulate.set("u_last", last ? 1 : 0);
    glBindImageTexture(0, m.caustics.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(1, m.spectral_sum.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(2, m.color.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    const GLuint groups = (m.caustics_size + 7) / 8;
    glDispatchCompute(groups, groups, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT);
    for (GLuint u = 0; u < 3; ++u) glBindImageTexture(u, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    if (last) glGenerateTextureMipmap(m.color.get());
  }

  // Mihalik 2008 ch. 8, GPU variant: render the water along V into the photon
  // texture (splat_photon.frag), copy it into a vertex buffer through the
  // pixel-pack binding (the paper's PBO route), draw it as points with
  // additive blending into the caustics map.
  void draw_splat(MapGpu& m, const CausticsOptions& o, const Light& light, float ior) {
    const gl::TimedPass timed("level maps: splats", gl::PassKind::kRaster);
    const BoundingFrame& f = m.lm->frame;
    const std::uint32_t p = o.photons;
    if (photon_size != p) {
      photon_texture = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(photon_texture.get(), 1, GL_RGBA32UI, static_cast<GLsizei>(p), static_cast<GLsizei>(p));
      photon_fbo = gl::make_framebuffer();
      glNamedFramebufferTexture(photon_fbo.get(), GL_COLOR_ATTACHMENT0, photon_texture.get(), 0);
      photon_vbo = gl::make_buffer();
      glNamedBufferStorage(photon_vbo.get(), GLsizeiptr{16} * p * p, nullptr, 0);
      photon_vao = gl::make_vertex_array();
      glVertexArrayVertexBuffer(photon_vao.get(), 0, photon_vbo.get(), 0, 16);
      glEnableVertexArrayAttrib(photon_vao.get(), 0);
      glVertexArrayAttribIFormat(photon_vao.get(), 0, 4, GL_UNSIGNED_INT, 0);
      glVertexArrayAttribBinding(photon_vao.get(), 0, 0);
      photon_size = p;
    }
    // The window: the frame's U-W rectangle grown by a margin, so that
    // photons the waves bend in from beside it are counted.
    constexpr float kMargin = 0.1f;
    const float gx = f.half[0] * (1 + 2 * kMargin), gz = f.half[2] * (1 + 2 * kMargin);
    const glm::vec3 origin(static_cast<float>(f.origin[0]), static_cast<float>(f.origin[1]), static_cast<float>(f.origin[2]));
    glm::mat4 to_clip(0.0f);  // world -> (U / gx, W / gz, 0, 1) about the frame's origin
    for (int k = 0; k < 3; ++k) {
      to_clip[k][0] = f.u[k] / gx;
      to_clip[k][1] = f.w[k] / gz;
    }
    to_clip[3][0] = -glm::dot(v3(f.u), origin) / gx;
    to_clip[3][1] = -glm::dot(v3(f.w), origin) / gz;
    to_clip[3][3] = 1.0f;
    const float zero[4] = {0, 0, 0, 0};
    glBindFramebuffer(GL_FRAMEBUFFER, photon_fbo.get());
    glViewport(0, 0, static_cast<GLsizei>(p), static_cast<GLsizei>(p));
    const GLuint zero_bits[4] = {0, 0, 0, 0};
    glClearNamedFramebufferuiv(photon_fbo.get(), GL_COLOR, 0, zero_bits);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    splat_photon.use();
    splat_photon.set("u_view_proj", to_clip);
    set_frame(splat_photon, f);
    set_light(splat_photon, light, ior);
    splat_photon.set("u_pixel_area", (2 * gx / static_cast<float>(p)) * (2 * gz / static_cast<float>(p)));
    const float texel_u = 2 * f.half[0] / static_cast<float>(m.caustics_size), texel_w = 2 * f.half[2] / static_cast<float>(m.caustics_size);
    splat_photon.set("u_texel_area", texel_u * texel_w);
    splat_photon.set("u_tolerance", m.self_tolerance + 4.0f * 2.0f * std::max(f.half[0], f.half[2]) / static_cast<float>(m.lm->map_size));
    glBindTextureUnit(0, m.position_map.get());
    water->bind_buffers();
    water->draw();

    glBindBuffer(GL_PIXEL_PACK_BUFFER, photon_vbo.get());
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT);
    glGetTextureImage(photon_texture.get(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(GLsizeiptr{16} * p * p), nullptr);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);

    glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
    glViewport(0, 0, static_cast<GLsizei>(m.caustics_size), static_cast<GLsizei>(m.caustics_size));
    glClearNamedFramebufferfv(m.fbo.get(), GL_COLOR, 0, zero);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    splat_points.use();
    splat_points.set("u_size", static_cast<float>(m.caustics_size));
    // Photons per texel along a side (the window is the map's, grown): the
    // wider filter where they are fewer than one (splat_points.vert).
    const float per_texel = static_cast<float>(p) / ((1 + 2 * kMargin) * static_cast<float>(m.caustics_size));
    splat_points.set("u_wide", per_texel < 1.0f ? 1 : 0);
    glBindVertexArray(photon_vao.get());
    glEnable(GL_PROGRAM_POINT_SIZE);
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(p * p));
    glDisable(GL_PROGRAM_POINT_SIZE);
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    stats.volumes_total += std::uint64_t{p} * p;
  }

  // Alpha = the receiver's presence (caustics_presence.frag), before the
  // mip chain (make_mips); m.fbo draws into the map's level 0. A level-map
  // draw's windows pass wrote it already (caustics_windows.frag), unless the
  // map sums wavelengths.
  void finish_map(MapGpu& m, const CausticsOptions& o) {
    if (m.windows_presence && !m.spectral) return;
    const gl::TimedPass timed("level maps: presence and mips", gl::PassKind::kRaster);
    glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
    glViewport(0, 0, static_cast<GLsizei>(m.caustics_size), static_cast<GLsizei>(m.caustics_size));
    glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
    presence.use();
    const auto [scale, samples] = texel_sampling(m);
    presence.set("u_map_scale", glm::vec2(scale));
    presence.set("u_samples", samples);
    // The level-map draws give a texel its surface samples' irradiance;
    // splats and the volumetric slices the light over the whole texel.
    presence.set("u_fraction", o.method == CausticsMethod::kSplat || o.method == CausticsMethod::kVolumetric ? 1 : 0);
    glBindTextureUnit(0, m.position_map.get());
    glBindVertexArray(empty_vao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }

  // The mip chains of the arrays that hold a map of `light` drawn now
  // (`drawing`), one call an array (a view's would make the whole
  // array's). Averaging keeps the mean irradiance.
  void make_mips(std::uint32_t light, const std::vector<bool>& drawing) {
    std::optional<gl::TimedPass> timed;
    for (const auto& [key, b] : batches) {
      if (std::get<0>(key) != light) continue;
      if (std::none_of(b.members.begin(), b.members.end(), [&](std::size_t i) { return drawing[i]; })) continue;
      if (!timed) timed.emplace("level maps: presence and mips", gl::PassKind::kRaster);
      glGenerateTextureMipmap(b.caustics.get());
    }
  }

  void ensure_rects() {
    if (rects_capacity >= maps.size() && cull_rects.get()) return;
    rects_capacity = maps.size();
    cull_rects = gl::make_buffer();
    glNamedBufferStorage(cull_rects.get(), kRectsHeader + kRectBytes * static_cast<GLsizeiptr>(rects_capacity), nullptr, 0);
    rect_boxes = gl::make_buffer();
    glNamedBufferStorage(rect_boxes.get(), 32 * static_cast<GLsizeiptr>(std::max<std::size_t>(rects_capacity, 1)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
  }

  // Every map's part of the water grid for the cull (caustics_rects.comp),
  // from the water's bounds that the refraction just took and the frames'
  // world boxes.
  void make_rects() {
    boxes.clear();
    for (const MapGpu& m : maps) {
      const BoundingFrame& f = m.lm->frame;
      glm::dvec3 lo(1e300), hi(-1e300);
      for (int c = 0; c < 8; ++c) {
        glm::dvec3 p(f.origin[0], f.origin[1], f.origin[2]);
        for (int a = 0; a < 3; ++a) {
          const Vec3f& axis = a == 0 ? f.u : a == 1 ? f.v : f.w;
          const double h = ((c >> a) & 1) != 0 ? f.half[static_cast<std::size_t>(a)] : -f.half[static_cast<std::size_t>(a)];
          p += h * glm::dvec3(axis[0], axis[1], axis[2]);
        }
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
      boxes.emplace_back(glm::vec3(lo), 0.0f);
      boxes.emplace_back(glm::vec3(hi), 0.0f);
    }
    if (boxes.empty()) return;
    const gl::TimedPass timed("level maps: water rectangles", gl::PassKind::kCompute);
    glNamedBufferSubData(rect_boxes.get(), 0, static_cast<GLsizeiptr>(boxes.size() * sizeof(glm::vec4)), boxes.data());
    const Water& w = water->water();
    rects.use();
    rects.set("u_count", static_cast<unsigned>(maps.size()));
    glProgramUniform2ui(rects.id(), rects.loc("u_cells"), w.cells[0], w.cells[1]);
    rects.set("u_extent", glm::vec4(w.extent[0], w.extent[1], w.extent[2], w.extent[3]));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 13, rect_boxes.get());
    glDispatchCompute((static_cast<GLuint>(maps.size()) + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  }

  // One wavelength's caustics map into level 0 (finish_map makes its
  // presence and mips).
  void draw_map(MapGpu& m, const CausticsOptions& o, const Light& light, float ior) {
    const BoundingFrame& f = m.lm->frame;
    plan_planes(m, o);
    m.windows_presence = false;
    const bool pairs = o.method != CausticsMethod::kVolumetric;
    // Another pass writes the presence, or nothing: the windows made last are
    // not what the map holds.
    if (!pairs || o.method == CausticsMethod::kSplat || (m.cpu_planes && m.cpu_planes->empty())) m.windows_made.reset();
    if (o.method == CausticsMethod::kSplat) {
      draw_splat(m, o, light, ior);
      return;
    }
    if (m.cpu_planes && m.cpu_planes->empty()) {  // a map whose sampled surface is empty (e.g. a tiny position map): no caustics
      const float none[4] = {0, 0, 0, 0};
      glClearTexImage(m.caustics.get(), 0, GL_RGBA, GL_FLOAT, none);
      glClearNamedBufferData(m.command.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
      return;
    }

    // 1. Cull: volumes that miss the frame, and (level map) planes the
    // surface under a volume does not need.
    // The list is sized by what it needs, not by the worst case (every
    // volume through every plane). The first frame a map is drawn with a
    // plan (the warm-up) reads the count back and re-runs the cull with a
    // larger list if it overflowed: exact, at the cost of one small
    // read-back. Later frames size it from counts read asynchronously
    // (size_list), with headroom; one that still overflows draws what fits
    // and says so (CausticsStats::overflowed).
    const ListKey list_key{pairs, o.cull, m.plan->smart, o.planes.value_or(0), o.epsilon.value_or(0.0f), m.caustics_size};
    const bool measure = m.measured != list_key;
    // Before the first measurement: a small list the warm-up re-sizes.
    if (m.capacity == 0) m.capacity = kMinCapacity;
    // The shared list may still feed the last map's draw.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    std::optional<gl::TimedPass> timed_cull;
    timed_cull.emplace("level maps: cull", gl::PassKind::kCompute);
    for (int attempt = 0; attempt < (measure ? 2 : 1); ++attempt) {
      ensure_list();
      glClearNamedBufferData(m.command.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
      cull.use();
      set_frame(cull, f);
      cull.set("u_triangles", water->triangle_count());
      cull.set("u_frame_cull", o.cull ? 1 : 0);
      cull.set("u_plane_cull", o.cull ? 1 : 0);
      cull.set("u_pairs", pairs ? 1 : 0);
      // Widen footprints by a caustics texel where the acceptance test
      // samples surface across it (texels coarser than the position map's);
      // at finer texels the depth tiles (8 position texels) already cover it.
      const bool coarse = m.caustics_size < m.lm->map_size;
      cull.set("u_texel", coarse ? glm::vec2(2.0f * f.half[0], 2.0f * f.half[2]) / static_cast<float>(m.caustics_size)
                                 : glm::vec2(0.0f));
      cull.set("u_capacity", static_cast<unsigned>(allocated));
      // Only the water triangles that can reach the frame (update_light's
      // rectangles), unless culling is off.
      const auto index = static_cast<std::size_t>(&m - maps.data());
      cull.set("u_rect", o.cull ? static_cast<int>(index) : -1);
      glBindTextureUnit(0, m.depth_tiles.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, flux.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, list.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, m.command.get());
      bind_planes(m);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, primitives.get());
      if (o.cull) {
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, cull_rects.get());
        glDispatchComputeIndirect(static_cast<GLintptr>(kRectsHeader + kRectBytes * index));
      } else {
        glDispatchCompute((water->triangle_count() + 63) / 64, 1, 1);
      }
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
      if (!measure) break;
      std::uint32_t listed = 0;
      glGetNamedBufferSubData(m.command.get(), 32, 4, &listed);  // warm-up only
      const bool fits = listed <= allocated || allocated >= kMaxPrimitives;
      m.capacity = std::clamp<std::uint64_t>(static_cast<std::uint64_t>(std::ceil(listed * kHeadroom)), kMinCapacity, kMaxPrimitives);
      if (fits) break;
    }
    if (measure) {
      m.measured = list_key;
      ++generation[static_cast<std::size_t>(&m - maps.data())];
    }
    // 2. The list's length becomes the geometry dispatch and the draw count.
    fixup.use();
    fixup.set("u_capacity", static_cast<unsigned>(allocated));
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    timed_cull.reset();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, m.command.get());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, m.command.get());
    geometry.use();
    set_frame(geometry, f);
    geometry.set("u_pairs", pairs ? 1 : 0);
    geometry.set("u_max_magnification", o.max_magnification);
    geometry.set("u_smooth", o.water_smooth ? 1 : 0);
    glProgramUniform2ui(geometry.id(), geometry.loc("u_grid"), water->water().cells[0] + 1, water->water().cells[1] + 1);
    geometry.set("u_map_size", static_cast<float>(m.caustics_size));

    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    const auto size = static_cast<GLsizei>(m.caustics_size);
    const float zero[4] = {0, 0, 0, 0};
    // 3. Geometry of every listed primitive, then 4. one rectangle each.
    auto geometry_then_draw = [&](const gl::Program& draw_program, int plane) {
      {
        const gl::TimedPass timed("level maps: geometry", gl::PassKind::kCompute);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // the last plane's draw read the primitives
        geometry.use();
        geometry.set("u_plane", plane);
        glDispatchComputeIndirect(20);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      }
      const gl::TimedPass timed("level maps: draw", gl::PassKind::kRaster);
      draw_program.use();
      draw_program.set("u_map_size", static_cast<float>(m.caustics_size));
      glBindVertexArray(empty_vao.get());
      glDrawArraysIndirect(GL_TRIANGLES, nullptr);
    };

    if (pairs) {
      m.windows_presence = true;
      ensure_windows(m);
      glNamedFramebufferTexture(m.fbo.get(), GL_DEPTH_ATTACHMENT, m.window_depth.get(), 0);
      glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
      glViewport(0, 0, size, size);
      const bool windows_kept = m.windows_made == windows_key(m);
      // The irradiance, and the presence too where the windows pass
      // writes it again.
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, windows_kept ? GL_FALSE : GL_TRUE);
      glClearNamedFramebufferfv(m.fbo.get(), GL_COLOR, 0, zero);
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      const auto [scale, samples] = texel_sampling(m);
      glBindTextureUnit(0, m.position_map.get());
      if (!windows_kept) {
        // 3a. Each texel's window into depth, so that the draw's depth test
        // drops the fragments its window test would discard, before they
        // are shaded (caustics_windows.frag). Made again only when the
        // planes, the position map or the map's side change.
        const gl::TimedPass timed("level maps: windows", gl::PassKind::kRaster);
        const float no_window = 0.0f;
        glDepthMask(GL_TRUE);
        glClearNamedFramebufferfv(m.fbo.get(), GL_DEPTH, 0, &no_window);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_ALWAYS);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);  // and the presence in alpha
        windows.use();
        windows.set("u_map_scale", glm::vec2(scale));
        windows.set("u_samples", samples);
        windows.set("u_half_v", f.half[1]);
        glBindImageTexture(0, m.window_surface.get(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16);
        glBindVertexArray(empty_vao.get());
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        m.windows_made = windows_key(m);
      }
      glEnable(GL_DEPTH_TEST);
      glDepthMask(GL_FALSE);
      glDepthFunc(GL_EQUAL);
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE);
      glBindTextureUnit(1, m.window_surface.get());
      levelmap.set("u_half_v", f.half[1]);
      levelmap.set("u_texels_per_metre", glm::vec2(static_cast<float>(m.caustics_size) / (2 * f.half[0]),
                                                   static_cast<float>(m.caustics_size) / (2 * f.half[2])));
      geometry_then_draw(levelmap, 0);
      glDisable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      glDepthMask(GL_TRUE);
      glNamedFramebufferTexture(m.fbo.get(), GL_DEPTH_ATTACHMENT, 0, 0);
    } else {
      // §5.2.1: per sample plane, the receiver's slice image, then the
      // plane's intersection triangles times that slice, then combine.
      const std::vector<ReferencePlane>& planes = *m.cpu_planes;  // uniform: planned on the CPU
      const auto nplanes = static_cast<std::uint32_t>(planes.size());
      ensure_slices(m, nplanes, m.caustics_size);
      glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
      glViewport(0, 0, size, size);
      for (std::uint32_t i = 0; i < nplanes; ++i) {
        std::optional<gl::TimedPass> timed_slice;
        timed_slice.emplace("level maps: slices (volumetric)", gl::PassKind::kRaster);
        glNamedFramebufferTextureLayer(m.fbo.get(), GL_COLOR_ATTACHMENT0, m.slices.get(), 0, static_cast<GLint>(i));
        glClearNamedFramebufferfv(m.fbo.get(), GL_COLOR, 0, zero);
        glDisable(GL_BLEND);
        slab.use();
        set_frame(slab, f);
        slab.set("u_write_depth", 0);
        slab.set("u_near", planes[i].offset + planes[i].epsilon);
        slab.set("u_far", planes[i].offset - planes[i].epsilon);
        slab.set("u_model", model_of(m.lm->object));
        draw_object(m.lm->object);
        timed_slice.reset();

        glNamedFramebufferTextureLayer(m.fbo.get(), GL_COLOR_ATTACHMENT0, m.illumination.get(), 0, static_cast<GLint>(i));
        glClearNamedFramebufferfv(m.fbo.get(), GL_COLOR, 0, zero);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        volumetric.set("u_slice", static_cast<int>(i));
        glBindTextureUnit(0, m.slices.get());
        geometry_then_draw(volumetric, static_cast<int>(i));
      }
      glNamedFramebufferTexture(m.fbo.get(), GL_COLOR_ATTACHMENT0, m.caustics.get(), 0);
      glDisable(GL_BLEND);
      const gl::TimedPass timed("level maps: combine (volumetric)", gl::PassKind::kRaster);
      combine.use();
      combine.set("u_count", static_cast<int>(nplanes));
      glBindTextureUnit(0, m.slices.get());
      glBindTextureUnit(1, m.illumination.get());
      glBindVertexArray(empty_vao.get());
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glDisable(GL_BLEND);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glBindVertexArray(0);
    stats.volumes_total += water->triangle_count();
  }
  // Whether a light's level maps are drawn in batches (draw_batch): the
  // pair methods, one wavelength, and a driver that can choose a layer
  // from the vertex shader.
  bool batching(const CausticsOptions& o, bool spectral) const {
    const bool wanted = o.map_batching == MapBatching::kAlways || (o.map_batching == MapBatching::kAuto && !software);
    return wanted && layered && !spectral && (o.method == CausticsMethod::kLevelMap || o.method == CausticsMethod::kUniform);
  }

  // The maps `which` of batch `key` (one wavelength) in a fixed number of
  // calls, whatever their number: draw_map's passes, each map in its
  // layer (caustics_batch.glsl). The windows pass clears the drawn maps'
  // texels as it goes, so that those of the batch this update keeps are
  // untouched, and writes their presence (make_mips follows). As drawn
  // alone, the pass does not run again while its inputs hold: when every
  // map of the batch is drawn in this update (`whole`: those in `which`
  // and any without planes, which draw_map clears) and each keeps its
  // windows, one clear of the arrays' irradiance (not the presence in
  // alpha) takes its place.
  void draw_batch(const BatchKey& key, const std::vector<std::size_t>& which, const CausticsOptions& o, bool whole) {
    Batch& b = batches.at(key);
    const std::uint32_t side = std::get<1>(key);
    const auto size = static_cast<GLsizei>(side);
    const PositionArrays& positions = position_arrays.at({std::get<0>(key), std::get<2>(key)});
    batch_info.resize(which.size());
    for (std::size_t k = 0; k < which.size(); ++k) {
      MapGpu& m = maps[which[k]];
      if (m.window_depth.get()) release_windows(m);  // drawn alone last: its batch's layer serves, made again
      const BoundingFrame& f = m.lm->frame;
      const auto [scale, samples] = texel_sampling(m);
      // As draw_map: the cull widens footprints by a caustics texel where
      // it is coarser than the position map's.
      const glm::vec2 texel = glm::vec2(2.0f * f.half[0], 2.0f * f.half[2]) / static_cast<float>(side);
      BatchMap& d = batch_info[k];
      d.origin = glm::vec4(static_cast<float>(f.origin[0]), static_cast<float>(f.origin[1]), static_cast<float>(f.origin[2]),
                           static_cast<float>(side));
      d.u = glm::vec4(v3(f.u), scale);
      d.v = glm::vec4(v3(f.v), 0.0f);
      d.w = glm::vec4(v3(f.w), 0.0f);
      d.half_size = glm::vec4(v3(f.half), 0.0f);
      d.texel = glm::vec4(side < m.lm->map_size ? texel : glm::vec2(0.0f), 1.0f / texel);
      d.ints = glm::uvec4(m.layer, static_cast<std::uint32_t>(m.planes_offset / 4), static_cast<std::uint32_t>(samples), m.position_layer);
    }
    bool fresh = false;  // the windows' textures or flags are new
    if (b.maps_capacity < b.members.size()) {
      fresh = true;
      b.maps_capacity = b.members.size();
      b.command = gl::make_buffer();
      glNamedBufferStorage(b.command.get(), kBatchCounts + static_cast<GLsizeiptr>(b.maps_capacity) * kBatchBytesPerMap, nullptr, 0);
      b.maps = gl::make_buffer();
      glNamedBufferStorage(b.maps.get(), static_cast<GLsizeiptr>(b.maps_capacity * sizeof(BatchMap)), nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    if (!b.window_depth.get()) {
      fresh = true;
      b.window_depth = gl::make_texture(GL_TEXTURE_2D_ARRAY);
      glTextureStorage3D(b.window_depth.get(), 1, GL_DEPTH_COMPONENT16, size, size, static_cast<GLsizei>(b.members.size()));
      b.window_surface = gl::make_texture(GL_TEXTURE_2D_ARRAY);
      glTextureStorage3D(b.window_surface.get(), 1, GL_R16, size, size, static_cast<GLsizei>(b.members.size()));
      b.fbo = gl::make_framebuffer();
      glNamedFramebufferTexture(b.fbo.get(), GL_COLOR_ATTACHMENT0, b.caustics.get(), 0);
      glNamedFramebufferTexture(b.fbo.get(), GL_DEPTH_ATTACHMENT, b.window_depth.get(), 0);
      for (const std::size_t j : b.members) maps[j].batched = true;
    }
    if (fresh) {
      for (const std::size_t j : b.members) maps[j].windows_made.reset();
    }
    bool keep_windows = whole;
    for (const std::size_t i : which) keep_windows = keep_windows && maps[i].windows_made == windows_key(maps[i]);
    const auto batch_maps = static_cast<unsigned>(b.maps_capacity);
    const auto upload = [&] {
      glNamedBufferSubData(b.maps.get(), 0, static_cast<GLsizeiptr>(which.size() * sizeof(BatchMap)), batch_info.data());
    };
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, b.maps.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, flux.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, b.command.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, all_planes.get());
    const GLintptr counts_bytes = static_cast<GLintptr>(which.size()) * kBatchCountBytes;
    const auto clear_counts = [&] {
      glClearNamedBufferSubData(b.command.get(), GL_R32UI, kBatchCounts, counts_bytes, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    };
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // the shared list may still feed the last draw
    clear_counts();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, b.command.get());
    const auto cull_dispatch = [&](std::size_t first) {
      return kBatchCounts + static_cast<GLintptr>(first) * kBatchCountBytes + kBatchCullDispatch;
    };
    const auto fixup_run = [&](int stage, std::size_t first, std::size_t count) {
      fixup_batch.use();
      fixup_batch.set("u_stage", stage);
      fixup_batch.set("u_map_base", static_cast<unsigned>(first));
      fixup_batch.set("u_count", static_cast<unsigned>(count));
      fixup_batch.set("u_batch_maps", batch_maps);
      glDispatchCompute((static_cast<GLuint>(count) + 63) / 64, 1, 1);
    };
    auto cull_run = [&](std::size_t first, std::size_t count) {
      if (o.cull) {
        // As many groups as the run's largest water rectangle needs
        // (caustics_batch_fixup.comp), not the grid's for every map.
        fixup_run(0, first, count);
        glMemoryBarrier(GL_COMMAND_BARRIER_BIT);
      }
      cull_batch.use();
      cull_batch.set("u_triangles", water->triangle_count());
      cull_batch.set("u_frame_cull", o.cull ? 1 : 0);
      cull_batch.set("u_plane_cull", o.cull ? 1 : 0);
      cull_batch.set("u_pairs", 1);
      cull_batch.set("u_map_base", static_cast<unsigned>(first));
      cull_batch.set("u_batch_maps", batch_maps);
      cull_batch.set("u_rect", o.cull ? 0 : -1);
      glBindTextureUnit(0, positions.tiles.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, list.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, primitives.get());
      if (o.cull) {
        glDispatchComputeIndirect(cull_dispatch(first));
      } else {
        glDispatchCompute((water->triangle_count() + 63) / 64, static_cast<GLuint>(count), 1);
      }
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    };

    // 1. The first time a map is drawn with a plan (the warm-up) every
    // map's need is counted at once (a cull with no room, which lists
    // nothing) and read back, as draw_map measures a map's.
    const ListKey list_key{true, o.cull, o.method == CausticsMethod::kLevelMap, o.planes.value_or(0), o.epsilon.value_or(0.0f), side};
    bool measure = false;
    for (const std::size_t i : which) measure = measure || maps[i].measured != list_key;
    if (measure) {
      const gl::TimedPass timed("level maps: cull", gl::PassKind::kCompute);
      ensure_list();  // the lists exist before they are bound
      for (std::size_t k = 0; k < which.size(); ++k) batch_info[k].list = glm::uvec4(0, 0, static_cast<std::uint32_t>(which[k]), 0);
      upload();
      cull_run(0, which.size());
      std::vector<std::uint32_t> counts(static_cast<std::size_t>(counts_bytes / 4));
      glGetNamedBufferSubData(b.command.get(), kBatchCounts, counts_bytes, counts.data());  // warm-up only
      for (std::size_t k = 0; k < which.size(); ++k) {
        MapGpu& m = maps[which[k]];
        m.capacity = std::clamp<std::uint64_t>(static_cast<std::uint64_t>(std::ceil(counts[k * kBatchCountBytes / 4] * kHeadroom)),
                                               kMinCapacity, kMaxPrimitives);
        m.measured = list_key;
        ++generation[which[k]];
      }
      clear_counts();
    }
    ensure_list();
    // Runs of maps whose parts fit the shared list together (as large as
    // the largest map's: a batch holds no more list than map by map), each
    // map's part after the last's.
    batch_runs.clear();
    for (std::size_t k = 0; k < which.size();) {
      const std::size_t first = k;
      std::uint64_t at = 0;
      while (k < which.size() && (k == first || at + maps[which[k]].capacity <= allocated)) {
        batch_info[k].list = glm::uvec4(static_cast<std::uint32_t>(at), static_cast<std::uint32_t>(maps[which[k]].capacity),
                                        static_cast<std::uint32_t>(which[k]), 0);
        at += maps[which[k]].capacity;
        ++k;
      }
      batch_runs.emplace_back(first, k);
    }
    upload();

    // 2. Per run, in a fixed number of calls: cull, fix-up, windows (and
    // presence), geometry, draw.
    glBindFramebuffer(GL_FRAMEBUFFER, b.fbo.get());
    glViewport(0, 0, size, size);
    if (keep_windows) {
      // Every layer's irradiance, the presence kept: the windows pass,
      // which would clear the maps one by one, does not run.
      const float zero[4] = {0, 0, 0, 0};
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
      glClearNamedFramebufferfv(b.fbo.get(), GL_COLOR, 0, zero);
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
    glDisable(GL_CULL_FACE);
    glBindVertexArray(empty_vao.get());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, b.command.get());
    for (const auto& [first, end] : batch_runs) {
      const auto count = static_cast<GLsizei>(end - first);
      std::uint64_t widest = 0;
      for (std::size_t k = first; k < end; ++k) widest = std::max(widest, maps[which[k]].capacity);
      {
        const gl::TimedPass timed("level maps: cull", gl::PassKind::kCompute);
        cull_run(first, end - first);
        // Each map's count becomes its draw (caustics_batch_fixup.comp).
        fixup_run(1, first, end - first);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
      }
      glBindTextureUnit(0, positions.positions.get());
      if (keep_windows) {
        glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_EQUAL);
      } else {
        // 3a. Each texel's window into the layers' depth, and the drawn
        // maps' irradiance cleared (caustics_windows.frag).
        const gl::TimedPass timed("level maps: windows", gl::PassKind::kRaster);
        glDisable(GL_BLEND);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_ALWAYS);
        glDepthMask(GL_TRUE);
        windows_batch.use();
        windows_batch.set("u_map_base", static_cast<unsigned>(first));
        windows_batch.set("u_batch_maps", batch_maps);
        glBindImageTexture(0, b.window_surface.get(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R16);
        glDrawArraysInstanced(GL_TRIANGLES, 0, 3, count);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_EQUAL);
        for (std::size_t k = first; k < end; ++k) maps[which[k]].windows_made = windows_key(maps[which[k]]);
      }
      // 3. Geometry of every listed primitive, then 4. one rectangle each
      // in its map's layer, map after map.
      {
        const gl::TimedPass timed("level maps: geometry", gl::PassKind::kCompute);
        geometry_batch.use();
        geometry_batch.set("u_pairs", 1);
        geometry_batch.set("u_max_magnification", o.max_magnification);
        geometry_batch.set("u_smooth", o.water_smooth ? 1 : 0);
        geometry_batch.set("u_map_base", static_cast<unsigned>(first));
        geometry_batch.set("u_batch_maps", batch_maps);
        glProgramUniform2ui(geometry_batch.id(), geometry_batch.loc("u_grid"), water->water().cells[0] + 1, water->water().cells[1] + 1);
        glDispatchCompute(static_cast<GLuint>(std::min<std::uint64_t>((widest + 63) / 64, 65535)), static_cast<GLuint>(count), 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      }
      {
        const gl::TimedPass timed("level maps: draw", gl::PassKind::kRaster);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        levelmap_batch.use();
        glBindTextureUnit(1, b.window_surface.get());
        const auto offset = static_cast<std::uintptr_t>(kBatchCounts + b.maps_capacity * kBatchCountBytes + first * kBatchDrawBytes);
        glMultiDrawArraysIndirect(GL_TRIANGLES, reinterpret_cast<const void*>(offset), count, 0);
        glDisable(GL_BLEND);
        glDisable(GL_DEPTH_TEST);
      }
      for (std::size_t k = first; k < end; ++k) {
        read_counters_later(which[k], b.command.get(), kBatchCounts + static_cast<GLintptr>(k) * kBatchCountBytes);
      }
    }
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glBindVertexArray(0);
    stats.volumes_total += std::uint64_t{water->triangle_count()} * which.size();
  }
};

CausticsEngine::~CausticsEngine() = default;

Status CausticsEngine::check(const CausticsOptions& o) {
  if (o.map_size < 1 || o.map_size > kMaxRuntimeMapSize) {
    return make_error(ErrorCode::kUsage, "caustics options: map_size must be 1.." + std::to_string(kMaxRuntimeMapSize) + ", got " +
                                             std::to_string(o.map_size));
  }
  if (!(std::isfinite(o.texel_size) && o.texel_size >= 0.0f)) {
    return make_error(ErrorCode::kUsage, "caustics options: texel_size must be 0 (from map_size) or a finite length in metres");
  }
  return Status::success();
}

Result<std::unique_ptr<CausticsEngine>> CausticsEngine::create(std::vector<LevelMap>& maps, const WaterSurface& water,
                                                               std::function<void(std::uint32_t)> draw_object,
                                                               std::function<glm::mat4(std::uint32_t)> model_of) {
  std::unique_ptr<CausticsEngine> e(new CausticsEngine());
  e->impl_ = std::make_unique<Impl>();
  Impl& s = *e->impl_;
  s.water = &water;
  s.draw_object = std::move(draw_object);
  s.model_of = std::move(model_of);
  const std::string coverage = std::string("#version 450 core\n") + shaders::k_caustics_coverage_glsl;
  // The passes that read a position map decode it (position_code.glsl).
  const std::string code = shaders::k_position_code_glsl;
  const std::string splat_fs = with_optics((code + shaders::k_splat_photon_frag_glsl).c_str());
  const std::string levelmap_vs =
      insert_after_version(shaders::k_caustics_intersect_vert_glsl, "#define DEPTH_SHIFT\n#define WINDOW_DEPTH\n");
  const std::string levelmap_fs = coverage + code + shaders::k_caustics_levelmap_frag_glsl;
  const std::string windows_fs =
      std::string("#version 450 core\n") + code + shaders::k_caustics_windows_glsl + shaders::k_caustics_windows_frag_glsl;
  const std::string presence_fs = insert_after_version(shaders::k_caustics_presence_frag_glsl, code);
  const std::string profile_src = std::string("#version 450 core\n") + code + shaders::k_profile_comp_glsl;
  const std::string slab_fs = std::string("#version 450 core\n") + code + shaders::k_slab_frag_glsl;
  const std::string volumetric_fs = coverage + shaders::k_caustics_volumetric_frag_glsl;
  const std::string prepare_src = with_optics(shaders::k_caustics_prepare_comp_glsl);
  const std::string cull_src = insert_after_version(shaders::k_caustics_cull_comp_glsl, shaders::k_caustics_windows_glsl);
  const std::string geometry_src = insert_after_version(shaders::k_caustics_geometry_comp_glsl, shaders::k_caustics_windows_glsl);
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs(
      {{&s.levelmap, "caustics_levelmap", levelmap_vs.c_str(), levelmap_fs.c_str()},
       {&s.windows, "caustics_windows", shaders::k_fullscreen_vert_glsl, windows_fs.c_str()},
       {&s.volumetric, "caustics_volumetric", shaders::k_caustics_intersect_vert_glsl, volumetric_fs.c_str()},
       {&s.slab, "slab", shaders::k_slab_vert_glsl, slab_fs.c_str()},
       {&s.splat_photon, "splat_photon", shaders::k_water_vert_glsl, splat_fs.c_str()},
       {&s.splat_points, "splat_points", shaders::k_splat_points_vert_glsl, shaders::k_splat_points_frag_glsl},
       {&s.combine, "volumetric_combine", shaders::k_fullscreen_vert_glsl, shaders::k_volumetric_combine_frag_glsl},
       {&s.presence, "caustics_presence", shaders::k_fullscreen_vert_glsl, presence_fs.c_str()},
       {&s.prepare, "caustics_prepare", prepare_src.c_str()},
       {&s.cull, "caustics_cull", cull_src.c_str()},
       {&s.fixup, "caustics_fixup", shaders::k_caustics_fixup_comp_glsl},
       {&s.geometry, "caustics_geometry", geometry_src.c_str()},
       {&s.profile, "profile", profile_src.c_str()},
       {&s.accumulate, "caustics_accumulate", shaders::k_caustics_accumulate_comp_glsl},
       {&s.plan, "caustics_plan", shaders::k_caustics_plan_comp_glsl},
       {&s.rects, "caustics_rects", shaders::k_caustics_rects_comp_glsl}}));
  // The batches' passes (draw_batch): the same shaders, each map read
  // from the batch's buffer and drawn into its layer.
  s.layered = epoxy_has_gl_extension("GL_ARB_shader_viewport_layer_array");
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const std::string name = renderer ? renderer : "";
  s.software = name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos ||
               name.find("SWR") != std::string::npos || name.find("swrast") != std::string::npos;
  if (s.layered) {
    const std::string batch = std::string("#define BATCH\n") + shaders::k_caustics_batch_glsl;
    const std::string layer_vs = "#extension GL_ARB_shader_viewport_layer_array : require\n" + batch;
    const std::string cull_batch = insert_after_version(shaders::k_caustics_cull_comp_glsl, batch + shaders::k_caustics_windows_glsl);
    const std::string geometry_batch =
        insert_after_version(shaders::k_caustics_geometry_comp_glsl, batch + shaders::k_caustics_windows_glsl);
    const std::string levelmap_batch_vs =
        insert_after_version(shaders::k_caustics_intersect_vert_glsl, layer_vs + "#define DEPTH_SHIFT\n#define WINDOW_DEPTH\n");
    const std::string levelmap_batch_fs = std::string("#version 450 core\n") + batch + shaders::k_caustics_coverage_glsl + code +
                                          shaders::k_caustics_levelmap_frag_glsl;
    const std::string quad_vs = std::string("#version 450 core\n") + layer_vs + shaders::k_caustics_batch_vert_glsl;
    const std::string windows_batch_fs =
        std::string("#version 450 core\n") + batch + code + shaders::k_caustics_windows_glsl + shaders::k_caustics_windows_frag_glsl;
    const std::string fixup_batch = insert_after_version(shaders::k_caustics_batch_fixup_comp_glsl, batch);
    CAUSTIX_RETURN_IF_ERROR(gl::build_programs(
        {{&s.levelmap_batch, "caustics_levelmap (batch)", levelmap_batch_vs.c_str(), levelmap_batch_fs.c_str()},
         {&s.windows_batch, "caustics_windows (batch)", quad_vs.c_str(), windows_batch_fs.c_str()},
         {&s.cull_batch, "caustics_cull (batch)", cull_batch.c_str()},
         {&s.fixup_batch, "caustics_batch_fixup", fixup_batch.c_str()},
         {&s.geometry_batch, "caustics_geometry (batch)", geometry_batch.c_str()}}));
  }
  s.empty_vao = gl::make_vertex_array();
  s.black = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(s.black.get(), 1, GL_RGBA32F, 1, 1);
  const float none[4] = {0, 0, 0, 0};
  glClearTexImage(s.black.get(), 0, GL_RGBA, GL_FLOAT, none);

  s.refracted = gl::make_buffer();
  glNamedBufferStorage(s.refracted.get(), GLsizeiptr{16} * water.vertex_count(), nullptr, 0);
  s.flux = gl::make_buffer();
  glNamedBufferStorage(s.flux.get(), GLsizeiptr{8} * water.triangle_count(), nullptr, 0);

  // Every map's planes in one buffer, and the position maps and depth
  // tiles of each light and size in one array each, a map to a layer.
  GLint alignment = 256;
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &alignment);
  alignment = std::max(alignment, 4);
  s.planes_stride = (kPlanesBytes + alignment - 1) / alignment * alignment;
  s.all_planes = gl::make_buffer();
  glNamedBufferStorage(s.all_planes.get(), s.planes_stride * static_cast<GLsizeiptr>(std::max<std::size_t>(maps.size(), 1)), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  s.maps.resize(maps.size());
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> layers;
  for (std::size_t i = 0; i < maps.size(); ++i) s.maps[i].position_layer = layers[{maps[i].light, maps[i].map_size}]++;
  const gl::ClientUnpack unpack(2);  // the codes' rows: 2 bytes a texel, packed (odd sides too)
  for (const auto& [key, count] : layers) {
    const auto ps = static_cast<GLsizei>(key.second), nt = static_cast<GLsizei>((key.second + kTileTexels - 1) / kTileTexels);
    Impl::PositionArrays& a = s.position_arrays[key];
    a.positions = gl::make_texture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(a.positions.get(), 1, GL_R16, ps, ps, static_cast<GLsizei>(count));
    gl::set_sampling(a.positions.get(), GL_NEAREST);
    a.tiles = gl::make_texture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(a.tiles.get(), 1, GL_RG32F, nt, nt, static_cast<GLsizei>(count));
    gl::set_sampling(a.tiles.get(), GL_NEAREST);
  }
  for (std::size_t i = 0; i < maps.size(); ++i) {
    MapGpu& m = s.maps[i];
    LevelMap& lm = maps[i];
    m.lm = &lm;
    m.planes_offset = s.planes_stride * static_cast<GLintptr>(i);
    // Position map: the baked 16-bit codes of frame V as they are
    // (position_code.glsl decodes them).
    const Impl::PositionArrays& a = s.position_arrays.at({lm.light, lm.map_size});
    m.position_map = gl::make_view(GL_TEXTURE_2D, a.positions.get(), GL_R16, 0, 1, m.position_layer, 1);
    m.depth_tiles = gl::make_view(GL_TEXTURE_2D, a.tiles.get(), GL_RG32F, 0, 1, m.position_layer, 1);
    const auto ps = static_cast<GLsizei>(lm.map_size);
    glTextureSubImage2D(m.position_map.get(), 0, 0, 0, ps, ps, GL_RED, GL_UNSIGNED_SHORT, lm.depth.data());
    gl::set_sampling(m.position_map.get(), GL_NEAREST);
    s.build_depth_tiles(m);
    m.command = gl::make_buffer();
    glNamedBufferStorage(m.command.get(), kCommandBytes, nullptr, 0);
    // The baked profile, for the GPU's planning after a re-derivation.
    m.histogram = gl::make_buffer();
    glNamedBufferStorage(m.histogram.get(), GLsizeiptr{4} * static_cast<GLsizeiptr>(std::max<std::size_t>(lm.histogram.size(), 1)),
                         lm.histogram.empty() ? nullptr : lm.histogram.data(), 0);
    const double h = 2.0 * lm.frame.half[1];
    m.default_epsilon = std::fabs(lm.epsilon - h / (2.0 * lm.planes_requested)) < 1e-6 * h;
  }
  s.generation.assign(s.maps.size(), 0);
  std::uint32_t lights = 0;
  for (const LevelMap& lm : maps) lights = std::max(lights, lm.light + 1);
  s.made.resize(lights);
  s.positions_made.assign(lights, 0);
  s.readback.reserve(kCounterBytes * s.maps.size());
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("caustics set-up"));
  return e;
}

void CausticsEngine::rederive(std::optional<std::uint32_t> light, std::optional<std::uint32_t> object) {
  for (MapGpu& m : impl_->maps) {
    if ((light && m.lm->light != *light) || (object && m.lm->object != *object)) continue;
    m.rederive = true;
  }
}

void CausticsEngine::Impl::rederive_map(MapGpu& m, const std::vector<Light>& lights, const std::optional<Water>& water,
                                        const std::vector<std::vector<std::array<double, 3>>>& world) {
  Impl& s = *this;
  m.rederive = false;
  ++s.positions_made[m.lm->light];
  {
    LevelMap& lm = *m.lm;
    const Light& desc = lights[lm.light];
    const auto& pts = world[lm.object];
    double min_y = pts[0][1], max_y = min_y;
    for (const auto& p : pts) {
      min_y = std::min(min_y, p[1]);
      max_y = std::max(max_y, p[1]);
    }
    const glm::mat4 model = s.model_of(lm.object);
    const Vec3d origin{model[3][0], model[3][1], model[3][2]};
    std::string why;
    const auto dir = light_direction(desc, water, origin, min_y, max_y, &why);
    m.unlit = !dir;
    if (!dir) {
      // The light no longer reaches it through the water: an empty map.
      glClearTexImage(m.position_map.get(), 0, GL_RED, GL_UNSIGNED_SHORT, &kEmptyDepth);
      const float empty[2] = {1e30f, -1e30f};
      glClearTexImage(m.depth_tiles.get(), 0, GL_RG, GL_FLOAT, empty);
      return;
    }
    lm.frame = make_frame(dir->travel, pts, origin);
    const BoundingFrame& f = lm.frame;

    // Position map: the receiver seen along -V, nearest surface to the light wins.
    const auto size = static_cast<GLsizei>(lm.map_size);
    if (!m.position_fbo.get()) {
      m.position_fbo = gl::make_framebuffer();
      glNamedFramebufferTexture(m.position_fbo.get(), GL_COLOR_ATTACHMENT0, m.position_map.get(), 0);
    }
    // One depth buffer for every map's re-derivation, as large as the
    // largest position map (a map's own made every moving light's maps
    // hold one more position map's bytes each).
    if (s.position_depth_size < lm.map_size || !s.position_depth.get()) {
      s.position_depth = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(s.position_depth.get(), 1, GL_DEPTH_COMPONENT32F, size, size);
      s.position_depth_size = lm.map_size;
    }
    glNamedFramebufferTexture(m.position_fbo.get(), GL_DEPTH_ATTACHMENT, s.position_depth.get(), 0);
    std::optional<gl::TimedPass> timed_position;
    timed_position.emplace("level maps: position maps", gl::PassKind::kRaster);
    glBindFramebuffer(GL_FRAMEBUFFER, m.position_fbo.get());
    glViewport(0, 0, size, size);
    const float empty[4] = {1, 0, 0, 0};  // kEmptyDepth's code
    glClearNamedFramebufferfv(m.position_fbo.get(), GL_COLOR, 0, empty);
    const float far_depth = 1.0f;
    glClearNamedFramebufferfv(m.position_fbo.get(), GL_DEPTH, 0, &far_depth);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    s.slab.use();
    set_frame(s.slab, f);
    s.slab.set("u_write_depth", 1);
    s.slab.set("u_half_v", f.half[1]);
    s.slab.set("u_near", f.half[1] * 1.0001f);
    s.slab.set("u_far", -f.half[1] * 1.0001f);
    s.slab.set("u_model", model);
    s.draw_object(lm.object);

    // The histogram over the depth levels (fig. 4-19) stays on the GPU: the
    // next update plans the planes from it there (caustics_plan.comp).
    timed_position.reset();
    const gl::TimedPass timed_profile("level maps: depth profiles", gl::PassKind::kCompute);
    const auto levels = static_cast<std::uint32_t>(lm.histogram.size());
    glClearNamedBufferData(m.histogram.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    s.profile.use();
    s.profile.set("u_mode", 0);
    s.profile.set("u_levels", levels);
    s.profile.set("u_half_v", f.half[1]);
    glBindTextureUnit(0, m.position_map.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, m.histogram.get());
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    glDispatchCompute((lm.map_size + 7) / 8, (lm.map_size + 7) / 8, 1);
    s.build_depth_tiles(m);
    m.profile = ++s.profiles;
  }
  glDepthMask(GL_TRUE);
}

Status CausticsEngine::update_light(std::uint32_t light, const std::vector<Light>& lights, const std::optional<Water>& scene_water,
                                    const std::vector<std::vector<std::array<double, 3>>>& world, const CausticsOptions& o,
                                    const SceneVersions& versions, bool due, EffectWork& work) {
  Impl& s = *impl_;
  bool any = false;
  for (const MapGpu& m : s.maps) any = any || m.lm->light == light;
  if (!any || o.method == CausticsMethod::kNone) return Status::success();
  const LightInputs key{versions, o};
  // A map kept while out of view is remade once in view, even where
  // nothing else changed since (then only such maps are drawn).
  const bool remake = s.made.decide(light, key, due, work) == Refresh::kRemake;
  bool catch_up = false;
  for (const MapGpu& m : s.maps) catch_up = catch_up || (m.lm->light == light && m.stale && !s.hidden(m));
  if (!remake && !(catch_up && due)) return Status::success();
  s.made.made(light, key);
  if (!s.counted_this_frame) s.stats = CausticsStats{};  // the counts describe the last frame that drew
  s.counted_this_frame = true;
  const Light& desc = lights[light];
  std::vector<bool>& moved = s.moved;  // re-derived now: its old map lies in the old frame
  moved.assign(s.maps.size(), false);
  for (std::size_t i = 0; i < s.maps.size(); ++i) {
    MapGpu& m = s.maps[i];
    if (m.lm->light != light || !m.rederive) continue;
    moved[i] = true;
    s.rederive_map(m, lights, scene_water, world);
  }
  s.plan_texels(o, lights);
  for (MapGpu& m : s.maps) {
    if (m.lm->light == light && m.planned_side == 0) Impl::release_textures(m);
  }
  // Which maps this update draws: a remake draws every map but those out
  // of view that keep what they have (a map of the size planned, not
  // re-derived), each of those remade on one update in
  // out_of_view_interval, map i on the updates k with (k + i) mod N = 0,
  // so that their cost is spread over the updates rather than paid at
  // once; a catch-up draws only the stale maps now in view.
  std::vector<bool>& draws = s.draws;
  draws.assign(s.maps.size(), false);
  for (std::size_t i = 0; i < s.maps.size(); ++i) {
    MapGpu& m = s.maps[i];
    if (m.lm->light != light || m.planned_side == 0) continue;
    const bool keeps = m.caustics.get() && m.caustics_size == m.planned_side && !moved[i];
    if (!remake) {
      draws[i] = m.stale && !s.hidden(m);
    } else if (keeps && s.hidden(m) && (s.frame + i) % s.out_of_view_interval != 0) {
      m.stale = true;
      ++s.maps_out_of_view;
    } else {
      draws[i] = true;
    }
    if (draws[i]) m.stale = false;
  }
  s.arrange(light, draws);

  // Per traced wavelength (one, at n_d or wavelength_nm, unless the water
  // disperses): refract at every water vertex, then each
  // triangle's flux (eq. 2-8, 4-18), then every map of this light; photon
  // splatting refracts per photon instead. Several wavelengths add up in
  // each map's spectral sums (accumulate_wavelength).
  const Water& water = s.water->water();
  const std::vector<WavelengthSample> samples = water_wavelengths(water, o);
  const bool spectral = samples.size() > 1;
  const bool splat = o.method == CausticsMethod::kSplat;
  const bool batch = s.batching(o, spectral);
  CausticsStats counted;  // after the first wavelength: the counters count one pass
  // Nothing to draw (every map kept out of view): not even the water's pass.
  const bool drawing = std::any_of(draws.begin(), draws.end(), [](bool d) { return d; });
  for (std::size_t k = 0; drawing && k < samples.size(); ++k) {
    // One wavelength and no wavelength_nm: exactly n_d (KHR's 1.5168 is
    // 523655 / 587.56^2 to 4 places only).
    const float ior = spectral || o.wavelength_nm ? index_at(water.ior, water.dispersion, samples[k].nm) : water.ior;
    s.water->bind_buffers();
    if (!splat) {
      const gl::TimedPass timed("level maps: refract at the water", gl::PassKind::kCompute);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, s.refracted.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, s.flux.get());
      s.prepare.use();
      s.set_light(s.prepare, desc, ior);
      s.ensure_rects();
      const std::uint32_t unset = 0xffffffffu;
      glClearNamedBufferSubData(s.cull_rects.get(), GL_R32UI, 0, kRectsHeader, GL_RED_INTEGER, GL_UNSIGNED_INT, &unset);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, s.cull_rects.get());
      s.prepare.set("u_mode", 0);
      s.prepare.set("u_count", s.water->vertex_count());
      glDispatchCompute((s.water->vertex_count() + 63) / 64, 1, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      s.prepare.set("u_mode", 1);
      s.prepare.set("u_count", s.water->triangle_count());
      glDispatchCompute((s.water->triangle_count() + 63) / 64, 1, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      s.stats.water_triangles = s.water->triangle_count();
    }
    if (!splat && o.cull) s.make_rects();
    // A light's maps in batches (draw_batch, finished there), but for a
    // map without planes, which draw_map clears, and the maps of a batch
    // drawn now when they are fewer than kBatchMinMaps; or map by map.
    for (auto& [batch_key, b] : s.batches) {
      if (!batch || std::get<0>(batch_key) != light) continue;
      s.batch_drawn.clear();
      for (const std::size_t i : b.members) {
        MapGpu& m = s.maps[i];
        if (!draws[i]) continue;
        s.plan_planes(m, o);
        if (m.cpu_planes && m.cpu_planes->empty()) {
          s.draw_map(m, o, desc, ior);
          s.finish_map(m, o);
        } else {
          s.batch_drawn.push_back(i);
        }
      }
      if (s.batch_drawn.empty()) continue;  // every map kept: no pass, no window depth
      if (o.map_batching == MapBatching::kAlways || s.batch_drawn.size() >= kBatchMinMaps) {
        const bool whole = std::all_of(b.members.begin(), b.members.end(), [&](std::size_t i) { return draws[i]; });
        s.draw_batch(batch_key, s.batch_drawn, o, whole);
        continue;
      }
      for (const std::size_t i : s.batch_drawn) {
        s.draw_map(s.maps[i], o, desc, ior);
        s.read_counters_later(i, s.maps[i].command.get(), 32);
        s.finish_map(s.maps[i], o);
      }
    }
    for (std::size_t i = 0; i < s.maps.size() && !batch; ++i) {
      MapGpu& m = s.maps[i];
      if (!draws[i]) continue;
      s.draw_map(m, o, desc, ior);
      if (!splat && k == 0) s.read_counters_later(i, m.command.get(), 32);  // one wavelength's; splatting fills no culling counters
      if (spectral) s.accumulate_wavelength(m, samples[k], k == 0, k + 1 == samples.size());
    }
    if (k == 0) counted = s.stats;
  }
  if (drawing) s.stats = counted;
  for (std::size_t i = 0; i < s.maps.size(); ++i) {
    MapGpu& m = s.maps[i];
    if (m.lm->light != light) continue;
    if (draws[i]) {
      m.spectral = spectral;
      if (!batch) s.finish_map(m, o);
    }
    m.gpu_bytes = Impl::bytes_of(m);
  }
  s.make_mips(light, draws);
  s.stats.wavelengths = static_cast<std::uint32_t>(samples.size());
  return gl::check_gl("caustics pass");
}

std::optional<CausticsEngine::Binding> CausticsEngine::binding(std::uint32_t object, std::uint32_t light) const {
  for (const MapGpu& m : impl_->maps) {
    if (m.lm->object != object || m.lm->light != light) continue;
    if (m.caustics.get()) return Binding{m.lm, m.caustics.get(), m.spectral ? m.color.get() : 0u, m.position_map.get(), m.self_tolerance};
    if (m.planned) return Binding{m.lm, impl_->black.get(), 0u, m.position_map.get(), m.self_tolerance};
  }
  return std::nullopt;
}

void CausticsEngine::begin_frame(std::uint64_t frame, std::uint64_t other_bytes, const std::vector<bool>* out_of_view,
                                 std::uint32_t out_of_view_interval) {
  Impl& s = *impl_;
  s.out_of_view = out_of_view && !out_of_view->empty() ? *out_of_view : std::vector<bool>{};
  s.out_of_view_interval = std::max(out_of_view_interval, 1u);
  s.maps_out_of_view = 0;
  s.other_bytes = other_bytes;
  s.poll();
  s.frame = frame;
  s.counted_this_frame = false;
}

void CausticsEngine::end_frame() {
  Impl& s = *impl_;
  if (s.slot_open) s.readback.end(s.frame);
  s.slot_open = false;
}

CausticsStats CausticsEngine::stats(bool wait) {
  Impl& s = *impl_;
  if (wait && s.readback.pending()) {
    s.readback.wait();
    s.poll();
  }
  CausticsStats out = s.stats;
  out.maps_out_of_view = s.maps_out_of_view;
  out.gpu_bytes = gpu_bytes();
  out.counters_frame = s.gpu_counts.frame;
  out.volumes_drawn = s.gpu_counts.volumes_drawn;
  out.planes_drawn = s.gpu_counts.planes_drawn;
  out.overflowed = s.gpu_counts.overflowed;
  out.texels = s.texels;
  out.texels.maps = 0;
  out.texels.map_bytes = 0;
  for (const MapGpu& m : s.maps) {
    out.texels.maps += m.caustics.get() ? 1u : 0u;
    out.texels.map_bytes += Impl::texture_bytes(m);
  }
  out.warnings = std::move(s.warnings);
  s.warnings.clear();
  return out;
}

std::uint64_t CausticsEngine::times_made(std::uint32_t light) const { return impl_->made.times_made(light); }

std::uint64_t CausticsEngine::position_maps_made(std::uint32_t light) const {
  return light < impl_->positions_made.size() ? impl_->positions_made[light] : 0;
}

std::uint64_t CausticsEngine::gpu_bytes() const {
  const Impl& s = *impl_;
  std::uint64_t bytes = s.shared_bytes();
  for (const MapGpu& m : s.maps) bytes += m.gpu_bytes;
  return bytes;
}

}  // namespace caustix::runtime
