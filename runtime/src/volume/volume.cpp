#include "volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "caustix_shaders.h"
#include "pass_timer.h"
#include "readback.h"
#include "shader_text.h"
#include "water_surface.h"

namespace caustix::runtime {
namespace {

glm::vec3 to_glm(const Vec3f& v) { return {v[0], v[1], v[2]}; }

struct Box {
  glm::vec3 lo{1e30f}, hi{-1e30f};
  bool empty() const { return !(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z); }
  void add(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
};

// sigma_s (w: Schlick k) and sigma_t (w: phase) as the shaders read them.
struct Coefficients {
  glm::vec4 ss{0.0f}, st{0.0f, 0.0f, 0.0f, 1.0f};
  bool scatters() const { return ss.x > 0 || ss.y > 0 || ss.z > 0; }
  bool any() const { return st.x > 0 || st.y > 0 || st.z > 0; }
};

Coefficients coefficients(const Vec3f& absorption, const Scattering& s) {
  Coefficients c;
  c.ss = glm::vec4(to_glm(s.coefficient), s.phase == Phase::kSchlick ? s.anisotropy : 0.0f);
  c.st = glm::vec4(to_glm(s.coefficient) + to_glm(absorption), s.phase == Phase::kSchlick ? 2.0f : 1.0f);
  return c;
}

float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// The radiance grid spans the whole medium (fog_ball: 4.7 cm
// voxels), and a ball lens puts its light through a focal line a few
// millimetres wide, so the line came out at 0.41 of optics' in-scatter
// and 13 cm too high (the grid's blur keeps the wider cone above the
// focus brighter than the line itself). The focus grid is fitted to where
// the light through glass concentrates, as the glass's focus windows are
// (glass.cpp): the glass's sampled exit rays are followed through the
// radiance grid's cells, and the cells whose fluence from them reaches
// kFocusConcentration times the incident irradiance, from at least
// kFocusMinRays rays, with one cell more on every side, are the box.
constexpr double kFocusConcentration = 16.0;
constexpr int kFocusMinRays = 4;
// Photons per axis over the glass's own square, with a focus grid, for P
// per axis over the light's (update_light). fog_ball: twice the light
// window's density over the glass; P^2 cost 76 % more per frame with the
// light turning (llvmpipe), P/3 gives no more photons than the light's
// window did.
std::uint32_t glass_side(std::uint32_t photons) { return std::max(1u, photons / 2); }

// The glass's photons start on a square across the light through the
// lens's centre, its sides the lens box's half-widths along x and z, turned
// from the horizontal by the least rotation that takes straight down to the
// light's direction n. On a window of fixed height, as the glass's was, a
// light turning by a small angle moved every photon across the lens (the
// window's width grows with the lens's height x the tangent of the light's
// angle: fog_ball's photons by up to 1.7 cells a frame at 0.2 degrees),
// and the few photons bent far sideways by the rim sprang to new paths
// every frame. Over the square a photon keeps its place on the lens as the
// light turns about it: a ball lens's photons all turn with the light. The
// square's size does not depend on the light; where a lens reaches past
// it (a tall lens under a low sun) the light's window keeps those rays.
struct LensSquare {
  glm::vec3 c{0.0f}, u{0.0f}, v{0.0f}, n{0.0f, -1.0f, 0.0f};
};
LensSquare lens_square(const Box& lens, const glm::vec3& n) {
  // The rotation taking e = (0, -1, 0) to n (n.y < 0):
  // R = I + [w]x + [w]x^2 / (1 + e.n), w = e x n.
  const glm::vec3 e(0.0f, -1.0f, 0.0f), w = glm::cross(e, n);
  const float k = 1.0f / (1.0f + glm::dot(e, n));
  const auto rotate = [&](const glm::vec3& a) { return a + glm::cross(w, a) + k * glm::cross(w, glm::cross(w, a)); };
  const glm::vec3 half = 0.5f * (lens.hi - lens.lo);
  return {0.5f * (lens.lo + lens.hi), rotate(glm::vec3(half.x, 0.0f, 0.0f)), rotate(glm::vec3(0.0f, 0.0f, half.z)), n};
}

// Per-cell tallies of focus_box, kept between calls (zero between them):
// a light turning every frame fits a box every frame, and clearing and
// scanning every cell of the radiance grid made it 1.3-2.3 ms of the CPU's
// frame on fog_ball (221 k cells); visiting only the cells the rays
// touched, 0.9-1.2 ms (the rest is the sample's table look-ups and rays).
struct FocusScratch {
  std::vector<double> fluence;
  std::vector<int> count, last;
  std::vector<std::size_t> touched;
};

// The box of the concentrated cells of `grid` (n cells) with one cell more
// on every side, or an empty box; the light turning moves it by whole
// cells, so the box kept from the last update (`kept`) stays while it
// serves: while it holds every concentrated cell and no cell past those
// that reach a quarter of the concentration (with their margin). On fog_ball at
// the fast preset (9.4 cm cells), the box had changed 3 times in 12
// frames of a sun turning 0.2 degrees a frame, from a cell crossing the
// threshold: the focal line, on a cell face under the sun straight down,
// puts its light into one cell or into four as it drifts across.
Box focus_box(const std::vector<ExitRay>& rays, const Box& grid, const glm::ivec3& n, const Box& kept, FocusScratch& t) {
  const glm::vec3 h = (grid.hi - grid.lo) / glm::vec3(n);
  const std::size_t cells = std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z);
  if (t.fluence.size() != cells) t = FocusScratch{std::vector<double>(cells, 0.0), std::vector<int>(cells, 0), std::vector<int>(cells, -1), {}};
  const float step = 0.25f * std::min({h.x, h.y, h.z});
  for (std::size_t ri = 0; ri < rays.size(); ++ri) {
    const ExitRay& r = rays[ri];
    if (!(r.flux > 0.0f)) continue;
    // The part of the ray inside the grid (slab test).
    float t0 = 0.0f, t1 = 1e30f;
    for (int k = 0; k < 3; ++k) {
      if (std::fabs(r.direction[k]) < 1e-12f) {
        if (r.exit[k] < grid.lo[k] || r.exit[k] > grid.hi[k]) t1 = -1.0f;
        continue;
      }
      float a = (grid.lo[k] - r.exit[k]) / r.direction[k], b = (grid.hi[k] - r.exit[k]) / r.direction[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
    if (!(t1 > t0)) continue;
    // Midpoint samples a quarter of a cell apart: flux x length per cell.
    const int samples = std::min(100000, static_cast<int>(std::ceil((t1 - t0) / step)));
    const float ds = (t1 - t0) / static_cast<float>(samples);
    for (int i = 0; i < samples; ++i) {
      const glm::vec3 x = r.exit + r.direction * (t0 + (static_cast<float>(i) + 0.5f) * ds);
      const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor((x - grid.lo) / h)), glm::ivec3(0), n - 1);
      const std::size_t v = (std::size_t(c.z) * std::size_t(n.y) + std::size_t(c.y)) * std::size_t(n.x) + std::size_t(c.x);
      if (t.last[v] < 0) t.touched.push_back(v);
      t.fluence[v] += double(r.flux) * double(ds);
      if (t.last[v] != static_cast<int>(ri)) {
        t.last[v] = static_cast<int>(ri);
        ++t.count[v];
      }
    }
  }
  const double volume = double(h.x) * double(h.y) * double(h.z);
  glm::ivec3 lo(n), hi(-1), loose_lo(n), loose_hi(-1);  // cells at the concentration; at a quarter of it
  for (const std::size_t v : t.touched) {
    if (t.count[v] >= kFocusMinRays && t.fluence[v] >= 0.25 * kFocusConcentration * volume) {
      const glm::ivec3 c(static_cast<int>(v % std::size_t(n.x)), static_cast<int>(v / std::size_t(n.x) % std::size_t(n.y)),
                         static_cast<int>(v / (std::size_t(n.x) * std::size_t(n.y))));
      loose_lo = glm::min(loose_lo, c);
      loose_hi = glm::max(loose_hi, c);
      if (t.fluence[v] >= kFocusConcentration * volume) {
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
      }
    }
    t.fluence[v] = 0.0;
    t.count[v] = 0;
    t.last[v] = -1;
  }
  t.touched.clear();
  if (hi.x < 0) return Box{};
  const auto box = [&](const glm::ivec3& a, const glm::ivec3& b) { return Box{grid.lo + glm::vec3(a) * h, grid.lo + glm::vec3(b) * h}; };
  const Box core = box(lo, hi + 1), loose = box(glm::max(loose_lo - 1, glm::ivec3(0)), glm::min(loose_hi + 2, n));
  const auto holds = [](const Box& outer, const Box& inner) {
    return glm::all(glm::lessThanEqual(outer.lo, inner.lo)) && glm::all(glm::greaterThanEqual(outer.hi, inner.hi));
  };
  if (!kept.empty() && holds(kept, core) && holds(loose, kept)) return kept;
  return box(glm::max(lo - 1, glm::ivec3(0)), glm::min(hi + 2, n));
}

constexpr int kTallyWords = 16;  // per light: see volume_photons.comp.glsl
constexpr int kMaxSteps = 4096;
// Texture units: the index grids from 0 (one at least), then the viewing
// pass's lights' sources and mean directions up to 5; the scene's depth and
// colour. All within the units 0-7 that the engine's state guard saves.
constexpr GLuint kGridUnit = 0, kDepthUnit = 6, kColorUnit = 7;

}  // namespace

struct VolumeEngine::Impl {
  struct Glass {
    std::uint32_t object;
    gl::Texture texture;  // RG16: coverage, octree level / 15
    glm::vec3 size;
    glm::mat4 voxel_to_object{1.0f};
    float n_out, n_in, voxel;
    Coefficients c;
    bool under_water = false;
  };
  struct PerLight {
    gl::Texture source, direction;
    gl::Query march, resolve;
    double march_ms = 0, resolve_ms = 0;  // the latest timer results ready
    bool valid = false;  // source and direction hold this light's radiance for the current grid
    bool timed = false;  // remade this frame: its photons and timer queries are this frame's
    double scale = 1, tally_scale = 1;  // fixed-point units per unit of power (light units)
    std::uint64_t photons = 0, glass_photons = 0;  // emitted; of which over the glass's own square
    Box focus;   // the light's focus grid; empty: none
    Box fitted;  // the box focus_box gave at the last update (kept while it serves)
  };
  std::vector<Glass> glass;
  std::optional<Box> fog_box, water_box;
  Coefficients fog, water;
  float water_level = 0, water_ior = 1.33f;
  Box grid_box;  // the radiance grid: where something scatters
  glm::ivec3 grid_n{0};
  int focus_n = 0;       // voxels a side of the focus grids (0: none)
  FocusScratch focus_scratch;
  glm::ivec3 atlas{0};   // the per-light textures: the radiance grid, then the focus grid's slices
  std::uint32_t grid_option = 0;
  float e0 = 1;
  gl::Program resolve;
  // The photons' and the viewing pass's programs for each way a ray crosses
  // an object's surface (VolumeOptions::surface_refraction; index 1:
  // surface), built from these sources when first used: with both in one
  // program, llvmpipe ran both in every grid step (fog_ball's media pass
  // 69 -> 134 ms at 320 x 200).
  std::string photons_src, view_src;
  std::array<gl::Program, 2> photons_by, view_by;

