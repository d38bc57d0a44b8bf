#include "causticmap.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <cstring>

#include <glm/gtc/type_ptr.hpp>

#include "caustix/formats/frame.h"
#include "caustix_shaders.h"
#include "focus_window.h"
#include "pass_timer.h"
#include "readback.h"
#include "shader_text.h"

namespace caustix::runtime {
namespace {

// Floats per object in the photon pass's material buffer (three vec4).
constexpr std::size_t kMaterialFloats = 12;


constexpr int kCounters = 10;
// causticmap_adaptive.comp's State block: count[2], leaves, threshold,
// dispatch (uvec4 at 16), photon_dispatch (32), draw (48), hist[16] (64).
constexpr GLsizeiptr kStateBytes = 128;
constexpr GLintptr kDispatchOffset = 16, kPhotonDispatchOffset = 32, kDrawOffset = 48;
// Caustic map texels a side of one texel of the adaptive photons' density
// map (causticmap_density.vert).
constexpr int kDensityBlock = 8;
// The focus window (causticmap_focus.comp): landed photons are
// counted in kFocusBins x kFocusBins cells over the map; a cell is
// concentrated where at least kFocusConcentration times the photons its
// area would catch straight from the light landed in it, and at least
// kFocusMinPhotons. The window is the square around those cells and one
// cell more, no larger than kFocusMaxHalf of the map (else the main map
// does nearly as well) and no smaller than kFocusMinHalf: the tables'
// windows' constants (gl/focus_window.h). It has half the main map's
// texels a side (focus_side) and lies above the main map in the same
// texture, whose height is then map_size + map_size / 2; which photons'
// light goes there is causticmap_splat.vert's.
constexpr int kFocusBins = focus::kBins;  // causticmap_focus.comp's and causticmap_splat.vert's kBins
constexpr float kFocusConcentration = static_cast<float>(focus::kConcentration);
constexpr float kFocusMinPhotons = static_cast<float>(focus::kMinSamples);
constexpr float kFocusMaxHalf = focus::kMaxHalf;
constexpr float kFocusMinHalf = focus::kMinHalf;
constexpr int kFocusWindowBytes = 16 + 4 * kFocusBins * kFocusBins;
int focus_side(int size) { return std::max(1, static_cast<int>(focus::kTexels * static_cast<float>(size))); }

glm::vec3 to_glm(const Vec3f& v) { return {v[0], v[1], v[2]}; }
Vec3f to_vec3f(const glm::vec3& v) { return {v.x, v.y, v.z}; }

gl::Texture make_map(int size, GLenum format, GLenum filter, int height = 0, int levels = 1) {
  gl::Texture t = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(t.get(), levels, format, size, height > 0 ? height : size);
  gl::set_sampling(t.get(), filter);
  if (levels > 1) glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  return t;
}

// An orthographic frame along the light: V towards it, (U, W) across.
struct LightFrame {
  glm::vec3 u, v, w;
  glm::vec3 origin;  // the caustic map's centre; coordinates along V are from here
  glm::vec2 map_half, caster_half;
  glm::vec3 caster_origin;
  float v_lo = 0, v_hi = 0;  // range along V of everything
  float diagonal = 0;        // of the box around every object
};

// Corners' extents of boxes along U, W, V.
void extents(const LightFrame& f, const std::vector<std::array<glm::vec3, 2>>& boxes, glm::vec3& lo, glm::vec3& hi) {
  lo = glm::vec3(1e30f);
  hi = glm::vec3(-1e30f);
  for (const auto& b : boxes) {
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 p(c & 1 ? b[1].x : b[0].x, c & 2 ? b[1].y : b[0].y, c & 4 ? b[1].z : b[0].z);
      const glm::vec3 q(glm::dot(p, f.u), glm::dot(p, f.w), glm::dot(p, f.v));
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
  }
}

// The frame along light `light` over every object's box, with the map's
// rectangle over all of them and the photons' over the casters' (a texel
// of margin on each side, at most 1 %, so that nothing touches the
// border). V towards the light (directional), or from the scene's centre
// towards it (point: an orthographic approximation of its view).
LightFrame light_frame(const Light& light, const std::vector<std::array<glm::vec3, 2>>& world_boxes,
                       const std::vector<std::array<glm::vec3, 2>>& caster_boxes, int size, int side) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const auto& b : world_boxes) {
    lo = glm::min(lo, b[0]);
    hi = glm::max(hi, b[1]);
  }
  LightFrame f;
  f.diagonal = glm::length(hi - lo);
  const bool directional = light.type == LightType::kDirectional;
  f.v = directional ? -glm::normalize(to_glm(light.direction)) : glm::normalize(to_glm(light.position) - 0.5f * (lo + hi));
  const glm::vec3 up = std::fabs(f.v.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  f.u = glm::normalize(glm::cross(up, f.v));
  f.w = glm::cross(f.v, f.u);
  glm::vec3 all_lo, all_hi, c_lo, c_hi;
  extents(f, world_boxes, all_lo, all_hi);
  extents(f, caster_boxes, c_lo, c_hi);
  auto rect = [&](const glm::vec3& a, const glm::vec3& b, int n, glm::vec3& origin, glm::vec2& half) {
    half = glm::max(0.5f * glm::vec2(b.x - a.x, b.y - a.y), glm::vec2(1e-4f));
    half *= 1.0f + std::min(2.0f / static_cast<float>(n), 0.01f);
    const glm::vec2 mid = 0.5f * glm::vec2(a.x + b.x, a.y + b.y);
    origin = mid.x * f.u + mid.y * f.w + 0.5f * (all_lo.z + all_hi.z) * f.v;
  };
  rect(all_lo, all_hi, size, f.origin, f.map_half);
  rect(c_lo, c_hi, side, f.caster_origin, f.caster_half);
  const float v0 = glm::dot(f.origin, f.v);
  f.v_lo = all_lo.z - v0;
  f.v_hi = all_hi.z - v0;
  return f;
}

// Orthographic projection of a rectangle of the frame: clip x, y over it,
// depth from the nearest to the light (largest V) to the farthest.
glm::mat4 ortho(const LightFrame& f, const glm::vec3& origin, const glm::vec2& half) {
  const float v0 = glm::dot(f.origin, f.v);
  const float v_pad = 0.01f * (f.v_hi - f.v_lo) + 1e-4f;
  const float vh = 0.5f * (f.v_hi - f.v_lo) + v_pad, vc = v0 + 0.5f * (f.v_hi + f.v_lo);
  glm::mat4 m(0.0f);
  const glm::vec3 rows[3] = {f.u / half.x, f.w / half.y, -f.v / vh};
  const float offs[3] = {-glm::dot(f.u, origin) / half.x, -glm::dot(f.w, origin) / half.y, vc / vh};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[c][r] = rows[r][c];
    m[3][r] = offs[r];
  }
  m[3][3] = 1.0f;
  return m;
}

}  // namespace

