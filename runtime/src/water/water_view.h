#pragma once
// The water surface's appearance (Mihalik 2008, ch. 5-9): the cameras
// of the refraction and reflection textures, the textures themselves, the
// surface shader that reads them, and the glow. The renderer draws the
// scene into the textures (it owns the lighting passes); this class says
// from where and keeps the targets. Internal to the runtime.

#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/engine.h"
#include "caustix/runtime/water_look.h"
#include "gl_objects.h"
#include "gl_state.h"
#include "scene_inputs.h"

namespace caustix::runtime {

// One camera of the frame: the main view or a texture's.
struct ViewCamera {
  glm::mat4 view{1.0f}, proj{1.0f};
  glm::vec3 eye{0.0f};
};

struct WaterCameras {
  bool under = false;  // the main camera is below the water's rest level
  ViewCamera refraction, reflection;
  // World clip planes (a.x + b >= 0 kept) of the two texture passes: a
  // little beyond the rest level, by the waves' largest crest.
  glm::vec4 refraction_clip{0.0f}, reflection_clip{0.0f};
};

// §5.1-5.2 and fig. 5. From above: the refraction camera is the main camera
// rotated about O, where the bottom ray of its frustum meets the water
// (eq. 1), by the angle between that ray and its refraction (eq. 2); from
// below it is the main camera. The reflection camera is the main camera
// mirrored in the water plane. Both projections widen the field of view by
// FOV_ext (x and y scaled by 1/FOV_ext).
WaterCameras water_cameras(const ViewCamera& main, float fov_y_deg, float aspect, float near_plane, float far_plane,
                           const Water& water, const WaterLook& look);

class WaterView {
 public:
  static Result<WaterView> create();

  // Colour targets of the two textures (texture_size^2) and their one
  // depth buffer: the reflection's pass must come first.
  void ensure_targets(int size);
  GLuint refraction_fbo() const { return refraction_.fbo.get(); }
  GLuint reflection_fbo() const { return reflection_.fbo.get(); }
  int size() const { return size_; }

  struct SurfaceParams {
    const WaterCameras* cameras;
    glm::mat4 view_proj;  // main camera
    glm::vec3 eye;
    std::vector<glm::vec4> waves;  // view_samples(): RGB weight and the water's index per wavelength
    glm::vec3 water_color;  // radiance
    glm::vec3 k;            // per metre
    glm::vec3 sun_direction, sun_color;
  };
  // The surface, opaque, into the bound framebuffer (depth-tested against
  // the scene). `draw_water` issues the grid's draw call.
  void draw_surface(const SurfaceParams& p, const WaterLook& look, const std::function<void()>& draw_water) const;
  // §9.3: the highlight at a quarter of the frame's size, spread over a
  // disc (or the paper's diagonals: look.glow_star) and added to `target_fbo` over `viewport` (x, y, w, h).
  // `scene_depth` (0: none) hides glints behind the scene.
  void draw_glow(const SurfaceParams& p, const WaterLook& look, GLuint target_fbo, const int viewport[4], GLuint scene_depth,
                 const std::function<void()>& draw_water);

  // What draw() needs of the frame: the caller's camera, target and
  // viewport, the water, what the light makes of it.
  struct Frame {
    ViewCamera main;
    float fov_y_deg = 45.0f, aspect = 1.0f, near_plane = 0.1f, far_plane = 100.0f;
    GLuint target_fbo = 0;  // bound for drawing when draw() is called
    int viewport[4] = {0, 0, 0, 0};
    const Water* water = nullptr;
    WaterMedium medium;
    std::vector<glm::vec4> waves;  // view_samples() of the water's index
    glm::vec3 sun_direction{0.0f}, sun_color{0.0f};  // the first directional light (zero: none)
  };
  // Engine::draw_water() after its checks, inside its state guard: the
  // application's two texture passes through `draw_scene` (run with the
  // caller's state as engine.h's WaterPass says: guard.restore() before,
  // enter() after), then the surface and the glow (hidden behind
  // `scene_depth`, read through `reader`), or without textures the plain
  // surface. `draw_grid` issues the water grid's draw call.
  Status draw(const Frame& f, const WaterLook& look, const std::function<void(const WaterPass&)>& draw_scene,
              const gl::StateGuard& guard, gl::SceneReader& reader, const gl::SceneTexture& scene_depth,
              const std::function<void()>& draw_grid);

  std::uint64_t gpu_bytes() const;

 private:
  struct Target {
    gl::Framebuffer fbo;
    gl::Texture color, depth;
  };
  // Colour in full floats: half floats top out at 65504, which a caustic
  // focus (tens of E0) passes for E0 above ~10^3 (a real sun is ~10^3
  // W/m^2); llvmpipe clamped the overflow, other drivers store Inf
  // (Water.BrightSunScalesLinearlyPastHalfFloat, docs/robustness.md).
  static constexpr GLenum kColorFormat = GL_RGBA32F;
  static constexpr std::uint64_t kColorBytes = 16;
  // Colour and a 32-bit depth (its own, or `depth` if given).
  static Target make_target(int w, int h, GLuint depth = 0);
  static Target make_glow_target(int w, int h);  // RGBA16F (the highlight scaled) and a 16-bit depth
  gl::Program surface_, highlight_, glow_, plain_;
  gl::Program exact_surface_;  // surface_ with the exact march's lookup (WaterDebug::kExactLookup), built when first drawn
  gl::VertexArray empty_vao_;
  gl::Sampler nearest_;  // the caller's scene depth read texel by texel, whatever its own parameters
  Target refraction_, reflection_, glow_target_;
  int size_ = 0, glow_w_ = 0, glow_h_ = 0;
};

}  // namespace caustix::runtime
