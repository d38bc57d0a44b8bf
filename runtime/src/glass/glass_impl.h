#pragma once
// GlassEngine's insides, shared by its sources: glass.cpp (the light side:
// tables, exit rays, virtual planes, illumination textures; Iwasaki et al. §4),
// glass_focus.cpp (the focus windows over concentrated light) and
// glass_view.cpp (the view through the glass, draw_glass; Iwasaki et al. §3 and
// timofy 2009's nearby-geometry refraction). Internal to the runtime.

#include "glass.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "caustix/formats/frame.h"
#include "caustix/formats/spectrum.h"
#include "focus_window.h"
#include "pass_timer.h"
#include "shader_text.h"

namespace caustix::runtime {
namespace {

constexpr std::uint32_t kMaxGlassPlanes = 16;  // u_glass_plane_v[16] in the shaders
constexpr std::size_t kPrimitiveBytes = 6 * 16;
// Per glass vertex and traced wavelength (glass_rays.comp): its exit ray,
// direction and colour, and those of the other path class in its table's
// stencil with the distance to their switch: 6 vec4.
constexpr std::size_t kRayBytes = 6 * 16;
// The CPU sample of each glass's n_d table (Glass::sample): about 4 MB of
// rows (655 vertices at the default 20 x 20 directions), never fewer than
// 64 vertices.
constexpr std::size_t kSampleBytes = 4u << 20;
constexpr std::size_t kMinSampleVertices = 64;
// Focus windows: the sampled exit rays are binned over the
// target's frame in kFocusBins x kFocusBins cells per plane; a cell is
// concentrated where the flux landing in it is at least
// kFocusConcentration times the incident irradiance over its area, from at
// least kFocusMinRays sampled rays (a cell of a flat pane gets T^2, about
// 0.92; the sampling stride alone can put two or three rays in a cell).
// The window is the square around the concentrated cells and one cell
// more, no larger than kFocusMaxHalf of the frame (else the main texture
// does nearly as well) and no smaller than kFocusMinHalf (at most 42
// times the main texture's resolution, with kFocusTexels). The caustic
// maps' windows use the same constants (gl/focus_window.h).
constexpr int kFocusBins = focus::kBins;
constexpr double kFocusConcentration = focus::kConcentration;
constexpr int kFocusMinRays = focus::kMinSamples;
constexpr float kFocusMaxHalf = focus::kMaxHalf;
constexpr float kFocusMinHalf = focus::kMinHalf;
// The window's texels per side, as a fraction of the main texture's: its
// layers hold it in their lower corner. A full layer would cost the
// illumination pass several times its time for little more of the focus
// (docs/glass-focus.md measures both). 0.65 rather than the caustic maps'
// half: by the tent (CausticsOptions::glass_focus_tent) a focus spreads by
// a texel more, and at 0.65 it is sharper than it was at a half by the
// box; beside it there is still room for a coarse window at half its
// texels (0.65 + 0.325 < 1, window_squares).
constexpr float kFocusTexels = 0.65f;

inline glm::mat4 to_glm(const Mat4f& m) { return glm::make_mat4(m.data()); }

// model = T R s for a similarity transform (validate_scene enforces it).
inline void decompose(const Mat4f& t, glm::mat3& rotation, float& scale) {
  const glm::mat3 m(to_glm(t));
  scale = glm::length(m[0]);
  rotation = m / scale;
}

}  // namespace

struct GlassEngine::Impl {
  struct Table {
    LightTransportTable params;  // words and switches dropped after upload
    gl::Buffer buffer;           // the entries, then the switch bytes (LTTW) if any
    std::uint32_t switch_base = 0;  // the switches' first word in the buffer; 0: none
  };
  // What every object on one table shares (objects that use
  // another's tables, Object::tables_from, draw from the same buffers).
  struct Tables {
    // By ascending IOR: the table at n_d (LTTB) and, for dispersive glass,
    // those at other wavelengths (LTTS).
    std::vector<Table> tables;
    std::size_t base = 0;  // the n_d table's place
    // Each vertex's one-ring of triangles (CSR): offsets (vertices + 1),
    // triangle indices (glass_corner_intensity.comp).
    gl::Buffer ring_offsets, ring_triangles;
    // A CPU copy of the n_d table's rows of every k-th vertex, with their
    // positions and normals: what the mean transmitted direction is
    // estimated from without reading the GPU's rays back (mean_travel).
    LightTransportTable sample;
    std::vector<std::array<float, 3>> sample_positions, sample_normals;
    // Each sampled vertex's share of the surface (a third of its one-ring's
    // area, object space) times the sampling stride: the surface it stands
    // for.
    std::vector<float> sample_areas;
    std::uint64_t gpu_bytes = 0;  // the tables and the one-rings
  };
  struct Glass {
    std::uint32_t object = 0;
    const GpuMesh* mesh = nullptr;
    const Tables* shared = nullptr;  // in table_sets
    std::uint32_t vertices = 0, triangles = 0;
    gl::Buffer rays, rays_b;  // this object's exit rays; rays_b: the second table's, dispersive glass only
  };
  std::vector<std::unique_ptr<Tables>> table_sets;
  // A sampled vertex's exit ray for one light, in world space: `flux` is
  // what it carries per unit incident irradiance (its surface share,
  // projected towards the light, times T).
  struct SampledRay {
    glm::vec3 exit, direction;
    float transmittance, flux;
    std::uint32_t object;
  };
  struct Target {
    std::uint32_t object = 0, light = 0;
    int size = 0;
    std::uint32_t planes = 0;
    gl::Texture target, depth, illumination;
    gl::Framebuffer fbo;
    BoundingFrame frame;
    std::vector<float> plane_v;
    // The focus window: centre u, v and half-size in the main
    // texture's coordinates; half-size 0 without one. The illumination
    // texture holds 2 x planes layers once a window was needed (`layers`).
    std::array<float, 3> focus{0, 0, 0};
    std::uint32_t layers = 0;
    int levels = 1;  // mips with focus layers
    // The target's plane normal if it is flat (world), for the transform it
    // was found at: flatness does not change as an object moves rigidly,
    // so the O(vertices) test runs again only when the transform does.
    std::optional<Vec3d> flat_normal;
    std::optional<Mat4f> flat_checked_at;
    bool valid = false;
  };
  std::vector<Glass> glass;
  // Thin-walled glass (Role::kThin): no tables; the caustic maps
  // carry its light, and the view draws it (glass_thin.frag).
  struct Thin {
    std::uint32_t object = 0;
    const GpuMesh* mesh = nullptr;
  };
  std::vector<Thin> thin;
  std::vector<Target> targets;
  std::function<void(std::uint32_t)> draw_object;
  gl::Program rays, rays_blend, geometry, corner_intensity, target_program, illumination, illumination_wide, window_resolve, surface,
      back_faces, nearby, thin_view;
  // GlassView::kNearby: the glass's nearest back faces seen from the camera
  // (world position, outward normal), over the glass's window.
  gl::Texture back_position, back_normal, back_depth;
  gl::Framebuffer back_fbo;
  int back_w = 0, back_h = 0;
  // The view is drawn into a target over the glass's rectangle of the
  // frame (its window), sampling the caller's scene directly, then copied
  // into the caller's framebuffer: memory follows the glass's size on
  // screen, not the frame's.
  gl::Texture window_color, window_depth;
  gl::Framebuffer window_fbo;
  int window_w = 0, window_h = 0;
  gl::Program composite;
  gl::Buffer primitives;  // the illumination volumes' intersections, target after target
  std::uint64_t primitive_capacity = 0;
  gl::Sampler nearest;  // the caller's textures read texel by texel, whatever their own parameters
  gl::VertexArray empty_vao;
  bool spectral = false;  // some glass has tables at other wavelengths
  // What each light's textures were made from.
  MadeFrom<LightInputs> made;
  std::uint32_t traced = 1;  // wavelengths of the last update

