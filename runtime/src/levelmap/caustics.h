#pragma once
// Water caustics on the GPU (Tipprasert 2006 §4.3-4.7, §5.2.1): per light, refract
// at every water vertex and compute each water triangle's flux; per level
// map of that light, cull the illumination volumes against the frame, then
// intersect them with the reference planes into the caustics map (level map:
// one instanced draw with the position-map acceptance test; volumetric: one
// slice per plane, combined afterwards). Internal to the runtime.

#include <functional>
#include <memory>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/level_map.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"
#include "gl_objects.h"
#include "made_from.h"
#include "water_surface.h"

namespace caustix::runtime {

class CausticsEngine {
 public:
  // `maps` must outlive the engine, which keeps pointers into it and
  // updates them when it re-derives a light's maps.
  // draw_object(i) issues object i's draw call (the engine sets u_model).
  static Result<std::unique_ptr<CausticsEngine>> create(std::vector<LevelMap>& maps,
                                                        const WaterSurface& water,
                                                        std::function<void(std::uint32_t)> draw_object,
                                                        std::function<glm::mat4(std::uint32_t)> model_of);
  ~CausticsEngine();
  // The options it reads that can be wrong: map_size, texel_size (a
  // usage error names the field).
  static Status check(const CausticsOptions& options);

  // Marks the maps of `light` (or of all lights) whose receiver is
  // `object` (or any) for re-derivation: their next update_light()
  // re-derives the frame, position map and depth profile (and so the
  // planes) for the lights' and objects' state then (Tipprasert 2006 §4.2; the
  // thesis re-profiled per frame): the frame on the CPU from the
  // receiver's world vertices, the position map rendered on the GPU, the
  // histogram by a compute shader and the planes from it
  // (caustics_plan.comp) without reading anything back.
  void rederive(std::optional<std::uint32_t> light, std::optional<std::uint32_t> object);

  // Caustics maps of light `light` for the water's current shape, remade
  // only when the light, the transforms, the water or the options changed
  // since (`versions`), and only when `due` unless none exists;
  // counted into `work`. world[i] are object i's vertices in world space.
  Status update_light(std::uint32_t light, const std::vector<Light>& lights, const std::optional<Water>& water,
                      const std::vector<std::vector<std::array<double, 3>>>& world, const CausticsOptions& options,
                      const SceneVersions& versions, bool due, EffectWork& work);

  struct Binding {
    const LevelMap* map;
    // RGBA32F: irradiance on planes perpendicular to V, its direction,
    // presence; a 1 x 1 black texture where the water's light cannot
    // reach the receiver now (it has no map then).
    GLuint caustics;
    GLuint color;         // RGBA32F: irradiance per RGB channel when the water disperses (else 0)
    GLuint position_map;  // R32F, frame V of the first surface
    float self_tolerance;
  };
  // The map of (object, light), or nothing if none was baked.
  std::optional<Binding> binding(std::uint32_t object, std::uint32_t light) const;

  // A frame's update_light() calls come between these two: begin_frame
  // polls the read-backs of earlier frames (never waiting) and resets the
  // frame's counts; end_frame sends this frame's GPU counters back.
  // `other_bytes`: the light side's memory held by the other effects
  // (GpuMemory::light_side() less the level maps), which the budget's
  // plan of texels leaves room for. `out_of_view` (per object; null or
  // empty: none): a map whose receiver is out of the camera's view keeps
  // what it has, remade on one update in `out_of_view_interval` (the maps
  // taking turns) and on the first update that finds it in view.
  void begin_frame(std::uint64_t frame, std::uint64_t other_bytes, const std::vector<bool>* out_of_view = nullptr,
                   std::uint32_t out_of_view_interval = 1);
  void end_frame();
  // The frame's counts; the GPU's (volumes and planes drawn, overflow) are
  // of the latest frame whose read-back has arrived (counters_frame), or of
  // the last frame with `wait` (a stall).
  CausticsStats stats(bool wait);
  // Its GPU memory: the refracted rays, the read-back ring, the splats'
  // photons, the intersection lists and the maps (stats().gpu_bytes).
  std::uint64_t gpu_bytes() const;
  // How many times light `light`'s caustics maps, and its position maps,
  // were made (the receiver table's versions).
  std::uint64_t times_made(std::uint32_t light) const;
  std::uint64_t position_maps_made(std::uint32_t light) const;

 private:
  CausticsEngine() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::runtime