  Status ensure_programs(bool surface) {
    const std::size_t i = surface ? 1 : 0;
    if (photons_by[i].id() != 0) return Status::success();
    const std::string define = std::string("#define CAUSTIX_SURFACE_REFRACTION ") + (surface ? "1" : "0") + "\n";
    const std::string photons = insert_after_version(photons_src.c_str(), define), view = insert_after_version(view_src.c_str(), define);
    return gl::build_programs({{&photons_by[i], "volume_photons", photons.c_str()},
                               {&view_by[i], "volume_view", shaders::k_fullscreen_vert_glsl, view.c_str()}});
  }
  gl::Buffer accumulator, tally;
  gl::Texture dummy_3d;
  gl::Sampler nearest;
  gl::VertexArray empty_vao;
  std::vector<PerLight> lights;
  std::uint64_t index_bytes = 0;
  bool ran = false;        // the effect is on and has a grid
  GLuint grid_units = 1;   // units the index grids take (CAUSTIX_GRID_UNITS)
  std::size_t view_lights = 1;  // lights one viewing pass marches for (CAUSTIX_VIEW_LIGHTS)
  bool counting = false;   // some light was remade this frame: its tallies are this frame's
  // What each light's radiance was made from.
  MadeFrom<LightInputs> made;
  // Each frame's tallies come back through `readback` without a stall:
  // `tallied` holds the latest that arrived (of frame `tallied_frame`),
  // with the scales and photon counts of the lights as they were then.
  gl::ReadbackRing readback;
  struct Tallied {
    std::vector<std::uint32_t> words;
    std::vector<double> scale, tally_scale;
    std::vector<std::uint64_t> photons, glass_photons;
    std::vector<bool> timed;
  } tallied;
  std::uint64_t tallied_frame = 0;
  std::map<std::uint64_t, Tallied> in_flight;  // the lights' scales per frame in flight
  void poll() {
    readback.poll([&](std::uint64_t tag, const std::uint8_t* data) {
      const auto it = in_flight.find(tag);
      if (it == in_flight.end()) return;
      tallied = std::move(it->second);
      tallied.words.resize(kTallyWords * lights.size());
      std::memcpy(tallied.words.data(), data, tallied.words.size() * 4);
      tallied_frame = tag;
      in_flight.erase(it);
    });
  }