  // The exit rays of the sampled vertices that face `light` and pass it
  // (the n_d table looked up as the GPU does: formats' lookup(), which
  // transport.glsl mirrors), in world space. Computed on the CPU from a
  // sample, so that no frame waits for the GPU's rays; they
  // orient the planes (mean_travel) and place the focus windows
  // (focus_window), and change neither image's light.
  std::vector<SampledRay> sampled_rays(const SceneDesc& scene, const Light& light) const;
  // The average direction of the transmitted light (Iwasaki et al. §4.2: "We set
  // a virtual camera so that the viewing direction is parallel to the
  // average direction of the transmitted lights"), unnormalised: the
  // sampled exit directions weighted by their Fresnel transmittance. An
  // estimate; it only orients the planes.
  static Vec3d mean_travel(const std::vector<SampledRay>& rays);
  // Iwasaki et al. gives every plane one texture over the whole target
  // (512^2: 7.8 mm texels over glass_ball's 4 m floor), and a ball lens
  // puts most of its light within a centimetre of its focus, so the focal
  // spot was a texel wide and its peak an eighth of the optics'. Here the
  // window is fitted to where the light lands concentrated (constants
  // above): the sampled rays cut with each plane, binned over the frame.
  // Returns {centre u, centre v, half-size} in texture coordinates, or a
  // zero half-size where nothing concentrates (a pane, a prism: no
  // window, no cost).
  // A glass in `skip` sends no light here (the caustic maps carry it).
  // `previous` is the target's last window, kept while it still serves
  // (hysteresis: glass_focus.cpp); `size` is the main texture's side.
  static std::array<float, 3> focus_window(const Target& t, const std::vector<SampledRay>& rays, const std::vector<bool>& skip,
                                           const std::array<float, 3>& previous, int size);
  // What the surface's tint leaves of light through the glass: in and out, tint^2.
  static glm::vec3 transmit(const Material& m) {
    const glm::vec3 t(m.tint[0], m.tint[1], m.tint[2]);
    return t * t;
  }
  static void set_table(const gl::Program& p, const Table& t);
  // The outgoing rays of every glass vertex at one traced wavelength into
  // each Glass::rays (§4.1).
  // At IOR n a glass between two tables a, b (n_a < n < n_b) traces both
  // and blends them (glass_rays_blend.comp); at a table's own index, that
  // table alone. `exact_nd`: every glass at its n_d table (one wavelength
  // traced, bit-identical to glass without dispersion).
  // A glass in `skip` sends no light (weight 0; its light is the caustic
  // maps').
  void trace_rays(const SceneDesc& scene, const WavelengthSample& w, bool exact_nd, const std::vector<bool>& skip,
                  const std::function<void(const gl::Program&)>& set_light_uniforms);
  void set_pose(const gl::Program& p, const SceneDesc& scene, const Glass& g) const;
  // An object's model matrix and the normals' matrix (inverse transpose)
  // for mesh.vert.
  static void set_mesh_pose(const gl::Program& p, const Object& o) {
    const glm::mat4 model = to_glm(o.transform);
    p.set("u_model", model);
    p.set("u_normal_matrix", glm::mat3(glm::transpose(glm::inverse(model))));
  }
  // The window's targets (and the back faces' for the nearby view) at
  // least w x h: grown in steps of 64 texels, re-made smaller when a
  // quarter of them would do.
  void ensure_window(int w, int h, bool back);
  // The back faces over the window (w x h texels; `ndc_window` maps the
  // window's NDC rectangle onto them) into back_fbo.
  void draw_back_faces(const SceneDesc& scene, const glm::mat4& view_proj, const glm::vec4& ndc_window, int w, int h);
  // Thin-walled glass into the window, after the solid glass:
  // every sheet depth-tested, not written, far sides first, each blended
  // as colour + destination x transmittance (glass_thin.frag), so that a
  // closed shade scales what is behind it twice.
  void draw_thin(const SceneDesc& scene, const glm::mat4& view_proj, const glm::vec4& ndc_window, const glm::vec3& eye,
                 const glm::vec3& sky, unsigned environment) const;
  // The glass's rectangle in the frame's pixels (x0, y0, x1, y1: what its
  // objects' world boxes project to, a pixel wider), or nothing when none
  // of it is in view. All of the frame when a box reaches behind the eye.
  std::optional<glm::ivec4> window_of(const SceneDesc& scene, const glm::mat4& view_proj, int width, int height) const;
  // Step 4 of update_light for one target and the rays of one wavelength
  // (blending adds into its illumination textures).
  void illuminate(const SceneDesc& scene, Target& t, const CausticsOptions& co,
                  const std::function<void(const gl::Program&)>& set_light_uniforms, bool coarse);
  // Where a focus window's layers hold it: the window over [0, side)^2
  // (kFocusTexels of the texture's side, where caustix.glsl reads it) and,
  // where the texture has room (side + coarse_side <= size), the square of
  // half its texels a side at (side, side) that a coarse window is drawn
  // into (update_light).
  struct WindowSquares {
    int side = 0, coarse_side = 0;
    bool coarse = false;
  };
  static WindowSquares window_squares(int size);
  // A coarse window into its own (glass_window_resolve.comp), then the
  // square cleared, so that the mips and the next update see none of it.
  void resolve_window(const Target& t);
  // The target's textures at `size` with `planes` planes; the
  // illumination texture with twice the layers once a focus window is
  // needed (kept after: a light that moves would otherwise re-make it as
  // the window comes and goes).
  void ensure_target(Target& t, int size, std::uint32_t planes, bool focus);
};

}  // namespace caustix::runtime