struct CausticMapEngine::Impl {
  struct PerLight {
    int photons = 0, size = 0;
    gl::Texture front_pos, front_nrm, back_pos, back_nrm, caster_depth;
    gl::Texture map, receivers, receiver_depth, scratch, scratch2;
    gl::Texture density;  // adaptive: finest-grid photons per kDensityBlock^2 texels
    bool focus = false;   // the map holds a focus window above the main map (and mips)
    gl::Buffer focus_buffer;  // causticmap_focus.comp's Focus: the window, then the cells' counts
    gl::Texture focus_density;  // photons per kDensityBlock^2 of the window's texels
    gl::Framebuffer caster_fbo, receiver_fbo, splat_fbo;
    gl::Buffer photon_buffer;
    // Adaptive traversal (causticmap_adaptive.comp): coverage pyramid, cell
    // lists (two of `budget`, then the leaves), state and indirect args.
    std::uint32_t levels = 0, budget = 0;
    gl::Buffer pyramid, cells, state;
    std::array<int, 9> offsets{};
    gl::Query capture_q;
    std::vector<gl::Query> photon_q, splat_q;  // one per traced wavelength
    bool valid = false, timed = false;
    double capture_ms = 0, photon_ms = 0, splat_ms = 0;  // the latest timer results ready
    std::uint32_t wavelengths = 1;  // traced by the last update
    Binding binding;
    std::uint64_t bytes = 0;
  };
  std::vector<PerLight> lights;
  std::function<void(std::uint32_t)> draw_object;
  gl::Program capture, photons, splat, density, blur, adaptive, focus;
  // The photon pass that also lands photons on receivers inside glass
  // (CAUSTIX_RECEIVERS_INSIDE), built the first time a receiver's box
  // meets a glass's: the test costs the pass 13 % on llvmpipe even where
  // no glass takes it, so scenes without such a receiver never run it.
  std::optional<gl::Program> photons_inside;
  gl::Buffer materials, counters;
  // The counters of each frame come back through `readback` (never
  // waited on); `counted` holds the latest that arrived, of frame
  // `counted_frame`, and `counting` whether this frame traced photons.
  gl::ReadbackRing readback;
  std::array<std::uint32_t, kCounters> counted{};
  std::uint64_t counted_frame = 0, frame = 0;
  bool counting = false;
  // What each light's map was made from.
  MadeFrom<LightInputs> made;

  // One light's update, pass by pass (update_light): what its passes
  // share -- the frame, the map's and the photon grid's sides, the switches
  // the options set.
  struct LightPass {
    LightFrame frame;
    int size = 0, side = 0, fside = 0;  // caustic map, photon grid, focus window (texels a side)
    bool adaptive = false, focus = false, two_pass = false;
    bool variable = false;  // adaptive one-pass splats sized by the photons' density
    float sigma = 0, texel = 0;
  };
  bool fill_materials(const SceneDesc& scene, const std::vector<bool>& casters, const std::vector<std::array<glm::vec3, 2>>& world_boxes,
                      std::vector<std::array<glm::vec3, 2>>& caster_boxes);
  void capture_surfaces(const SceneDesc& scene, PerLight& pl, const LightPass& lp, const std::vector<bool>& casters);
  Status build_photons_inside();
  void set_uniforms(const SceneDesc& scene, const Light& light, const CausticMapOptions& o, const PerLight& pl, const LightPass& lp,
                    const gl::Program& p);
  void dispatch_photons(const PerLight& pl, const LightPass& lp);
  void draw_photons(const PerLight& pl, const LightPass& lp);
  void trace_photons(PerLight& pl, const LightPass& lp, const gl::Program& p, const glm::vec3& weight, bool place_focus);
  void count_photons(PerLight& pl, const LightPass& lp, GLuint texture, int side_texels, int window);
  void splat_photons(PerLight& pl, const LightPass& lp, GLuint target);
  void blur_map(PerLight& pl, const LightPass& lp);
  void poll() {
    readback.poll([&](std::uint64_t tag, const std::uint8_t* data) {
      std::memcpy(counted.data(), data, sizeof counted);
      counted_frame = tag;
    });
  }
  gl::VertexArray empty_vao;
  std::vector<float> material_data;
  float max_splat_radius = 0;  // texels: (the largest point size - 1) / 2