  std::uint64_t voxels() const { return std::uint64_t(grid_n.x) * std::uint64_t(grid_n.y) * std::uint64_t(grid_n.z); }
  std::uint64_t focus_voxels() const { return std::uint64_t(focus_n) * std::uint64_t(focus_n) * std::uint64_t(focus_n); }
  std::uint64_t atlas_texels() const { return std::uint64_t(atlas.x) * std::uint64_t(atlas.y) * std::uint64_t(atlas.z); }

  // The focus grid's uniforms (volume_common.glsl) for light `l`.
  void set_focus(const gl::Program& p, const PerLight& l) const {
    const bool on = focus_n > 0 && !l.focus.empty();
    p.set("u_focus_on", on ? 1 : 0);
    p.set("u_focus_lo", on ? l.focus.lo : glm::vec3(0.0f));
    p.set("u_focus_hi", on ? l.focus.hi : glm::vec3(0.0f));
    glProgramUniform3i(p.id(), p.loc("u_focus_n"), focus_n, focus_n, focus_n);
  }

  glm::mat4 world_to_voxel(const SceneDesc& scene, const Glass& g) const {
    return glm::inverse(glm::make_mat4(scene.objects[g.object].transform.data()) * g.voxel_to_object);
  }

  // The uniforms of volume_common.glsl; the indices at wavelength `nm`
  // when set (dispersion), else n_d.
  void set_media(const gl::Program& p, const SceneDesc& scene, std::optional<float> nm = std::nullopt) const {
    for (std::size_t i = 0; i < glass.size(); ++i) {
      const Glass& g = glass[i];
      const char k[4] = {'[', static_cast<char>('0' + i), ']', 0};  // i < kMaxObjects
      auto name = [&k](const char* base) { return std::string(base) + k; };
      const glm::mat4 model = glm::make_mat4(scene.objects[g.object].transform.data());
      p.set(name("u_world_to_voxel").c_str(), world_to_voxel(scene, g));
      float n_out = g.n_out, n_in = g.n_in;
      if (nm) {
        n_in = index_at(g.n_in, scene.objects[g.object].material.dispersion, *nm);
        if (g.under_water && scene.water) n_out = index_at(g.n_out, scene.water->dispersion, *nm);
      }
      p.set(name("u_glass_ior").c_str(), glm::vec4(n_out, n_in, g.voxel * glm::length(glm::vec3(model[0])), 1.0f));
      p.set(name("u_glass_size").c_str(), glm::vec4(g.size, 0.0f));
      p.set(name("u_glass_ss").c_str(), g.c.ss);
      p.set(name("u_glass_st").c_str(), g.c.st);
    }
    p.set("u_fog_on", fog_box ? 1 : 0);
    if (fog_box) {
      p.set("u_fog_lo", fog_box->lo);
      p.set("u_fog_hi", fog_box->hi);
      p.set("u_fog_ss", fog.ss);
      p.set("u_fog_st", fog.st);
    }
    p.set("u_water_on", water_box ? 1 : 0);
    if (water_box) {
      p.set("u_water_lo", water_box->lo);
      p.set("u_water_hi", water_box->hi);
      p.set("u_water_level", water_level);
      p.set("u_water_ss", water.ss);
      p.set("u_water_st", water.st);
    }
    p.set("u_grid_lo", grid_box.lo);
    p.set("u_grid_hi", grid_box.hi);
    glProgramUniform3i(p.id(), p.loc("u_grid_n"), grid_n.x, grid_n.y, grid_n.z);
  }

  void bind_index_grids() const {
    for (GLuint u = 0; u < grid_units; ++u) {
      glBindTextureUnit(kGridUnit + u, u < glass.size() ? glass[u].texture.get() : dummy_3d.get());
    }
  }

  // World box of object g's index grid at its current transform.
  Box grid_world_box(const SceneDesc& scene, const Glass& g) const {
    const glm::mat4 m = glm::make_mat4(scene.objects[g.object].transform.data()) * g.voxel_to_object;
    Box b;
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 corner((c & 1) ? g.size.x : 0.0f, (c & 2) ? g.size.y : 0.0f, (c & 4) ? g.size.z : 0.0f);
      const glm::vec3 w(m * glm::vec4(corner, 1.0f));
      b.lo = glm::min(b.lo, w);
      b.hi = glm::max(b.hi, w);
    }
    return b;
  }

  // The largest sigma_s of any medium and channel.
  float max_scattering() const {
    auto mx = [](const Coefficients& c) { return std::max({c.ss.x, c.ss.y, c.ss.z}); };
    float m = 0;
    if (fog_box) m = std::max(m, mx(fog));
    if (water_box) m = std::max(m, mx(water));
    for (const Glass& g : glass) m = std::max(m, mx(g.c));
    return m;
  }

