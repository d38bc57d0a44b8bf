#pragma once
// Caustics from the glass's light-transport tables (Iwasaki et al. §4) as a
// light-side effect (engine/light_effect.h): per light, the exit rays of
// every glass vertex and each receiver's illumination textures. Its rays
// read the light's block and shadow maps. Internal to the runtime.

#include "glass.h"
#include "light_effect.h"
#include "receiver_table.h"

namespace caustix::runtime {

class GlassEffect final : public LightEffect {
 public:
  explicit GlassEffect(GlassEngine& glass) : glass_(glass) {}
  bool active(const CausticsOptions& o) const override { return o.method != CausticsMethod::kNone; }
  bool reads_light_block() const override { return true; }
  Status begin_frame(const FrameStart&) override { return Status::success(); }
  Status update_light(const LightUpdate& u) override {
    // The light's textures as they are when the rays run: this update may
    // reallocate the glass's own (new sizes), and binding a deleted
    // texture's name is an error.
    return glass_.update_light(
        u.scene, u.light, u.options, u.engine.world_vertices(), u.engine.caustic_map_casters(u.options),
        [&u](const gl::Program& p) { u.engine.bind_light(u.light, u.options, &p); }, u.versions, u.due, work(u.work));
  }
  void end_frame(std::uint64_t) override {}
  EffectWork& work(FrameWork& w) const override { return w.glass; }
  void product_versions(std::uint32_t light, ReceiverTable::Versions& v) const override {
    v[ReceiverTable::kGlass] = glass_.times_made(light);
  }
  void memory(GpuMemory& m) const override { m.glass = glass_.gpu_bytes(); }

 private:
  GlassEngine& glass_;
};

}  // namespace caustix::runtime
