#pragma once
// The sample renderer behind caustix-render and caustix-view: a client of
// the public Engine API (caustix/runtime/engine.h), as any application
// would be, built as its own library (caustix_sample, not installed). It
// owns what an application owns: the camera, a linear float HDR target, the
// receivers' shading (its shaders include caustix.glsl) and tone mapping.
// Needs a current OpenGL 4.5 core context (HeadlessContext, or a GLFW
// window's).
//
// A frame: Engine::update (water, shadow maps, caustics maps, glass
// illumination per light); receivers (ambient, then one additive pass per
// light: caustics casting, Tipprasert 2006 §4.6, eq. 4-19/4-20); Engine::draw_glass
// and Engine::draw_water on top (the water's textures drawn by the same
// receiver passes through its callback), then Engine::draw_media over it
// all (Pfeuti: single scattering, stopped by the opaque scene's depth). present() tone-maps to a display
// framebuffer; read_hdr() and read_display() return its pixels.
// render_irradiance() writes the irradiance images of docs/architecture.md.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"
#include "caustix/runtime/engine.h"
#include "caustix/runtime/water_look.h"
#include "caustix/runtime/scene_loader.h"

namespace caustix::sample {

// The sample is a client of the runtime's public API and uses its names as
// they are (Engine, View, CausticsOptions, ...).
using namespace caustix::runtime;

// The display transform of present() and read_display() (docs/display.md):
// linear radiance times 2^exposure_ev (and, with auto_exposure, times
// 0.18 / the frame's log-average luminance), through the tone curve, then
// sRGB-encoded. read_hdr() and EXR output stay linear, untouched by it.
enum class ToneMap {
  kFilmic,       // ACES's filmic curve as fitted by Narkowicz (2015): a toe, a long shoulder
  kExponential,  // 1 - e^-x (caustix's first curve)
};
struct DisplayOptions {
  ToneMap tone_map = ToneMap::kFilmic;
  // Stops, in [-16, 16]. Frames are in units of E0 (a white floor in full
  // light is ~1.05 with the ambient term); -1 puts it at sRGB 0.71 under the
  // filmic curve, leaving the shoulder to caustics (3x: 0.90, 6x: 0.96)
  // instead of near white (0.85 at 0 EV; 0.83 under 1 - e^-x).
  float exposure_ev = -1.0f;
  bool auto_exposure = false;  // Reinhard et al. 2002's key: log-average luminance -> 0.18
};
const char* to_string(ToneMap t);
std::optional<ToneMap> parse_tone_map(const std::string& name);  // "filmic", "exponential"

// What is seen where no receiver is: above the water, in its reflection and
// through it from below.
enum class SkyModel {
  kFlat,      // kSkyColor everywhere (times the scene's reference irradiance)
  // Preetham, Shirley & Smits's analytic daylight (1999; turbidity 2.5:
  // a clear day) for the scene's first directional light as the sun,
  // scaled so that the zenith has kSkyColor's luminance: blue overhead,
  // paler towards the horizon, bright about the sun. Flat in a scene
  // without a directional light.
  kAnalytic,
};

struct FrameParams {
  Camera camera;
  float time = 0.0f;  // seconds, drives the waves
  int width = 640;
  int height = 480;
  CausticsOptions caustics;
  WaterLook water;
  GlassViewOptions glass_view;  // how the view through glass is found (Engine::draw_glass)
  DisplayOptions display;       // what present() and read_display() make of the frame
  // Antialiasing by supersampling (docs/display.md): every pass runs at
  // supersample^2 the pixels and the frame is box-filtered down to
  // width x height (linear, so read_hdr() and EXR output are antialiased
  // too). 1..4; the cost grows with its square.
  int supersample = 1;
  // The background (caustix-render and caustix-view draw kAnalytic unless
  // told --sky flat; the library's default keeps tests' backgrounds exact).
  SkyModel sky = SkyModel::kFlat;
  // 0: the engine remakes every receiver's caustics; N > 0: it is told the
  // camera (FrameUpdate::camera) and keeps the maps of receivers out of
  // view, remaking them every Nth update (FrameUpdate::out_of_view_interval).
  std::uint32_t out_of_view_interval = 0;
};

// docs/architecture.md: a top-down orthographic view of [x0, x1] x [z0, z1];
// each pixel is the irradiance at the first surface of `receiver` seen from
// above, divided by E0 (the first directional light's irradiance, or 1 if
// the scene has none), averaged over the pixel's square (a pixel-box
// average; where the receiver is not seen the square counts 0). Row i spans
// z0 + [i, i + 1)(z1 - z0)/H, column j spans x0 + [j, j + 1)(x1 - x0)/W.
// The average is the mean of pixel_samples^2 point samples on a regular
// grid inside the pixel (1: the centre only).
struct IrradianceRequest {
  std::string receiver;
  float x0 = -1, z0 = -1, x1 = 1, z1 = 1;
  int width = 256, height = 256;
  float time = 0.0f;
  CausticsOptions caustics;
  int pixel_samples = 4;  // per axis, 1..16
};

struct IrradianceImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // row-major, row 0 at z0
  float e0 = 1.0f;
  // Per pixel, from the same samples (row-major, 3 floats): the fraction of
  // the pixel where the receiver is seen; the mean normal's |n_y| and the
  // mean cosine between the normal and the direction towards the first
  // light (below flat water: against its refracted direction; 0 for a point
  // light) over the samples that see it. What caustix-compare --split
  // classifies errors by.
  std::vector<float> aux;
};