  // Whether a medium's phase function depends on the light's direction
  // (Schlick with k != 0): only then do the photons keep their mean
  // direction in the radiance grid (3 of a deposit's 6 atomic adds).
  bool anisotropic() const {
    auto an = [](const Coefficients& c) { return c.scatters() && c.st.w > 1.5f && c.ss.w != 0.0f; };
    bool a = (fog_box && an(fog)) || (water_box && an(water));
    for (const Glass& g : glass) a = a || an(g.c);
    return a;
  }

  // The radiance grid's box: where something scatters.
  Box scattering_box(const SceneDesc& scene) const {
    Box b;
    if (fog_box && fog.scatters()) b.add(*fog_box);
    if (water_box && water.scatters()) b.add(*water_box);
    for (const Glass& g : glass) {
      if (g.c.scatters()) b.add(grid_world_box(scene, g));
    }
    return b;
  }
};

VolumeEngine::~VolumeEngine() = default;

Result<std::unique_ptr<VolumeEngine>> VolumeEngine::create(const SceneDesc& scene, const std::vector<IndexGrid>& grids,
                                                           float scene_min_y, const std::string& lighting_prefix) {
  if (!scene_scatters(scene)) return std::unique_ptr<VolumeEngine>();
  std::unique_ptr<VolumeEngine> e(new VolumeEngine());
  e->impl_ = std::make_unique<Impl>();
  Impl& s = *e->impl_;
  if (grids.size() > kMaxObjects) {
    return make_error(ErrorCode::kUsage, "the scene has " + std::to_string(grids.size()) + " transparent objects in media; the runtime's volume effect takes at most " +
                                             std::to_string(kMaxObjects));
  }
  s.e0 = scene_e0(scene);
  if (scene.medium) {
    const auto& x = scene.medium->extent;
    s.fog_box = Box{{x[0], x[1], x[2]}, {x[3], x[4], x[5]}};
    s.fog = coefficients(scene.medium->absorption, scene.medium->scattering);
  }
  if (scene.water) {
    const Water& w = *scene.water;
    float amplitude = 0;
    for (const Wave& wave : w.waves) amplitude += std::fabs(wave.amplitude);
    const float floor_y = std::min(w.level, scene_min_y);  // the lowest object: nothing below it is seen
    s.water_box = Box{{w.extent[0], floor_y, w.extent[1]}, {w.extent[2], w.level + amplitude + 1e-3f, w.extent[3]}};
    s.water = coefficients(w.absorption, w.scattering);
    s.water_level = w.level;
    s.water_ior = w.ior;
  }
  s.dummy_3d = gl::make_texture(GL_TEXTURE_3D);
  glTextureStorage3D(s.dummy_3d.get(), 1, GL_RG16, 1, 1, 1);
  glClearTexImage(s.dummy_3d.get(), 0, GL_RG, GL_UNSIGNED_SHORT, nullptr);
  for (const IndexGrid& g : grids) {
    Impl::Glass gl_grid;
    gl_grid.object = g.object;
    gl_grid.size = glm::vec3(g.size[0], g.size[1], g.size[2]);
    gl_grid.voxel_to_object = glm::scale(glm::translate(glm::mat4(1.0f), to_glm(g.origin)), glm::vec3(g.voxel));
    gl_grid.n_out = g.ior_outside;
    gl_grid.n_in = g.ior_inside;
    gl_grid.voxel = g.voxel;
    const Object& o = scene.objects[g.object];
    gl_grid.c = coefficients(o.material.absorption, o.material.scattering);
    // Coverage and level interleaved: the level as a 16-bit fraction of 15
    // (exact after rounding), read with texelFetch.
    std::vector<std::uint16_t> texels(2 * g.voxels());
    for (std::size_t v = 0; v < g.voxels(); ++v) {
      texels[2 * v] = g.coverage[v];
      texels[2 * v + 1] = static_cast<std::uint16_t>(g.level[v] * 4369u);
    }
    gl_grid.texture = gl::make_texture(GL_TEXTURE_3D);
    const GLuint t = gl_grid.texture.get();
    glTextureStorage3D(t, 1, GL_RG16, static_cast<GLsizei>(g.size[0]), static_cast<GLsizei>(g.size[1]), static_cast<GLsizei>(g.size[2]));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(t, 0, 0, 0, 0, static_cast<GLsizei>(g.size[0]), static_cast<GLsizei>(g.size[1]), static_cast<GLsizei>(g.size[2]),
                        GL_RG, GL_UNSIGNED_SHORT, texels.data());
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum w : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R}) glTextureParameteri(t, w, GL_CLAMP_TO_BORDER);
    const float border[4] = {0, 0, 0, 0};
    glTextureParameterfv(t, GL_TEXTURE_BORDER_COLOR, border);
    s.index_bytes += 4 * g.voxels();
    s.glass.push_back(std::move(gl_grid));
  }
  if (s.water_box) {
    for (Impl::Glass& g : s.glass) g.under_water = s.grid_world_box(scene, g).hi.y < s.water_level;
  }

  // The viewing pass marches for as many lights at once as units 0-5 hold
  // beside the index grids: a source each, and a mean direction each where
  // a phase function needs it.
  s.grid_units = static_cast<GLuint>(std::max<std::size_t>(s.glass.size(), 1));
  const std::size_t per_light = s.anisotropic() ? 2 : 1;
  s.view_lights = std::clamp<std::size_t>(scene.lights.size(), 1, (kDepthUnit - s.grid_units) / per_light);
  const std::string common = insert_after_version(lighting_prefix.c_str(), "#define CAUSTIX_GLASS_COUNT " + std::to_string(s.glass.size()) +
                                                                                "\n#define CAUSTIX_GRID_UNITS " + std::to_string(s.grid_units) +
                                                                                "\n#define CAUSTIX_DIRECTIONS " + (s.anisotropic() ? "1" : "0") + "\n") +
                             shaders::k_volume_common_glsl;
  s.photons_src = insert_after_version(common.c_str(), "#define CAUSTIX_NO_DERIVATIVES\n") + shaders::k_volume_photons_comp_glsl;
  s.view_src =
      insert_after_version(common.c_str(), "#define CAUSTIX_VIEW_LIGHTS " + std::to_string(s.view_lights) + "\n") + shaders::k_volume_view_frag_glsl;
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs({{&s.resolve, "volume_resolve", shaders::k_volume_resolve_comp_glsl}}));
  CAUSTIX_RETURN_IF_ERROR(s.ensure_programs(VolumeOptions{}.surface_refraction));
  s.empty_vao = gl::make_vertex_array();
  s.nearest = gl::make_nearest_sampler();
  s.lights.resize(scene.lights.size());
  s.made.resize(scene.lights.size());
  for (Impl::PerLight& l : s.lights) {
    l.march = gl::make_query(GL_TIME_ELAPSED);
    l.resolve = gl::make_query(GL_TIME_ELAPSED);
  }
  s.tally = gl::make_buffer();
  const std::size_t tally_bytes = std::size_t{4} * kTallyWords * std::max<std::size_t>(1, s.lights.size());
  glNamedBufferStorage(s.tally.get(), static_cast<GLsizeiptr>(tally_bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
  s.readback.reserve(tally_bytes);
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("volume set-up"));
  return e;
}