  // photons_side: the capture's side (a multiple of 2^levels when adaptive).
  void ensure(PerLight& pl, int photons_side, int size, std::uint32_t levels, std::uint32_t budget, bool with_focus) {
    const bool new_side = pl.photons != photons_side;
    if (new_side || pl.levels != levels || pl.budget != budget) {
      pl.levels = levels;
      pl.budget = budget;
      const std::uint64_t slots = levels > 0 ? budget : std::uint64_t(photons_side) * std::uint64_t(photons_side);
      pl.photon_buffer = gl::make_buffer();
      glNamedBufferStorage(pl.photon_buffer.get(), static_cast<GLsizeiptr>(32 * slots), nullptr, 0);
      pl.pyramid = gl::Buffer();
      pl.cells = gl::Buffer();
      pl.state = gl::Buffer();
      if (levels > 0) {
        int total = 0;
        for (std::uint32_t k = 0; k <= levels; ++k) {
          pl.offsets[k] = total;
          total += (photons_side >> k) * (photons_side >> k);
        }
        pl.pyramid = gl::make_buffer();
        glNamedBufferStorage(pl.pyramid.get(), static_cast<GLsizeiptr>(std::size_t{16} * static_cast<std::size_t>(total)), nullptr, 0);
        pl.cells = gl::make_buffer();
        glNamedBufferStorage(pl.cells.get(), static_cast<GLsizeiptr>(std::size_t{12} * budget), nullptr, 0);
        pl.state = gl::make_buffer();
        glNamedBufferStorage(pl.state.get(), kStateBytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
      }
    }
    if (new_side) {
      pl.photons = photons_side;
      pl.front_pos = make_map(photons_side, GL_RGBA32F, GL_NEAREST);
      pl.front_nrm = make_map(photons_side, GL_RGBA32F, GL_NEAREST);
      pl.back_pos = make_map(photons_side, GL_RGBA32F, GL_NEAREST);
      pl.back_nrm = make_map(photons_side, GL_RGBA32F, GL_LINEAR);
      pl.caster_depth = make_map(photons_side, GL_DEPTH_COMPONENT32F, GL_NEAREST);
      pl.caster_fbo = gl::make_framebuffer();
    }
    if (pl.size != size || pl.focus != with_focus) {
      pl.size = size;
      pl.focus = with_focus;
      // With a focus window, mips: its texels are finer than the pixels
      // that usually look at them, and a focus read at one point would
      // flicker as the view moves (as the tables' windows, docs/glass-focus.md).
      int mips = 1;
      while (with_focus && ((size + focus_side(size)) >> mips) > 0) ++mips;
      pl.map = make_map(size, GL_RGBA32F, GL_LINEAR, with_focus ? size + focus_side(size) : size, mips);
      pl.focus_buffer = gl::Buffer();
      pl.focus_density = gl::Texture();
      if (with_focus) {
        pl.focus_buffer = gl::make_buffer();
        glNamedBufferStorage(pl.focus_buffer.get(), kFocusWindowBytes, nullptr, 0);
      }
      pl.receivers = make_map(size, GL_RGBA32F, GL_NEAREST);
      pl.receiver_depth = make_map(size, GL_DEPTH_COMPONENT32F, GL_NEAREST);
      pl.scratch = make_map(size, GL_RGBA32F, GL_NEAREST);
      pl.scratch2 = make_map(size, GL_RGBA32F, GL_NEAREST);
      pl.density = make_map(std::max(1, size / kDensityBlock), GL_R32F, GL_LINEAR);
      pl.receiver_fbo = gl::make_framebuffer();
      glNamedFramebufferTexture(pl.receiver_fbo.get(), GL_COLOR_ATTACHMENT0, pl.map.get(), 0);
      glNamedFramebufferTexture(pl.receiver_fbo.get(), GL_COLOR_ATTACHMENT1, pl.receivers.get(), 0);
      glNamedFramebufferTexture(pl.receiver_fbo.get(), GL_DEPTH_ATTACHMENT, pl.receiver_depth.get(), 0);
      const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
      glNamedFramebufferDrawBuffers(pl.receiver_fbo.get(), 2, bufs);
      pl.splat_fbo = gl::make_framebuffer();
    }
    // The count over the window sizes adaptive leaves' splats only.
    const bool window_density = with_focus && levels > 0;
    if (!window_density) pl.focus_density = gl::Texture();
    else if (!pl.focus_density.get()) pl.focus_density = make_map(std::max(1, focus_side(size) / kDensityBlock), GL_R32F, GL_LINEAR);
    const std::uint64_t p2 = std::uint64_t(photons_side) * std::uint64_t(photons_side), s2 = std::uint64_t(size) * std::uint64_t(size);
    const std::uint64_t dside = std::uint64_t(std::max(1, size / kDensityBlock));
    pl.bytes = p2 * (4 * 16 + 4) + s2 * (4 * 16 + 4) + 4 * dside * dside;
    if (with_focus) {
      // The window's rows, the mips (a third more) and the cells.
      const std::uint64_t rows = std::uint64_t(size) * std::uint64_t(focus_side(size));
      const std::uint64_t fd = std::uint64_t(std::max(1, focus_side(size) / kDensityBlock));
      pl.bytes += 16 * rows + 16 * (s2 + rows) / 3 + kFocusWindowBytes + (window_density ? 4 * fd * fd : 0);
    }
    if (levels > 0) {
      pl.bytes += std::uint64_t{32 + 12} * budget + kStateBytes;
      for (std::uint32_t k = 0; k <= levels; ++k) pl.bytes += 16 * std::uint64_t(photons_side >> k) * std::uint64_t(photons_side >> k);
    } else {
      pl.bytes += 32 * p2;
    }
  }

  // Adaptive caustic maps' traversal (causticmap_adaptive.comp's stages):
  // the leaves into pl.cells' third list, and the photon pass's dispatch
  // and the splats' draw into pl.state.
  void traverse(PerLight& pl) {
    const gl::Program& a = adaptive;
    a.use();
    const int side = pl.photons, L = static_cast<int>(pl.levels);
    a.set("u_side", side);
    a.set("u_levels", L);
    glProgramUniform1iv(a.id(), a.loc("u_offset"), 9, pl.offsets.data());
    a.set("u_budget", static_cast<unsigned>(pl.budget));
    glClearNamedBufferData(pl.state.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glBindTextureUnit(0, pl.front_pos.get());
    glBindTextureUnit(1, pl.front_nrm.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, pl.pyramid.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, pl.cells.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, pl.state.get());
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, pl.state.get());
    // cells 0: over the current list (the indirect arguments stage 3 wrote).
    auto run = [&](int stage, int level, int cur, GLuint cells) {
      a.set("u_stage", stage);
      a.set("u_level", level);
      a.set("u_cur", cur);
      if (cells > 0) glDispatchCompute((cells + 63) / 64, 1, 1);
      else glDispatchComputeIndirect(kDispatchOffset);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    };
    auto cells_at = [&](int k) { return static_cast<GLuint>((side >> k) * (side >> k)); };
    run(0, 0, 0, cells_at(0));
    for (int k = 1; k <= L; ++k) run(1, k, 0, cells_at(k));
    run(2, L, 0, cells_at(L));
    int cur = 0;
    for (int k = L; k >= 0; --k, cur = 1 - cur) {
      run(3, k, cur, 1);
      run(4, k, cur, 0);
      run(5, k, cur, 1);
      run(6, k, cur, 0);
    }
    run(7, 0, 0, 1);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  }

  // Renders objects (casters or receivers) into the bound framebuffer.
  // `active`: CausticMapEngine::casters().
  void draw(const SceneDesc& scene, const glm::mat4& view_proj, bool casters, const std::vector<bool>& active) {
    capture.use();
    capture.set("u_view_proj", view_proj);
    capture.set("u_caster", casters ? 1 : 0);
    for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
      const Object& o = scene.objects[i];
      if (casters ? !active[i] : is_caster(o.role)) continue;
      const glm::mat4 model = glm::make_mat4(o.transform.data());
      capture.set("u_model", model);
      capture.set("u_normal_matrix", glm::mat3(glm::transpose(glm::inverse(model))));
      capture.set("u_object", static_cast<float>(i + 1));
      draw_object(i);
    }
  }
};

