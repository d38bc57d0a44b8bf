#pragma once
// The shadow maps as a light-side effect (engine/light_effect.h): every
// light's depth maps of the opaque objects and of the glass, and their
// moments for variance shadow maps. Internal to the runtime.

#include "light_effect.h"
#include "receiver_table.h"
#include "shadow_maps.h"

namespace caustix::runtime {

class ShadowEffect final : public LightEffect {
 public:
  explicit ShadowEffect(ShadowMaps& maps) : maps_(maps) {}
  Status check(const CausticsOptions& o, EngineServices&) override { return ShadowMaps::check(o.shadows); }
  bool active(const CausticsOptions&) const override { return true; }
  Status begin_frame(const FrameStart&) override { return Status::success(); }
  Status update_light(const LightUpdate& u) override {
    maps_.render(u.scene, u.light, u.engine.scene_center(), u.engine.scene_radius(), u.options.shadows, u.versions, u.due,
                 work(u.work));
    return Status::success();
  }
  void end_frame(std::uint64_t) override {}
  EffectWork& work(FrameWork& w) const override { return w.shadow_maps; }
  void product_versions(std::uint32_t light, ReceiverTable::Versions& v) const override {
    v[ReceiverTable::kShadowMaps] = maps_.times_made(light);
  }
  void memory(GpuMemory& m) const override { m.shadow_maps = maps_.gpu_bytes(); }

 private:
  ShadowMaps& maps_;
};

}  // namespace caustix::runtime