Status VolumeEngine::check(const VolumeOptions& o) {
  if (!o.enabled) return Status::success();
  if (o.photons < 1 || o.photons > 8192 || o.grid < 2 || o.grid > 1024 || !(o.step >= 0.05f && o.step <= 16.0f) ||
      !(o.view_step >= 0.05f && o.view_step <= 16.0f) || o.focus_grid == 1 || o.focus_grid > 128) {
    return make_error(ErrorCode::kUsage,
                      "volume options: photons 1..8192 per axis, grid 2..1024, focus grid 0 (off) or 2..128, step and view step 0.05..16 voxels");
  }
  return Status::success();
}

Status VolumeEngine::begin_frame(const SceneDesc& scene, const VolumeOptions& o) {
  Impl& s = *impl_;
  s.poll();
  s.ran = false;
  if (!o.enabled) return Status::success();
  const Box box = s.scattering_box(scene);
  if (box.empty()) return Status::success();
  const glm::vec3 ext = box.hi - box.lo;
  const float side = std::max({ext.x, ext.y, ext.z}) / static_cast<float>(o.grid);
  glm::ivec3 n;
  for (int k = 0; k < 3; ++k) n[k] = std::max(1, static_cast<int>(std::ceil(ext[k] / side - 1e-4f)));
  const std::uint64_t voxels = std::uint64_t(n.x) * std::uint64_t(n.y) * std::uint64_t(n.z);
  if (voxels > kMaxRadianceVoxels) {
    return make_error(ErrorCode::kUsage, "radiance grid " + std::to_string(n.x) + " x " + std::to_string(n.y) + " x " + std::to_string(n.z) +
                                             " voxels exceeds the limit of " + std::to_string(kMaxRadianceVoxels) + " (" +
                                             std::to_string(kMaxRadianceVoxels * 56 >> 20) + " MiB per light); lower the volume grid");
  }
  s.grid_box = box;
  // Only light through glass concentrates into a focus grid.
  const int focus_n = s.glass.empty() ? 0 : static_cast<int>(o.focus_grid);
  if (n != s.grid_n || focus_n != s.focus_n) {
    s.grid_n = n;
    s.focus_n = focus_n;
    s.atlas = focus_n > 0 ? glm::ivec3(std::max(n.x, focus_n), std::max(n.y, focus_n), n.z + focus_n) : n;
    s.made.forget_all();  // new grids: every light's radiance is remade
    for (Impl::PerLight& l : s.lights) {
      l.valid = false;
      l.fitted = Box{};
    }
    s.accumulator = gl::make_buffer();
    glNamedBufferStorage(s.accumulator.get(), static_cast<GLsizeiptr>((voxels + s.focus_voxels()) * 6 * 4), nullptr, 0);
    const glm::ivec3 a = s.atlas;
    for (Impl::PerLight& l : s.lights) {
      for (auto [tex, format] : {std::pair{&l.source, GL_RGBA32F}, std::pair{&l.direction, GL_RGBA16F}}) {
        *tex = gl::make_texture(GL_TEXTURE_3D);
        glTextureStorage3D(tex->get(), 1, format, a.x, a.y, a.z);
        glTextureParameteri(tex->get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(tex->get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        for (GLenum w : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R}) glTextureParameteri(tex->get(), w, GL_CLAMP_TO_EDGE);
      }
    }
  }
  glClearNamedBufferData(s.tally.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  for (Impl::PerLight& l : s.lights) l.timed = false;
  s.counting = false;
  s.ran = true;
  return gl::check_gl("volume grids");
}

Status VolumeEngine::update_light(const SceneDesc& scene, std::uint32_t li, const VolumeOptions& o, const WaterSurface* water,
                                  const std::vector<WavelengthSample>& waves, bool spectral, const std::function<void()>& bind_light,
                                  const std::function<std::vector<ExitRay>()>& focus_rays, const CausticsOptions& caustics,
                                  const SceneVersions& versions, bool due, EffectWork& work) {
  Impl& s = *impl_;
  if (!s.ran) return Status::success();
  const LightInputs key{SceneVersions{versions.light, versions.transforms, water ? versions.water : 0}, caustics};
  if (s.made.decide(li, key, due, work) != Refresh::kRemake) return Status::success();
  s.made.made(li, key);
  s.counting = true;
  Impl::PerLight& pl = s.lights[li];
  pl.photons = pl.glass_photons = 0;
  pl.focus = s.focus_n > 0 && focus_rays ? focus_box(focus_rays(), s.grid_box, s.grid_n, pl.fitted, s.focus_scratch) : Box{};
  pl.fitted = pl.focus;
  if (!pl.focus.empty()) {
    // Only where its voxels are at least twice as fine as the radiance
    // grid's (by volume, 8 times).
    const glm::vec3 fe = pl.focus.hi - pl.focus.lo, ge = s.grid_box.hi - s.grid_box.lo;
    const double focus_voxel = double(fe.x) * fe.y * fe.z / double(s.focus_voxels());
    if (focus_voxel * 8.0 > double(ge.x) * ge.y * ge.z / double(s.voxels())) pl.focus = Box{};
  }
  const Light& light = scene.lights[li];
  const bool point = light.type == LightType::kPoint;
  const glm::vec3 lp = to_glm(light.position);
  const glm::vec3 dir = point ? glm::vec3(0, -1, 0) : glm::normalize(to_glm(light.direction));
  const float power = point ? light.intensity : light.irradiance;
  const glm::vec3 color = to_glm(light.color) * power;

  // Sources (Pfeuti "Photon Generation"): the light's window over what
  // lies in the air (the medium box, objects above any water) on a plane
  // above it, and the water surface when the water or an object under it
  // scatters.
  Box air;
  if (s.fog_box) air.add(*s.fog_box);
  bool under_scatters = s.water_box && s.water.scatters();
  for (const Impl::Glass& g : s.glass) {
    if (!g.under_water) air.add(s.grid_world_box(scene, g));
    under_scatters = under_scatters || (g.under_water && g.c.scatters());
  }
  // The kinds, as volume_photons.comp reads u_source.
  constexpr int kLightWindow = 0, kWaterSurface = 1, kLensSquare = 2;
  struct Source {
    int kind;
    glm::vec4 window;
    float y = 0;
    double power = 0;        // most it emits: the largest power per unit of its area x that area
    bool square = false;     // kLightWindow: the lens's square takes the rays that cross it
    std::uint32_t side = 0;  // photons per axis
  };
  std::vector<Source> sources;
  LensSquare sq;
  const auto area_of = [](const glm::vec4& w) { return double(w.z - w.x) * double(w.w - w.y); };
  if (!air.empty()) {
    const float y_top = air.hi.y + 1e-3f;
    // A box's window: its corners back along the light's rays to y = y_top.
    auto window_of = [&](const Box& b) {
      glm::vec4 win(1e30f, 1e30f, -1e30f, -1e30f);
      for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z);
        const glm::vec3 q = point ? lp + (corner - lp) * ((lp.y - y_top) / std::max(lp.y - corner.y, 1e-6f))
                                  : corner + dir * ((y_top - corner.y) / dir.y);
        win = glm::vec4(std::min(win.x, q.x), std::min(win.y, q.z), std::max(win.z, q.x), std::max(win.w, q.z));
      }
      return win;
    };
    const bool ok = point ? lp.y > y_top : dir.y < 0.0f;
    if (ok) {
      const double bound = point ? 1.0 / double(lp.y - y_top) / double(lp.y - y_top) : -dir.y;
      const glm::vec4 win = window_of(air);
      // With a focus grid, the glass gets photons of its own, (P/2)^2
      // (glass_side), on a square across the light over the lens, and the
      // light's window leaves the rays through that square to them: the
      // focal line is drawn by the photons that cross the glass, which the
      // light's window spreads thinly (fog_ball: 1 in 11 of them cross the
      // ball; their tracks showed as streaks in the 4 mm voxels).
      Box lens;
      if (!pl.focus.empty()) {
        for (const Impl::Glass& g : s.glass) {
          if (!g.under_water) lens.add(s.grid_world_box(scene, g));
        }
      }
      sources.push_back({kLightWindow, win, y_top, bound * area_of(win), !lens.empty(), o.photons});
      if (!lens.empty()) {
        sq = lens_square(lens, point ? glm::normalize(0.5f * (lens.lo + lens.hi) - lp) : dir);
        const float dist = glm::dot(sq.c - lp, sq.n);
        const double square_area = 4.0 * double(glm::length(sq.u)) * double(glm::length(sq.v));
        sources.push_back({kLensSquare, win, y_top, (point ? 1.0 / double(dist * dist) : 1.0) * square_area, false, glass_side(o.photons)});
      }
    }
  }
  if (under_scatters && water) {
    const Water& w = water->water();
    const bool lit = point ? lp.y > s.water_box->hi.y : dir.y < 0.0f;
    if (lit) {
      const double d = lp.y - s.water_box->hi.y;
      const glm::vec4 extent(w.extent[0], w.extent[1], w.extent[2], w.extent[3]);
      sources.push_back({kWaterSurface, extent, 0.0f, (point ? 1.0 / (d * d) : -dir.y) * area_of(extent), false, o.photons});
    }
  }
  // Fixed point: one photon crossing one voxel deposits at most
  // min(1, sigma_s sqrt(3) h) of its power, so no voxel can hold more than
  // that share of all the power emitted (2^29: room for a path that turns
  // back through a voxel).
  double total = 0;
  for (const Source& src : sources) total += src.power;
  const double cmax = std::max({color.r, color.g, color.b, 1e-30f});
  const glm::vec3 hg = (s.grid_box.hi - s.grid_box.lo) / glm::vec3(s.grid_n);
  const double share = std::min(1.0, double(s.max_scattering()) * std::sqrt(3.0) * double(std::max({hg.x, hg.y, hg.z})));
  pl.scale = std::ldexp(1.0, 29) / std::max(total * cmax * share, 1e-30);
  pl.tally_scale = std::ldexp(1.0, 28) / std::max(total * std::max(double(luminance(color)), 1e-30), 1e-30);

  glClearNamedBufferData(s.accumulator.get(), GL_R32I, GL_RED_INTEGER, GL_INT, nullptr);
  bind_light();
  s.bind_index_grids();
  CAUSTIX_RETURN_IF_ERROR(s.ensure_programs(o.surface_refraction));
  const gl::Program& p = s.photons_by[o.surface_refraction ? 1 : 0];
  p.use();
  s.set_media(p, scene);
  const glm::vec3 ext = s.grid_box.hi - s.grid_box.lo;
  p.set("u_light_color", color);
  p.set("u_scale", static_cast<float>(pl.scale));
  p.set("u_tally_scale", static_cast<float>(pl.tally_scale));
  p.set("u_step", o.step);
  p.set("u_octree", o.octree ? 1 : 0);
  p.set("u_max_steps", kMaxSteps);
  p.set("u_eps", 1e-5f * std::max({ext.x, ext.y, ext.z}));
  p.set("u_water_ior", s.water_ior);
  s.set_focus(p, pl);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, s.accumulator.get());
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, s.tally.get(), GLintptr{4} * kTallyWords * li, GLsizeiptr{4} * kTallyWords);
  if (water) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, water->positions_buffer());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, water->normals_buffer());
    glProgramUniform2ui(p.id(), p.loc("u_water_cells"), water->water().cells[0], water->water().cells[1]);
  } else {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, s.tally.get());  // never read
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, s.tally.get());
  }
  std::optional<gl::TimedPass> timed;
  timed.emplace("media: photons", gl::PassKind::kCompute);
  glBeginQuery(GL_TIME_ELAPSED, pl.march.get());
  // Per traced wavelength (dispersion): the same photons (same seed: the
  // channels' noise stays correlated, no coloured grain), the bin's share
  // of the light's colour (signed: the fixed point is), the indices at its
  // wavelength. The fixed-point bound above keeps its margin: a bin's weight
  // reaches 1.135 at most (red of 2 bins; 2^29 of the 2^31 leaves 4x).
  for (const WavelengthSample& w : waves) {
    if (spectral) {
      p.set("u_light_color", color * glm::vec3(w.rgb[0], w.rgb[1], w.rgb[2]));
      if (scene.water) p.set("u_water_ior", index_at(s.water_ior, scene.water->dispersion, w.nm));
      s.set_media(p, scene, w.nm);
    }
    for (const Source& src : sources) {
      p.set("u_seed", 0x9E3779B9u * (li + 1) + (src.kind == kLensSquare ? 0x632BE5ABu : 0u));
      p.set("u_source", src.kind);
      p.set("u_window", src.window);
      p.set("u_window_y", src.y);
      p.set("u_square_on", src.square ? 1 : 0);
      p.set("u_square_c", sq.c);
      p.set("u_square_u", sq.u);
      p.set("u_square_v", sq.v);
      p.set("u_square_n", sq.n);
      p.set("u_side", src.side);
      glDispatchCompute((src.side * src.side + 63) / 64, 1, 1);
      pl.photons += std::uint64_t{src.side} * src.side;
      if (src.kind == kLensSquare) pl.glass_photons += std::uint64_t{src.side} * src.side;
    }
  }
  glEndQuery(GL_TIME_ELAPSED);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

  timed.emplace("media: radiance grid", gl::PassKind::kCompute);
  glBeginQuery(GL_TIME_ELAPSED, pl.resolve.get());
  s.resolve.use();
  glBindImageTexture(0, pl.source.get(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(1, pl.direction.get(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
  // The radiance grid (its sum tallied), then the focus grid after it.
  auto resolve = [&](const glm::ivec3& n, const glm::vec3& size, int base, int slice, int count) {
    glProgramUniform3i(s.resolve.id(), s.resolve.loc("u_grid_n"), n.x, n.y, n.z);
    const glm::vec3 h = size / glm::vec3(n);
    s.resolve.set("u_inv_scale_volume", static_cast<float>(1.0 / (pl.scale * double(h.x) * double(h.y) * double(h.z))));
    s.resolve.set("u_base", base);
    s.resolve.set("u_slice", slice);
    s.resolve.set("u_count", count);
    glDispatchCompute(static_cast<GLuint>((std::uint64_t(n.x) * std::uint64_t(n.y) * std::uint64_t(n.z) + 63) / 64), 1, 1);
  };
  resolve(s.grid_n, ext, 0, 0, 1);
  if (!pl.focus.empty()) resolve(glm::ivec3(s.focus_n), pl.focus.hi - pl.focus.lo, static_cast<int>(6 * s.voxels()), s.grid_n.z, 0);
  glEndQuery(GL_TIME_ELAPSED);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  pl.timed = pl.valid = true;
  return gl::check_gl("volume photons");
}

Status VolumeEngine::draw(const SceneDesc& scene, const glm::mat4& view_proj, const gl::SceneTexture& scene_color,
                          const gl::SceneTexture& scene_depth, gl::SceneReader& reader, float scale, const VolumeOptions& o) {
  Impl& s = *impl_;
  if (!s.ran) return Status::success();
  const gl::TimedPass timed("media: view", gl::PassKind::kRaster);
  GLint vp[4] = {0, 0, 0, 0}, target_fbo = 0;
  glGetIntegerv(GL_VIEWPORT, vp);
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target_fbo);
  // The caller's textures are read in place unless the bound framebuffer
  // holds them or they are multisampled (gl/scene_inputs.h; no full-frame
  // copies where none is needed). Compositing over the colour the
  // framebuffer draws into is blending (dual-source: dst x T + L), which
  // needs no read of it at all.
  const bool blend_over = scene_color && gl::draws_only_into(scene_color.name);
  const bool copy_color = scene_color && !blend_over && gl::attached_to_draw_framebuffer(scene_color.name);
  const bool copy_depth = gl::attached_to_draw_framebuffer(scene_depth.name);
  CAUSTIX_RETURN_IF_ERROR(reader.read(blend_over ? gl::SceneTexture{} : scene_color, scene_depth, copy_color, copy_depth));
  const GLuint color_read = reader.color(), depth_read = reader.depth();
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(target_fbo));
  glViewport(vp[0], vp[1], vp[2], vp[3]);
  gl::encode_srgb_if_the_target_is_srgb();

  CAUSTIX_RETURN_IF_ERROR(s.ensure_programs(o.surface_refraction));
  const gl::Program& p = s.view_by[o.surface_refraction ? 1 : 0];
  p.use();
  s.set_media(p, scene);
  const glm::vec3 hv = (s.grid_box.hi - s.grid_box.lo) / glm::vec3(s.grid_n);
  p.set("u_view_proj", view_proj);
  p.set("u_inv_view_proj", glm::inverse(view_proj));
  p.set("u_viewport_origin", glm::vec2(vp[0], vp[1]));
  p.set("u_viewport_size", glm::vec2(vp[2], vp[3]));
  p.set("u_water_excluded", 1);
  p.set("u_scale", scale);
  p.set("u_view_step", o.view_step * std::min({hv.x, hv.y, hv.z}));
  p.set("u_atlas", glm::vec3(s.atlas));
  p.set("u_step", o.step);
  p.set("u_octree", o.octree ? 1 : 0);
  p.set("u_max_steps", kMaxSteps);
  glProgramUniform3i(p.id(), p.loc("u_focus_n"), s.focus_n, s.focus_n, s.focus_n);
  s.bind_index_grids();
  glBindTextureUnit(kDepthUnit, depth_read);
  glBindTextureUnit(kColorUnit, color_read);
  glBindSampler(kDepthUnit, s.nearest.get());
  glBindSampler(kColorUnit, s.nearest.get());
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glDisable(GL_CULL_FACE);
  glBindVertexArray(s.empty_vao.get());
  bool first = true;
  // The lights in groups of view_lights, a march each (volume_view.frag).
  for (std::size_t group = 0; group < s.lights.size(); group += s.view_lights) {
    const std::size_t end = std::min(group + s.view_lights, s.lights.size());
    if (std::none_of(s.lights.begin() + static_cast<std::ptrdiff_t>(group), s.lights.begin() + static_cast<std::ptrdiff_t>(end),
                     [](const Impl::PerLight& l) { return l.valid; })) {
      continue;  // no photons yet
    }
    const bool composite = scene_color && first;
    first = false;
    p.set("u_composite", !composite ? 0 : blend_over ? 2 : 1);
    if (composite && blend_over) {
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_SRC1_COLOR);  // L + dst x T
    } else if (composite) {
      glDisable(GL_BLEND);
    } else {
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE);
    }
    for (std::size_t k = 0; k < s.view_lights; ++k) {
      // A slot past the last light, or a light without photons yet: no
      // source (the 1-voxel zero texture) and no focus.
      const Impl::PerLight* pl = group + k < end && s.lights[group + k].valid ? &s.lights[group + k] : nullptr;
      const std::string at = "[" + std::to_string(k) + "]";
      const bool focus = pl && s.focus_n > 0 && !pl->focus.empty();
      p.set(("u_light_focus_on" + at).c_str(), focus ? 1 : 0);
      p.set(("u_light_focus_lo" + at).c_str(), focus ? pl->focus.lo : glm::vec3(0.0f));
      p.set(("u_light_focus_hi" + at).c_str(), focus ? pl->focus.hi : glm::vec3(0.0f));
      if (focus) {
        const glm::vec3 hf = (pl->focus.hi - pl->focus.lo) / static_cast<float>(s.focus_n);
        p.set(("u_light_step_focus" + at).c_str(), o.view_step * std::min({hf.x, hf.y, hf.z}));
      }
      const auto unit = static_cast<GLuint>(s.grid_units + k);
      glBindTextureUnit(unit, pl ? pl->source.get() : s.dummy_3d.get());
      if (s.anisotropic()) glBindTextureUnit(unit + static_cast<GLuint>(s.view_lights), pl ? pl->direction.get() : s.dummy_3d.get());
    }
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glBindVertexArray(0);
  glBindSampler(kDepthUnit, 0);
  glBindSampler(kColorUnit, 0);
  return Status::success();
}