Status CausticMapEngine::check(const CausticMapOptions& o) {
  auto bad = [](const std::string& what) { return make_error(ErrorCode::kUsage, "caustic map options: " + what); };
  if (o.photons < 1 || o.photons > 4096) return bad("photons must be 1..4096 (grid side), got " + std::to_string(o.photons));
  if (o.map_size < 16 || o.map_size > 4096) return bad("map_size must be 16..4096, got " + std::to_string(o.map_size));
  if (!(o.splat_sigma >= 0.0f && o.splat_sigma <= 8.0f)) return bad("splat_sigma must be 0..8 texels");
  if (o.iterations < 1 || o.iterations > 64 || o.exit_iterations < 1 || o.exit_iterations > 64) {
    return bad("iterations and exit_iterations must be 1..64");
  }
  if (o.bounces < 1 || o.bounces > 8) return bad("bounces must be 1..8, got " + std::to_string(o.bounces));
  if (!(o.edge_cos >= 0.0f && o.edge_cos <= 1.0f)) return bad("edge_cos must be in [0, 1]");
  if (!(o.max_deviation_deg >= 0.0f && o.max_deviation_deg <= 180.0f)) return bad("max_deviation_deg must be in [0, 180]");
  if (!(o.max_travel >= 0.0f && std::isfinite(o.max_travel))) return bad("max_travel must be finite and >= 0");
  if (o.adaptive_levels > 8) return bad("adaptive_levels must be 0..8, got " + std::to_string(o.adaptive_levels));
  if (o.adaptive_levels > 0) {
    const std::uint32_t coarse = (o.photons + (1u << o.adaptive_levels) - 1) >> o.adaptive_levels;
    if (o.photon_budget > (1u << 24) || o.photon_budget < coarse * coarse) {
      return bad("photon_budget must be " + std::to_string(coarse * coarse) + " (the coarsest level's " + std::to_string(coarse) + "^2 cells) .. " +
                 std::to_string(1u << 24) + ", got " + std::to_string(o.photon_budget));
    }
  }
  return Status::success();
}

std::vector<bool> CausticMapEngine::casters(const SceneDesc& scene, GlassMethod method) {
  const auto inside = receiver_inside_glass(scene);
  std::vector<bool> out(scene.objects.size(), false);
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Role r = scene.objects[i].role;
    // Thin-walled glass has no tables: the caustic maps always carry its light.
    out[i] = is_mirror(r) || is_thin(r) || (is_transparent(r) && (method == GlassMethod::kCausticMap || inside[i].has_value()));
  }
  return out;
}

bool CausticMapEngine::needed(const std::vector<bool>& casters) {
  return std::any_of(casters.begin(), casters.end(), [](bool c) { return c; });
}

CausticMapEngine::~CausticMapEngine() = default;

Result<std::unique_ptr<CausticMapEngine>> CausticMapEngine::create(const SceneDesc& scene, std::function<void(std::uint32_t)> draw_object) {
  std::unique_ptr<CausticMapEngine> e(new CausticMapEngine());
  e->impl_ = std::make_unique<Impl>();
  Impl& s = *e->impl_;
  s.draw_object = std::move(draw_object);
  const std::string photons_src = with_optics(shaders::k_causticmap_photons_comp_glsl);
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs({
      {&s.capture, "causticmap_capture", shaders::k_mesh_vert_glsl, shaders::k_causticmap_capture_frag_glsl},
      {&s.photons, "causticmap_photons", photons_src.c_str()},
      {&s.splat, "causticmap_splat", shaders::k_causticmap_splat_vert_glsl, shaders::k_causticmap_splat_frag_glsl},
      {&s.density, "causticmap_density", shaders::k_causticmap_density_vert_glsl, shaders::k_causticmap_density_frag_glsl},
      {&s.blur, "causticmap_blur", shaders::k_causticmap_blur_comp_glsl},
      {&s.adaptive, "causticmap_adaptive", shaders::k_causticmap_adaptive_comp_glsl},
      {&s.focus, "causticmap_focus", shaders::k_causticmap_focus_comp_glsl},
  }));
  s.lights.resize(scene.lights.size());
  s.made.resize(scene.lights.size());
  // Per object: (kind, ior, receivers may lie inside, 0), (absorption or reflectance, 0), (glass:
  // the tint at a crossing, Material::tint, 0); kind is set per update
  // (glass counts only with caustic maps).
  s.material_data.assign(scene.objects.size() * kMaterialFloats, 0.0f);
  s.materials = gl::make_buffer();
  glNamedBufferStorage(s.materials.get(), static_cast<GLsizeiptr>(std::max<std::size_t>(s.material_data.size(), kMaterialFloats) * 4), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  s.counters = gl::make_buffer();
  glNamedBufferStorage(s.counters.get(), kCounters * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  glClearNamedBufferData(s.counters.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  s.readback.reserve(kCounters * 4);
  s.empty_vao = gl::make_vertex_array();
  GLfloat point_range[2] = {1, 1};
  glGetFloatv(GL_POINT_SIZE_RANGE, point_range);
  s.max_splat_radius = std::max(0.0f, std::floor((point_range[1] - 1.0f) / 2.0f));
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("caustic maps set-up"));
  return e;
}

// Fills the photon pass's material of every object (0 where it casts
// nothing) and gives the casters' boxes; true where a receiver's box meets
// a casting glass's, so that the photons look for a receiver inside it
// before the exit (only scenes with one pay).
bool CausticMapEngine::Impl::fill_materials(const SceneDesc& scene, const std::vector<bool>& casters,
                                            const std::vector<std::array<glm::vec3, 2>>& world_boxes,
                                            std::vector<std::array<glm::vec3, 2>>& caster_boxes) {
  bool any_inside = false;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    const Object& obj = scene.objects[i];
    const bool active = casters[i];
    float* md = &material_data[kMaterialFloats * i];
    md[0] = !active ? 0.0f : is_mirror(obj.role) ? 2.0f : is_thin(obj.role) ? 3.0f : 1.0f;
    md[1] = obj.material.ior;
    md[2] = 0.0f;
    for (std::uint32_t j = 0; active && is_transparent(obj.role) && j < scene.objects.size(); ++j) {
      const auto &a = world_boxes[i], &b = world_boxes[j];
      if (j != i && is_receiver(scene.objects[j].role) && glm::all(glm::lessThanEqual(a[0], b[1])) &&
          glm::all(glm::lessThanEqual(b[0], a[1]))) {
        md[2] = 1.0f;
        any_inside = true;
      }
    }
    const Vec3f& c = is_mirror(obj.role) ? obj.material.reflectance : obj.material.absorption;
    for (std::size_t k = 0; k < 3; ++k) {
      md[4 + k] = c[k];
      md[8 + k] = obj.material.tint[k];
    }
    if (active) caster_boxes.push_back(world_boxes[i]);
  }
  return any_inside;
}

