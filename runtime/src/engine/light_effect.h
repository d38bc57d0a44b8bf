#pragma once
// The contract of a light-side effect (shadow maps, the level-map caustics
// and their siblings, the glass tables, the image-space caustic maps, the
// media): what Engine::update() asks of each, so that it is one loop over
// the effects the scene needs, per light, in the order they are registered
// (Engine::create). A new effect implements this in its own folder and is
// registered once.
//
// What an effect depends on is said through SceneVersions (made_from.h):
// the Engine numbers the changes of each light, of the transforms and of
// the water; the effect keeps, per light, what its products were made from
// and remakes them only when that moved (or never made), counting the
// remade, reused and deferred ones into its EffectWork. The receiver table
// (bind_all) copies again the textures of the products whose versions
// (product_versions(): how many times each was made) moved since it last
// copied them. Internal to the runtime.

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"
#include "exit_ray.h"
#include "made_from.h"
#include "receiver_table.h"

namespace caustix::runtime {

namespace gl {
class Program;
}
class WaterSurface;

// What the Engine lends an effect while it updates: the scene as the
// Engine holds it now, the water, and the light's resources for the
// effect's own shaders.
class EngineServices {
 public:
  // Every object's vertices and its bounds (min, max) in world space, at
  // the current transforms.
  virtual const std::vector<std::vector<std::array<double, 3>>>& world_vertices() const = 0;
  virtual const std::vector<std::array<glm::vec3, 2>>& object_boxes() const = 0;
  virtual glm::vec3 scene_center() const = 0;
  virtual float scene_radius() const = 0;
  // The water's surface as this frame animated it; null without water.
  virtual const WaterSurface* water() const = 0;
  // Per object, whether the image-space caustic maps carry its light
  // with these options (mirrors; glass with GlassMethod::kCausticMap).
  virtual const std::vector<bool>& caustic_map_casters(const CausticsOptions& options) = 0;
  // Binds the light's block, shadow maps and textures where the GLSL
  // include reads them (caustix.glsl), as they are now; with `program`,
  // also sets its light uniforms (u_light_type, u_light_direction,
  // u_light_position, u_light_power, u_spot).
  virtual void bind_light(std::uint32_t light, const CausticsOptions& options, const gl::Program* program) = 0;
  // GPU memory by effect as it is now (Engine::stats().memory).
  virtual GpuMemory memory() const = 0;
  // The glass's exit rays towards `light` (a CPU sample of its tables), to
  // call when needed; an empty function without glass.
  virtual std::function<std::vector<ExitRay>()> glass_exit_rays(std::uint32_t light) const = 0;

 protected:
  ~EngineServices() = default;
};

// One frame's start, and one light's update, as the Engine hands them out.
struct FrameStart {
  const SceneDesc& scene;
  std::uint64_t frame = 0;
  const CausticsOptions& options;
  EngineServices& engine;
  // Per object, whether it lies outside the application's view
  // (FrameUpdate::camera; empty: none is), and how often such a receiver's
  // products are remade anyway (FrameUpdate::out_of_view_interval).
  const std::vector<bool>* out_of_view = nullptr;
  std::uint32_t out_of_view_interval = 1;
};
struct LightUpdate {
  const SceneDesc& scene;
  std::uint32_t light = 0;
  const CausticsOptions& options;
  SceneVersions versions;  // of this light, the transforms, the water
  bool due = true;         // out-of-date products are remade only when due (FrameUpdate::light_side_interval)
  EngineServices& engine;
  FrameWork& work;         // the frame's counts: the effect counts into its slot (LightEffect::work)
};

class LightEffect {
 public:
  virtual ~LightEffect() = default;
  // Checks the options it reads (a usage error names the field). The
  // Engine calls it when the options differ from the last accepted ones,
  // not every frame.
  virtual Status check(const CausticsOptions&, EngineServices&) { return Status::success(); }
  // Whether update_light() runs this frame with these options.
  virtual bool active(const CausticsOptions& options) const = 0;
  // Whether its passes read the light's block (the Engine uploads it with
  // what the effects before made first), and whether its products are in
  // the block and the light's textures (the Engine uploads it after).
  virtual bool reads_light_block() const { return false; }
  virtual bool writes_light_block() const { return true; }
  // Around a frame's update_light() calls: begin polls earlier frames'
  // read-backs (never waiting) and resets the frame's counts; end sends
  // this frame's GPU counters back.
  virtual Status begin_frame(const FrameStart& start) = 0;
  virtual Status update_light(const LightUpdate& u) = 0;
  virtual void end_frame(std::uint64_t frame) = 0;
  // Its slot of the frame's work counts.
  virtual EffectWork& work(FrameWork& w) const = 0;
  // The versions of light `light`'s products whose textures the receiver
  // table holds, into their slots of `v` (ReceiverTable::Product): each
  // changes exactly when the effect replaces that product's texels. An
  // effect whose products are not in the table leaves `v` alone.
  virtual void product_versions(std::uint32_t light, ReceiverTable::Versions& v) const = 0;
  // Its GPU memory, into its field of `m`.
  virtual void memory(GpuMemory& m) const = 0;
};

}  // namespace caustix::runtime