void VolumeEngine::end_frame(std::uint64_t frame) {
  Impl& s = *impl_;
  if (!s.ran || !s.counting || !s.readback.begin()) return;
  s.readback.copy(s.tally.get(), 0, 0, static_cast<GLsizeiptr>(std::size_t{4} * kTallyWords * s.lights.size()));
  s.readback.end(frame);
  Impl::Tallied& t = s.in_flight[frame];
  for (const Impl::PerLight& l : s.lights) {
    t.scale.push_back(l.scale);
    t.tally_scale.push_back(l.tally_scale);
    t.photons.push_back(l.photons);
    t.glass_photons.push_back(l.glass_photons);
    t.timed.push_back(l.timed);
  }
}

VolumeStats VolumeEngine::stats(bool wait) {
  Impl& s = *impl_;
  VolumeStats st;
  st.active = s.ran;
  st.grid_size = {static_cast<std::uint32_t>(s.grid_n.x), static_cast<std::uint32_t>(s.grid_n.y), static_cast<std::uint32_t>(s.grid_n.z)};
  st.grid_bytes = gpu_bytes();
  for (const Impl::PerLight& l : s.lights) {
    st.focus_boxes.push_back(l.focus.empty() ? std::array<float, 6>{0, 0, 0, 0, 0, 0}
                                             : std::array<float, 6>{l.focus.lo.x, l.focus.lo.y, l.focus.lo.z, l.focus.hi.x, l.focus.hi.y, l.focus.hi.z});
  }
  if (wait && s.readback.pending()) s.readback.wait();
  s.poll();
  const Impl::Tallied& t = s.tallied;
  st.tallies_frame = s.tallied_frame;
  for (std::size_t li = 0; li < t.timed.size(); ++li) {
    if (!t.timed[li]) continue;
    const std::uint32_t* w = &t.words[kTallyWords * li];
    const double k = 1.0 / (t.tally_scale[li] * s.e0);
    st.photons += t.photons[li];
    st.glass_photons += t.glass_photons[li];
    st.power_in += w[0] * k;
    st.scattered += w[1] * k;
    st.absorbed += w[2] * k;
    st.leaving += w[3] * k;
    st.reflected += w[4] * k;
    st.truncated += w[5] * k;
    st.steps += w[6] + (std::uint64_t{w[7]} << 32);
    st.grid_steps += w[8] + (std::uint64_t{w[9]} << 32);
    st.deposited += (w[10] + std::ldexp(double(w[11]), 32)) / (t.scale[li] * s.e0);
  }
  for (Impl::PerLight& l : s.lights) {
    if (!l.valid) continue;
    // The latest times ready (or, waiting, the last frame's).
    for (auto [q, ms] : {std::pair{l.march.get(), &l.march_ms}, std::pair{l.resolve.get(), &l.resolve_ms}}) {
      GLint ready = GL_FALSE;
      if (!wait) glGetQueryObjectiv(q, GL_QUERY_RESULT_AVAILABLE, &ready);
      if (!wait && !ready) continue;
      GLuint64 ns = 0;
      glGetQueryObjectui64v(q, wait ? GL_QUERY_RESULT : GL_QUERY_RESULT_NO_WAIT, &ns);
      *ms = static_cast<double>(ns) * 1e-6;
    }
    st.march_ms += l.march_ms;
    st.resolve_ms += l.resolve_ms;
  }
  return st;
}


std::uint64_t VolumeEngine::gpu_bytes() const {
  const Impl& s = *impl_;
  // Accumulator (6 x 4 B per voxel of both grids), per light RGBA32F +
  // RGBA16F per texel of the textures that hold both; index grids RG16.
  return (s.voxels() + s.focus_voxels()) * 24 + s.atlas_texels() * 24 * s.lights.size() + s.index_bytes + s.readback.gpu_bytes() +
         std::uint64_t{4} * kTallyWords * s.lights.size();
}

}  // namespace caustix::runtime