// The receivers into the caustic map's alpha (their V) and the receiver
// map, then the casters' nearest and farthest surfaces (positions and
// normals) over the photons' grid.
void CausticMapEngine::Impl::capture_surfaces(const SceneDesc& scene, PerLight& pl, const LightPass& lp, const std::vector<bool>& casters) {
  const LightFrame& f = lp.frame;
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glEnable(GL_DEPTH_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  capture.set("u_origin", f.origin);
  capture.set("u_v", f.v);
  const float zero[4] = {0, 0, 0, -1e30f};
  const float none[4] = {0, 0, 0, -1e30f};
  glBindFramebuffer(GL_FRAMEBUFFER, pl.receiver_fbo.get());
  glViewport(0, 0, lp.size, lp.size);
  glClearTexImage(pl.map.get(), 0, GL_RGBA, GL_FLOAT, zero);  // the window's rows too (outside the framebuffer's size x size)
  glClearNamedFramebufferfv(pl.receiver_fbo.get(), GL_COLOR, 1, none);
  glClearNamedFramebufferfi(pl.receiver_fbo.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glDepthFunc(GL_LESS);
  draw(scene, ortho(f, f.origin, f.map_half), false, casters);
  glBindFramebuffer(GL_FRAMEBUFFER, pl.caster_fbo.get());
  glViewport(0, 0, lp.side, lp.side);
  const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  const float empty[4] = {0, 0, 0, 0};
  for (int layer = 0; layer < 2; ++layer) {
    glNamedFramebufferTexture(pl.caster_fbo.get(), GL_COLOR_ATTACHMENT0, (layer ? pl.back_pos : pl.front_pos).get(), 0);
    glNamedFramebufferTexture(pl.caster_fbo.get(), GL_COLOR_ATTACHMENT1, (layer ? pl.back_nrm : pl.front_nrm).get(), 0);
    glNamedFramebufferTexture(pl.caster_fbo.get(), GL_DEPTH_ATTACHMENT, pl.caster_depth.get(), 0);
    glNamedFramebufferDrawBuffers(pl.caster_fbo.get(), 2, bufs);
    glClearNamedFramebufferfv(pl.caster_fbo.get(), GL_COLOR, 0, empty);
    glClearNamedFramebufferfv(pl.caster_fbo.get(), GL_COLOR, 1, empty);
    glClearNamedFramebufferfi(pl.caster_fbo.get(), GL_DEPTH_STENCIL, 0, layer ? 0.0f : 1.0f, 0);
    glDepthFunc(layer ? GL_GREATER : GL_LESS);
    draw(scene, ortho(f, f.caster_origin, f.caster_half), true, casters);
  }
  glDepthFunc(GL_LESS);
}

// The photon pass that also looks for receivers inside glass, built the
// first time a scene needs it.
Status CausticMapEngine::Impl::build_photons_inside() {
  if (photons_inside) return Status::success();
  const std::string src = with_optics(shaders::k_causticmap_photons_comp_glsl);
  auto built = gl::Program::build_compute("causticmap_photons (receivers inside glass)",
                                          insert_after_version(src.c_str(), "#define CAUSTIX_RECEIVERS_INSIDE\n").c_str());
  if (!built) return built.error();
  photons_inside = std::move(*built);
  return Status::success();
}

// What every wavelength shares: the photon, splat and focus programs'
// uniforms but the photons' weight.
void CausticMapEngine::Impl::set_uniforms(const SceneDesc& scene, const Light& light, const CausticMapOptions& o, const PerLight& pl,
                                          const LightPass& lp, const gl::Program& p) {
  const LightFrame& f = lp.frame;
  const bool directional = light.type == LightType::kDirectional;
  p.set("u_photons", lp.side);
  p.set("u_adaptive", lp.adaptive ? 1 : 0);
  glProgramUniform1iv(p.id(), p.loc("u_offset"), 9, pl.offsets.data());
  p.set("u_budget", static_cast<unsigned>(pl.budget));
  p.set("u_u", f.u);
  p.set("u_v", f.v);
  p.set("u_w", f.w);
  p.set("u_caster_origin", f.caster_origin);
  p.set("u_caster_half", f.caster_half);
  p.set("u_map_origin", f.origin);
  p.set("u_map_half", f.map_half);
  p.set("u_light_type", directional ? 1 : 2);
  p.set("u_light_dir", glm::normalize(to_glm(light.direction)));
  p.set("u_light_pos", to_glm(light.position));
  p.set("u_light_power", directional ? light.irradiance : light.intensity);
  const auto cone = spot_terms(light);
  p.set("u_spot", glm::vec3(cone[0], cone[1], cone[2]));
  p.set("u_iterations", static_cast<int>(o.iterations));
  p.set("u_exit_iterations", static_cast<int>(o.exit_iterations));
  p.set("u_bounces", static_cast<int>(o.bounces));
  p.set("u_mirrors", std::any_of(scene.objects.begin(), scene.objects.end(), [](const Object& obj) { return is_mirror(obj.role); }) ? 1 : 0);
  p.set("u_tir_one_sided", o.tir_one_sided ? 1 : 0);
  p.set("u_edge_cos", o.edge_cos);
  p.set("u_max_deviation_cos", std::cos(glm::radians(o.max_deviation_deg)));
  p.set("u_max_travel", o.max_travel > 0 ? o.max_travel : f.diagonal);
  p.set("u_tolerance", 2.0f * lp.texel * 3.73f + 1e-4f * f.diagonal);
  splat.set("u_max_radius", max_splat_radius);
  splat.set("u_variable", lp.variable ? 1 : 0);
  splat.set("u_block", static_cast<float>(kDensityBlock));
  splat.set("u_texel_area", 4.0f * f.map_half.x * f.map_half.y / static_cast<float>(lp.size * lp.size));
  splat.set("u_v", f.v);
  splat.set("u_main_size", static_cast<float>(lp.size));
  splat.set("u_window_size", static_cast<float>(lp.fside));
  splat.set("u_window_sigma", lp.sigma);
  splat.set("u_grid", lp.adaptive ? 0 : lp.side);
  if (lp.focus) {
    // The focus cells' threshold: the photons (finest-grid units) a cell
    // catches straight from the light, times kFocusConcentration.
    const float photon_area = 4.0f * f.caster_half.x * f.caster_half.y / static_cast<float>(lp.side * lp.side);
    const float cell_area = 4.0f * f.map_half.x * f.map_half.y / static_cast<float>(kFocusBins * kFocusBins);
    focus.set("u_photons", lp.side);
    focus.set("u_adaptive", lp.adaptive ? 1 : 0);
    const float min_count = std::max(kFocusMinPhotons, kFocusConcentration * cell_area / photon_area);
    focus.set("u_min_count", min_count);
    splat.set("u_min_count", min_count);
    focus.set("u_min_half", kFocusMinHalf);
    focus.set("u_max_half", kFocusMaxHalf);
    glProgramUniform2i(focus.id(), focus.loc("u_params"), lp.size - 1, lp.size + lp.fside - 1);
  }
}

// One dispatch over the photons: the adaptive traversal's leaves, or the
// whole grid.
void CausticMapEngine::Impl::dispatch_photons(const PerLight& pl, const LightPass& lp) {
  if (lp.adaptive) {
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, pl.state.get());
    glDispatchComputeIndirect(kPhotonDispatchOffset);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  } else {
    const GLuint groups = static_cast<GLuint>((lp.side + 7) / 8);
    glDispatchCompute(groups, groups, 1);
  }
}

// One point per photon: the adaptive traversal's leaves, or the grid.
void CausticMapEngine::Impl::draw_photons(const PerLight& pl, const LightPass& lp) {
  if (lp.adaptive) {
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, pl.state.get());
    glDrawArraysIndirect(GL_POINTS, reinterpret_cast<const void*>(kDrawOffset));
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  } else {
    glDrawArrays(GL_POINTS, 0, lp.side * lp.side);
  }
}

