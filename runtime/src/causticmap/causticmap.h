#pragma once
// Image-space caustic maps (timofy 2009; Shah, Konttinen & Pattanaik 2007;
// docs/caustic-maps.md): per light, the casters (mirrors and thin-walled
// glass always, solid glass when CausticsOptions::glass_method is
// kCausticMap) seen from the light in an
// orthographic frame along it give a grid of photons; a compute shader
// refracts (or reflects) them and lands them on the receivers seen from the
// light; their flux is splatted into the light's caustic map, which holds
// irradiance on the receivers' first surface seen from the light (rgb) and
// that surface's coordinate along V (alpha). Nothing is baked: casters may
// move or deform between frames. Internal to the runtime.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/level_map.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"
#include "gl_objects.h"
#include "made_from.h"

namespace caustix::runtime {

class CausticMapEngine {
 public:
  // kUsage naming the knob when an option is out of its documented range
  // (caustics_options.h) or not finite.
  static Status check(const CausticMapOptions& options);
  // Per object, whether the caustic maps carry its light: mirrors and
  // thin-walled glass (no tables) always; solid glass with GlassMethod::kCausticMap, and with the tables glass that
  // holds a receiver (receiver_inside_glass(), formats/frame.h: the
  // tables' rays start where light leaves the glass and never reach it).
  static std::vector<bool> casters(const SceneDesc& scene, GlassMethod method);
  // Whether the effect is needed at all (some caster).
  static bool needed(const std::vector<bool>& casters);
  // draw_object(i) issues object i's draw call (attribute 0 position, 1
  // normal).
  static Result<std::unique_ptr<CausticMapEngine>> create(const SceneDesc& scene, std::function<void(std::uint32_t)> draw_object);
  ~CausticMapEngine();

  // The caustic map of `light` for the current transforms. world_boxes[i]
  // is object i's world bounding box (min, max). Remade only when the
  // light, the transforms or the options changed since (`versions`), and
  // only when `due` unless none exists; counted into `work`.
  // `casters` as casters() gives it.
  Status update_light(const SceneDesc& scene, std::uint32_t light, const CausticsOptions& options,
                      const std::vector<std::array<glm::vec3, 2>>& world_boxes, const std::vector<bool>& casters,
                      const SceneVersions& versions, bool due, EffectWork& work);

  struct Binding {
    BoundingFrame frame;  // orthographic along the light: V towards it; the map covers (u, w) in +-half
    GLuint map = 0;       // RGBA32F: irradiance rgb (W/m^2 without the light's colour), alpha the receivers' V
    float texel_diagonal = 0;  // half a texel's diagonal, metres (the slope-scaled visibility tolerance)
    float tolerance = 0;       // constant visibility tolerance along V, metres
    // The main map's share of the texture's height: 1, or with a focus
    // window above it map_size / (map_size + map_size / 2).
    float main_share = 1;
  };
  // Forgets the light's map (an update without caster light).
  void clear(std::uint32_t light);
  // The light's map from its last update_light(), if it had casters.
  std::optional<Binding> binding(std::uint32_t light) const;

  // A frame's update_light() calls come between these: begin_frame polls
  // earlier frames' counters (never waiting) and clears this frame's;
  // end_frame sends them back.
  void begin_frame(std::uint64_t frame);
  void end_frame();
  // Counters summed over the lights: of the latest frame whose read-back
  // arrived, or with `wait` of the last frame, with the photons' landed
  // power and adaptive levels (read back: a stall).
  CausticMapStats stats(bool wait);
  std::uint64_t gpu_bytes() const;
  // How many times light li's caustic map was made (the receiver table's
  // version).
  std::uint64_t times_made(std::uint32_t li) const;

 private:
  CausticMapEngine() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::runtime