// docs/architecture.md's in-scatter image (Pfeuti; docs/volume.md): an
// orthographic view along -z of [x0, x1] x [y0, y1], columns along +x, row
// 0 at y1; each pixel the single-scattered radiance reaching the camera
// divided by E0, averaged over the pixel's square (pixel_samples^2 rays on
// a regular grid); surfaces are not drawn, but view rays are bent by
// transparent objects and stopped by opaque ones.
struct InscatterRequest {
  float x0 = -1, y0 = -1, x1 = 1, y1 = 1;
  int width = 256, height = 256;
  float time = 0.0f;
  CausticsOptions caustics;
  int pixel_samples = 2;  // per axis, 1..16
};

struct InscatterImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // row-major, row 0 at y1
  float e0 = 1.0f;
  VolumeStats stats;       // of the photon marching behind it
};

// GPU time of the stages of one render() (GL_TIMESTAMP queries), for
// viewers and profiling: the light side (Engine::update: water, shadow
// maps, caustics maps, glass illumination, caustic maps, media photons),
// the receivers (with the water's refraction and reflection textures
// drawn inside draw_water, counted there), the glass, the water surface,
// the media and the supersampling resolve.
struct PassTimes {
  static constexpr int kCount = 6;
  static const char* name(int pass);  // "light side", "receivers", "glass", "water", "media", "resolve"
  bool valid = false;                 // a frame's queries have been read
  float ms[kCount] = {};
  float total_ms() const;
};

// The sky's linear colour: the beauty image's background, times the
// scene's reference irradiance (default_exposure_ev(): E0 of a sun, else
// the brightest lamp's irradiance at the scene's centre), as the ambient
// term (0.12 of it) is.
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
  // kUsage for a scene without media.
  Result<InscatterImage> render_inscatter(const InscatterRequest& request);

  // Moves light `index` (directional: direction of travel; point: position)
  // and re-derives the level maps it lights, on the GPU (see caustics.h).
  Status set_light(std::uint32_t index, const Light& light);
  // Moves object `index` (rigid or affine: its object -> world matrix) and
  // re-derives its level maps on the GPU.
  Status set_object_transform(std::uint32_t index, const Mat4f& transform);
  const SceneDesc& scene() const;
  // Scales every wave's amplitude (1 = as baked); for interactive tuning.
  void set_wave_scale(float scale);

  // The engine underneath, for what the renderer does not wrap.
  Engine& engine();

  // Waits until the GPU has finished every command (for timing).
  void finish();

  // Per-stage GPU times, measured when enabled (off by default: the
  // queries cost a little). Results arrive a frame or two late (no stall):
  // pass_times() is the latest frame whose queries have completed.
  void set_pass_timing(bool enabled);
  PassTimes pass_times();

  // What the caustics passes of the last render did.
  CausticsStats caustics_stats(bool wait = false);
  // The last frame through its FrameParams::display transform into
  // `framebuffer` (0: the window).
  void present(unsigned framebuffer, int width, int height);

  // Pixels of the last frame, top row first: linear RGBA float, and
  // tone-mapped sRGB RGBA8.
  std::vector<float> read_hdr();
  std::vector<std::uint8_t> read_display();

  // The scene's camera, or one that frames the scene's bounds.
  Camera default_camera() const;
  // The exposure (EV) a display should start at for this scene: -1 EV
  // relative to its reference irradiance -- the first directional light's
  // E0, else the largest I / d^2 of its point and spot lights at the centre
  // of the scene's bounds, so that a glTF lamp's room shows as a sun's pool
  // does; in [-16, 16].
  float default_exposure_ev() const;
  glm::vec3 bounds_min() const;
  glm::vec3 bounds_max() const;

 private:
  Renderer();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::sample