// Traces one wavelength's photons (weighted by its bin's RGB) and, with
// `place_focus`, places the focus window from where they landed.
void CausticMapEngine::Impl::trace_photons(PerLight& pl, const LightPass& lp, const gl::Program& p, const glm::vec3& weight,
                                           bool place_focus) {
  p.use();
  p.set("u_weight", weight);
  glBindTextureUnit(0, pl.front_pos.get());
  glBindTextureUnit(1, pl.front_nrm.get());
  glBindTextureUnit(2, pl.back_pos.get());
  glBindTextureUnit(3, pl.back_nrm.get());
  glBindTextureUnit(4, pl.receivers.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, pl.photon_buffer.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, materials.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, counters.get());
  if (!lp.adaptive) {
    // The adaptive blocks are not read; any buffer keeps them bound.
    for (GLuint b : {3u, 4u, 5u}) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, counters.get());
  }
  dispatch_photons(pl, lp);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  if (!place_focus) return;
  focus.use();
  glClearNamedBufferData(pl.focus_buffer.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, pl.focus_buffer.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, lp.adaptive ? pl.state.get() : counters.get());
  glBindImageTexture(0, pl.map.get(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  focus.set("u_stage", 0);
  dispatch_photons(pl, lp);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  focus.set("u_stage", 1);
  glDispatchCompute(1, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                  GL_FRAMEBUFFER_BARRIER_BIT);
}

// Photons counted into a density texture of `side_texels` texels (over the
// main map, or over the focus window: causticmap_density.vert).
void CausticMapEngine::Impl::count_photons(PerLight& pl, const LightPass& lp, GLuint texture, int side_texels, int window) {
  const float no_photons[4] = {0, 0, 0, 0};
  glClearTexImage(texture, 0, GL_RGBA, GL_FLOAT, no_photons);
  glNamedFramebufferTexture(pl.splat_fbo.get(), GL_COLOR_ATTACHMENT0, texture, 0);
  glNamedFramebufferDrawBuffer(pl.splat_fbo.get(), GL_COLOR_ATTACHMENT0);
  glBindFramebuffer(GL_FRAMEBUFFER, pl.splat_fbo.get());
  glViewport(0, 0, side_texels, side_texels);
  glBlendFunc(GL_ONE, GL_ONE);
  density.use();
  density.set("u_window", window);
  draw_photons(pl, lp);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
}

// Splats the photons into `target` (the caustic map in one pass, or the
// two-pass blur's scratch at one texel each), and the focus window's share
// into its texels above the main map.
void CausticMapEngine::Impl::splat_photons(PerLight& pl, const LightPass& lp, GLuint target) {
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glEnable(GL_PROGRAM_POINT_SIZE);
  glBindVertexArray(empty_vao.get());
  // Adaptive one-pass splats size themselves by the landed photons'
  // density: count them first.
  if (lp.variable) count_photons(pl, lp, pl.density.get(), std::max(1, lp.size / kDensityBlock), 0);
  // The focus window's share of each photon (causticmap_splat.vert): for
  // adaptive leaves from the photons counted over the window.
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, lp.focus ? pl.focus_buffer.get() : counters.get());
  if (lp.focus && lp.adaptive) count_photons(pl, lp, pl.focus_density.get(), std::max(1, lp.fside / kDensityBlock), 1);
  glNamedFramebufferTexture(pl.splat_fbo.get(), GL_COLOR_ATTACHMENT0, target, 0);
  glNamedFramebufferDrawBuffer(pl.splat_fbo.get(), GL_COLOR_ATTACHMENT0);
  glBindFramebuffer(GL_FRAMEBUFFER, pl.splat_fbo.get());
  glViewport(0, 0, lp.size, lp.size);
  glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ZERO, GL_ONE);  // alpha keeps the receivers' V
  splat.use();
  glBindTextureUnit(0, pl.receivers.get());
  glBindTextureUnit(1, pl.density.get());
  glBindTextureUnit(2, pl.focus_density.get() ? pl.focus_density.get() : pl.density.get());
  splat.set("u_focus", lp.focus ? 1 : 0);
  splat.set("u_window", 0);
  splat.set("u_size", static_cast<float>(lp.size));
  splat.set("u_sigma", lp.two_pass ? 0.0f : lp.sigma);
  splat.set("u_origin", glm::vec2(0.0f));
  draw_photons(pl, lp);
  if (lp.focus) {
    // One-pass Gaussians in the window (also with the two-pass blur, which
    // covers the main map only).
    glNamedFramebufferTexture(pl.splat_fbo.get(), GL_COLOR_ATTACHMENT0, pl.map.get(), 0);
    glViewport(0, lp.size, lp.fside, lp.fside);
    splat.set("u_window", 1);
    splat.set("u_size", static_cast<float>(lp.fside));
    splat.set("u_sigma", lp.sigma);
    splat.set("u_origin", glm::vec2(0.0f, static_cast<float>(lp.size)));
    draw_photons(pl, lp);
  }
  glDisable(GL_PROGRAM_POINT_SIZE);
  glDisable(GL_BLEND);
}

