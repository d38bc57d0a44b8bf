#pragma once
// Image-space caustic maps (timofy 2009) as a light-side effect
// (engine/light_effect.h): per light, the caustic map of the mirrors and,
// with GlassMethod::kCausticMap, the glass. Made on the first frame whose
// options need it; a frame that needs none clears every light's. Internal
// to the runtime.

#include <functional>
#include <memory>

#include "causticmap.h"
#include "light_effect.h"
#include "receiver_table.h"

namespace caustix::runtime {

class CausticMapEffect final : public LightEffect {
 public:
  // `owner` holds the engine once made (the Engine reads its bindings and
  // statistics there); `draw_object` draws an object's mesh for it.
  CausticMapEffect(std::unique_ptr<CausticMapEngine>& owner, const SceneDesc& scene, std::function<void(std::uint32_t)> draw_object)
      : owner_(owner), scene_(scene), draw_object_(std::move(draw_object)) {}
  // Its options are checked whenever some object's light goes through
  // the caustic maps with these options.
  Status check(const CausticsOptions& o, EngineServices& engine) override {
    if (!CausticMapEngine::needed(engine.caustic_map_casters(o))) return Status::success();
    return CausticMapEngine::check(o.caustic_map);
  }
  bool active(const CausticsOptions&) const override { return owner_ != nullptr; }
  Status begin_frame(const FrameStart& start) override {
    needed_ = start.options.method != CausticsMethod::kNone &&
              CausticMapEngine::needed(start.engine.caustic_map_casters(start.options));
    if (needed_ && !owner_) {
      auto made = CausticMapEngine::create(scene_, draw_object_);
      if (!made) return made.error();
      owner_ = std::move(*made);
    }
    if (owner_) owner_->begin_frame(start.frame);
    return Status::success();
  }
  Status update_light(const LightUpdate& u) override {
    if (!needed_) {
      owner_->clear(u.light);
      return Status::success();
    }
    return owner_->update_light(u.scene, u.light, u.options, u.engine.object_boxes(), u.engine.caustic_map_casters(u.options),
                                u.versions, u.due, work(u.work));
  }
  void end_frame(std::uint64_t) override {
    if (owner_) owner_->end_frame();
  }
  EffectWork& work(FrameWork& w) const override { return w.caustic_maps; }
  void product_versions(std::uint32_t light, ReceiverTable::Versions& v) const override {
    if (owner_) v[ReceiverTable::kCausticMaps] = owner_->times_made(light);
  }
  void memory(GpuMemory& m) const override {
    if (owner_) m.caustic_maps = owner_->gpu_bytes();  // caster maps, caustic maps, photons
  }

 private:
  std::unique_ptr<CausticMapEngine>& owner_;
  const SceneDesc& scene_;
  std::function<void(std::uint32_t)> draw_object_;
  bool needed_ = false;  // this frame's options need caustic maps
};

}  // namespace caustix::runtime
