#pragma once
// The water's caustics (Tipprasert 2006's level maps, the uniform and volumetric
// baselines, photon splatting) as a light-side effect
// (engine/light_effect.h): each (receiver, light)'s caustics map for the
// water's current shape. Internal to the runtime.

#include "caustics.h"
#include "light_effect.h"
#include "receiver_table.h"

namespace caustix::runtime {

class CausticsEffect final : public LightEffect {
 public:
  explicit CausticsEffect(CausticsEngine& caustics) : caustics_(caustics) {}
  Status check(const CausticsOptions& o, EngineServices&) override { return CausticsEngine::check(o); }
  bool active(const CausticsOptions&) const override { return true; }
  Status begin_frame(const FrameStart& start) override {
    const GpuMemory m = start.engine.memory();
    caustics_.begin_frame(start.frame, m.light_side() - m.level_maps, start.out_of_view, start.out_of_view_interval);
    return Status::success();
  }
  Status update_light(const LightUpdate& u) override {
    return caustics_.update_light(u.light, u.scene.lights, u.scene.water, u.engine.world_vertices(), u.options, u.versions, u.due,
                                  work(u.work));
  }
  void end_frame(std::uint64_t) override { caustics_.end_frame(); }
  EffectWork& work(FrameWork& w) const override { return w.level_maps; }
  void product_versions(std::uint32_t light, ReceiverTable::Versions& v) const override {
    v[ReceiverTable::kLevelMaps] = caustics_.times_made(light);
    v[ReceiverTable::kPositionMaps] = caustics_.position_maps_made(light);
  }
  void memory(GpuMemory& m) const override { m.level_maps = caustics_.gpu_bytes(); }

 private:
  CausticsEngine& caustics_;
};

}  // namespace caustix::runtime
