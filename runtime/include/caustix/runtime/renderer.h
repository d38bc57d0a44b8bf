#pragma once
// The runtime's GL renderer. Needs a current OpenGL 4.5 core context
// (HeadlessContext, or a GLFW window's). Creates only what the loaded scene
// needs: mesh buffers, a shadow map per light kind present, the water grid if
// the scene has water.
//
// A frame: the water surface animated on the GPU; per light, its shadow map
// and (scenes with water) its caustics maps; receivers (ambient, then one
// additive pass per light: caustics casting, seed 000 §4.6, eq. 4-19/4-20);
// the water surface on top; into a linear float HDR target. present()
// tone-maps it to a display framebuffer; read_hdr() and read_display()
// return its pixels. render_irradiance() writes the irradiance images of
// shared/DESIGN.md.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/scene_loader.h"

namespace caustix::runtime {

// How the water surface looks (seed 001, Mihálik, ch. 5-9). Each effect can
// be switched off on its own, for the viewer's toggles and for measuring
// what it costs.
enum class FresnelMode {
  kApprox,  // eq. 7-8: F = f + (1 - f)(1 - E.N)^q
  kExact,   // unpolarised Fresnel reflectance, total internal reflection included
};

// Diagnostic outputs of the water surface instead of its colour (tests and
// the iteration study of docs/water.md). The water's pixels have alpha 2
// in read_hdr(); the others keep the scene's colour.
enum class WaterDebug {
  kNone,
  kFresnel,      // r: the reflected fraction F used for the pixel
  kLookup,       // rg: refraction-texture coordinates the W/A iteration found, b: its |A - W|
  kExactLookup,  // rg: where the refracted ray meets the same depth texture, by an exact march
};

struct WaterLook {
  bool textures = true;    // false: the plain surface (sky reflection, no refraction textures)
  bool refraction = true;  // §7.1: bend the view ray; off: look straight through
  bool reflection = true;  // §5.2/§7.3: reflection texture; off: no reflection
  bool colour = true;      // eq. 4-5 (and eq. 10 under water): attenuation towards the water colour
  bool glow = true;        // §9.3
  FresnelMode fresnel = FresnelMode::kApprox;
  int steps = 3;              // W/A iterations (§7.1; the paper could afford 3)
  int texture_size = 512;     // refraction and reflection textures, square (table 3: 256..1024)
  float fov_ext = 1.5f;       // FOV_ext (fig. 5, table 1)
  float fresnel_q = 5.0f;     // q of eq. 7 (table 1)
  float reflect_scale = 1.0f; // c of eq. 6 (table 1; metres)
  float under_scale = 1.5f;   // m of eq. 13/15 (§7.5)
  // Water colour as a reflectance; its radiance is this times the light
  // entering the water (docs/water.md). Table 1: (0, 0.2, 0.1).
  glm::vec3 water_color{0.0f, 0.2f, 0.1f};
  // k of eq. 4, per metre and channel; unset: the scene's absorption.
  std::optional<glm::vec3> attenuation;
  WaterDebug debug = WaterDebug::kNone;
};

struct FrameParams {
  Camera camera;
  float time = 0.0f;  // seconds, drives the waves
  int width = 640;
  int height = 480;
  CausticsOptions caustics;
  WaterLook water;
};

// shared/DESIGN.md: a top-down orthographic view of [x0, x1] x [z0, z1];
// each pixel is the irradiance at the first surface of `receiver` seen from
// above, divided by E0 (the first directional light's irradiance, or 1 if
// the scene has none). Row i is z = z0 + (i + 1/2)(z1 - z0)/H, column j is
// x = x0 + (j + 1/2)(x1 - x0)/W.
struct IrradianceRequest {
  std::string receiver;
  float x0 = -1, z0 = -1, x1 = 1, z1 = 1;
  int width = 256, height = 256;
  float time = 0.0f;
  CausticsOptions caustics;
};

struct IrradianceImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // row-major, row 0 at z0
  float e0 = 1.0f;
};

// The sky's linear colour: the beauty image's background.
inline constexpr float kSkyColor[3] = {0.42f, 0.58f, 0.78f};

class Renderer {
 public:
  // Copies what it needs from `scene`, which need not outlive the renderer.
  static Result<std::unique_ptr<Renderer>> create(const RuntimeScene& scene);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  Status render(const FrameParams& frame);
  Result<IrradianceImage> render_irradiance(const IrradianceRequest& request);

  // Moves light `index` (directional: direction of travel; point: position)
  // and re-derives the level maps it lights, on the GPU (see caustics.h).
  Status set_light(std::uint32_t index, const Light& light);
  // Moves object `index` (rigid or affine: its object -> world matrix) and
  // re-derives its level maps on the GPU.
  Status set_object_transform(std::uint32_t index, const Mat4f& transform);
  const SceneDesc& scene() const;
  // Scales every wave's amplitude (1 = as baked); for interactive tuning.
  void set_wave_scale(float scale);

  // Waits until the GPU has finished every command (for timing).
  void finish();

  // What the caustics passes of the last render did.
  CausticsStats caustics_stats(bool read_gpu_counters = true);
  // Tone-mapped display image into `framebuffer` (0: the window).
  void present(unsigned framebuffer, int width, int height);

  // Pixels of the last frame, top row first: linear RGBA float, and
  // tone-mapped sRGB RGBA8.
  std::vector<float> read_hdr();
  std::vector<std::uint8_t> read_display();

  // The scene's camera, or one that frames the scene's bounds.
  Camera default_camera() const;
  glm::vec3 bounds_min() const;
  glm::vec3 bounds_max() const;

 private:
  Renderer();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::runtime