// The two-pass splats' separable Gaussian, scratch -> scratch2 -> map.
void CausticMapEngine::Impl::blur_map(PerLight& pl, const LightPass& lp) {
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
  blur.use();
  blur.set("u_sigma", lp.sigma);
  const GLuint g = static_cast<GLuint>((lp.size + 7) / 8);
  for (int axis = 0; axis < 2; ++axis) {
    blur.set("u_axis", axis);
    glBindTextureUnit(0, axis == 0 ? pl.scratch.get() : pl.scratch2.get());
    glBindTextureUnit(1, pl.map.get());
    glBindImageTexture(0, axis == 0 ? pl.scratch2.get() : pl.map.get(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(g, g, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
}

Status CausticMapEngine::update_light(const SceneDesc& scene, std::uint32_t li, const CausticsOptions& options,
                                      const std::vector<std::array<glm::vec3, 2>>& world_boxes, const std::vector<bool>& casters,
                                      const SceneVersions& versions, bool due, EffectWork& work) {
  Impl& s = *impl_;
  const LightInputs key{SceneVersions{versions.light, versions.transforms, 0}, options};  // not the water's
  if (s.made.decide(li, key, due, work) != Refresh::kRemake) return Status::success();
  s.made.made(li, key);
  Impl::PerLight& pl = s.lights[li];
  const CausticMapOptions& o = options.caustic_map;
  pl.valid = false;
  std::vector<std::array<glm::vec3, 2>> caster_boxes;
  const bool any_inside = s.fill_materials(scene, casters, world_boxes, caster_boxes);
  if (caster_boxes.empty()) return Status::success();
  glNamedBufferSubData(s.materials.get(), 0, static_cast<GLsizeiptr>(s.material_data.size() * 4), s.material_data.data());

  const Light& light = scene.lights[li];
  Impl::LightPass lp;
  lp.size = static_cast<int>(o.map_size);
  const std::uint32_t cell = 1u << o.adaptive_levels;
  lp.side = static_cast<int>((o.photons + cell - 1) / cell * cell);
  lp.fside = focus_side(lp.size);
  lp.adaptive = o.adaptive_levels > 0;
  lp.focus = o.focus;
  lp.sigma = o.splat_sigma;
  lp.two_pass = o.two_pass && lp.sigma > 0;
  lp.variable = lp.adaptive && !lp.two_pass;
  lp.frame = light_frame(light, world_boxes, caster_boxes, lp.size, lp.side);
  const LightFrame& f = lp.frame;
  // A landing point must lie on the receiver texel it projects into: within
  // two texels' run along V on a surface tilted up to 75 degrees.
  lp.texel = 2.0f * std::max(f.map_half.x, f.map_half.y) / static_cast<float>(lp.size);
  s.ensure(pl, lp.side, lp.size, o.adaptive_levels, o.photon_budget, o.focus);

  // Dispersion: the photons and their splats once per traced wavelength,
  // every glass index at n(lambda) and each photon's power times its bin's
  // RGB weights; the splats add up in the one map.
  const std::vector<WavelengthSample> waves = traced_wavelengths(scene, options);
  if (!pl.capture_q.get()) pl.capture_q = gl::make_query(GL_TIME_ELAPSED);
  while (pl.photon_q.size() < waves.size()) {
    pl.photon_q.push_back(gl::make_query(GL_TIME_ELAPSED));
    pl.splat_q.push_back(gl::make_query(GL_TIME_ELAPSED));
  }
  pl.wavelengths = static_cast<std::uint32_t>(waves.size());
  glBeginQuery(GL_TIME_ELAPSED, pl.capture_q.get());
  std::optional<gl::TimedPass> timed;
  timed.emplace("caustic maps: capture", gl::PassKind::kRaster);
  s.capture_surfaces(scene, pl, lp, casters);
  glEndQuery(GL_TIME_ELAPSED);

  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
  s.counting = true;
  timed.reset();
  if (lp.adaptive) {
    const gl::TimedPass traversal("caustic maps: adaptive traversal", gl::PassKind::kCompute);
    s.traverse(pl);  // over the casters' coverage, the same at every wavelength
  }
  GLuint target = pl.map.get();
  if (lp.two_pass) {
    target = pl.scratch.get();
    const float clear[4] = {0, 0, 0, 0};
    glClearTexImage(target, 0, GL_RGBA, GL_FLOAT, clear);
  }
  if (any_inside) CAUSTIX_RETURN_IF_ERROR(s.build_photons_inside());
  const gl::Program& p = any_inside ? *s.photons_inside : s.photons;
  s.set_uniforms(scene, light, o, pl, lp, p);
  for (std::size_t k = 0; k < waves.size(); ++k) {
    if (waves.size() > 1 || options.wavelength_nm) {
      for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
        const Material& m = scene.objects[i].material;
        s.material_data[kMaterialFloats * i + 1] = index_at(m.ior, m.dispersion, waves[k].nm);
      }
      glNamedBufferSubData(s.materials.get(), 0, static_cast<GLsizeiptr>(s.material_data.size() * 4), s.material_data.data());
    }
    glBeginQuery(GL_TIME_ELAPSED, pl.photon_q[k].get());
    timed.emplace("caustic maps: photons", gl::PassKind::kCompute);
    // The focus window from where the first wavelength's photons landed
    // (the others' focus lies within its margin).
    s.trace_photons(pl, lp, p, glm::vec3(waves[k].rgb[0], waves[k].rgb[1], waves[k].rgb[2]), lp.focus && k == 0);
    glEndQuery(GL_TIME_ELAPSED);

    glBeginQuery(GL_TIME_ELAPSED, pl.splat_q[k].get());
    timed.emplace("caustic maps: splats", gl::PassKind::kRaster);
    s.splat_photons(pl, lp, target);
    if (k + 1 < waves.size()) {
      glEndQuery(GL_TIME_ELAPSED);
      // The next wavelength's photons overwrite the buffer these splats read.
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
  }
  if (lp.two_pass) {
    timed.emplace("caustic maps: blur", gl::PassKind::kCompute);
    s.blur_map(pl, lp);
  }
  if (lp.focus) {
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glGenerateTextureMipmap(pl.map.get());
  }
  glEndQuery(GL_TIME_ELAPSED);
  timed.reset();
  pl.timed = true;

  Binding& b = pl.binding;
  b.frame.origin = {f.origin.x, f.origin.y, f.origin.z};
  b.frame.u = to_vec3f(f.u);
  b.frame.v = to_vec3f(f.v);
  b.frame.w = to_vec3f(f.w);
  b.frame.half = {f.map_half.x, 0.5f * (f.v_hi - f.v_lo), f.map_half.y};
  b.map = pl.map.get();
  const float n = static_cast<float>(lp.size);
  b.texel_diagonal = 0.5f * std::hypot(2.0f * f.map_half.x / n, 2.0f * f.map_half.y / n);
  b.tolerance = lp.texel + 1e-4f * f.diagonal;
  b.main_share = lp.focus ? static_cast<float>(lp.size) / static_cast<float>(lp.size + lp.fside) : 1.0f;
  pl.valid = true;
  return gl::check_gl("caustic map");
}

void CausticMapEngine::clear(std::uint32_t light) {
  if (light >= impl_->lights.size()) return;
  impl_->lights[light].valid = false;
  impl_->made.forget(light);
}

std::optional<CausticMapEngine::Binding> CausticMapEngine::binding(std::uint32_t light) const {
  if (light >= impl_->lights.size() || !impl_->lights[light].valid) return std::nullopt;
  return impl_->lights[light].binding;
}

void CausticMapEngine::begin_frame(std::uint64_t frame) {
  Impl& s = *impl_;
  s.poll();
  s.frame = frame;
  s.counting = false;
  glClearNamedBufferData(s.counters.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
}

void CausticMapEngine::end_frame() {
  Impl& s = *impl_;
  if (!s.counting || !s.readback.begin()) return;
  s.readback.copy(s.counters.get(), 0, 0, kCounters * 4);
  s.readback.end(s.frame);
}

namespace {

// A timer query's milliseconds: waiting for it, or only if it is ready.
std::optional<double> query_ms(GLuint q, bool wait) {
  GLint ready = GL_FALSE;
  if (!wait) glGetQueryObjectiv(q, GL_QUERY_RESULT_AVAILABLE, &ready);
  if (!wait && !ready) return std::nullopt;
  GLuint64 ns = 0;
  glGetQueryObjectui64v(q, wait ? GL_QUERY_RESULT : GL_QUERY_RESULT_NO_WAIT, &ns);
  return static_cast<double>(ns) * 1e-6;
}

}  // namespace

CausticMapStats CausticMapEngine::stats(bool wait) {
  Impl& s = *impl_;
  CausticMapStats st;
  st.gpu_bytes = gpu_bytes();
  for (const auto& pl : s.lights) {
    st.active = st.active || pl.valid;
    if (pl.valid) st.wavelengths = std::max(st.wavelengths, pl.wavelengths);
  }
  if (!st.active) return st;
  if (wait && s.readback.pending()) s.readback.wait();
  s.poll();
  const auto& c = s.counted;
  st.counters_frame = s.counted_frame;
  st.photons = c[0];
  st.landed = c[1];
  st.tir = c[2];
  st.edge_dropped = c[3];
  st.deviation_dropped = c[4];
  st.too_far = c[5];
  st.lost = c[6];
  st.reflections = c[7];
  st.tir_dropped = c[8];
  st.out_of_bounces = c[9];
  for (auto& pl : s.lights) {
    if (!pl.valid) continue;
    if (wait) {
      // The photons themselves: their landed power and the adaptive
      // traversal's levels (read back: a stall, asked for).
      std::size_t slots = std::size_t(pl.photons) * std::size_t(pl.photons);
      if (pl.levels > 0) {
        std::uint32_t leaves = 0;
        glGetNamedBufferSubData(pl.state.get(), 8, 4, &leaves);
        slots = leaves;
        std::vector<std::uint32_t> cells(leaves);
        glGetNamedBufferSubData(pl.cells.get(), static_cast<GLintptr>(std::size_t{8} * pl.budget), static_cast<GLsizeiptr>(4 * cells.size()), cells.data());
        for (std::uint32_t cell : cells) ++st.photons_per_level[std::min<std::uint32_t>(cell >> 24, 8)];
      }
      std::vector<float> ph(std::size_t{8} * slots);
      glGetNamedBufferSubData(pl.photon_buffer.get(), 0, static_cast<GLsizeiptr>(ph.size() * 4), ph.data());
      for (std::size_t i = 0; i < ph.size(); i += 8) {
        if (ph[i + 7] > 0) st.landed_power += 0.2126 * ph[i + 4] + 0.7152 * ph[i + 5] + 0.0722 * ph[i + 6];
      }
      st.focus = {0, 0, 0};
      if (pl.focus) {
        float w[4] = {0, 0, 0, 0};
        glGetNamedBufferSubData(pl.focus_buffer.get(), 0, sizeof w, w);
        st.focus = {w[0], w[1], w[2]};
      }
    }
    if (pl.timed) {
      // The latest light's times, kept until newer ones are ready.
      if (const auto ms = query_ms(pl.capture_q.get(), wait)) pl.capture_ms = *ms;
      double photon = 0, splat = 0;
      bool ready = true;
      for (std::uint32_t k = 0; k < pl.wavelengths && ready; ++k) {
        const auto a = query_ms(pl.photon_q[k].get(), wait), b = query_ms(pl.splat_q[k].get(), wait);
        ready = a && b;
        if (ready) {
          photon += *a;
          splat += *b;
        }
      }
      if (ready) {
        pl.photon_ms = photon;
        pl.splat_ms = splat;
      }
      st.capture_ms = pl.capture_ms;
      st.photon_ms = pl.photon_ms;
      st.splat_ms = pl.splat_ms;
    }
  }
  return st;
}

std::uint64_t CausticMapEngine::times_made(std::uint32_t li) const { return impl_->made.times_made(li); }

std::uint64_t CausticMapEngine::gpu_bytes() const {
  std::uint64_t b = impl_->readback.gpu_bytes() + kCounters * 4 + impl_->material_data.size() * 4;
  for (const auto& pl : impl_->lights) b += pl.bytes;
  return b;
}

}  // namespace caustix::runtime
