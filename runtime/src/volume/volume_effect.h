#pragma once
// The media (Pfeuti) as a light-side effect (engine/light_effect.h):
// photons marched through the media from the same water state as the
// caustics, bent by the glass's index grids, into each light's radiance
// grid; the glass's exit rays place its focus grid. Its photons read the
// light's block and shadow maps; it writes nothing the block holds.
// Internal to the runtime.

#include <vector>

#include "light_effect.h"
#include "volume.h"

namespace caustix::runtime {

class VolumeEffect final : public LightEffect {
 public:
  explicit VolumeEffect(VolumeEngine& volume) : volume_(volume) {}
  Status check(const CausticsOptions& o, EngineServices&) override { return VolumeEngine::check(o.volume); }
  bool active(const CausticsOptions&) const override { return true; }
  bool reads_light_block() const override { return true; }
  bool writes_light_block() const override { return false; }
  Status begin_frame(const FrameStart& start) override { return volume_.begin_frame(start.scene, start.options.volume); }
  Status update_light(const LightUpdate& u) override {
    const std::vector<WavelengthSample> waves = traced_wavelengths(u.scene, u.options);
    const bool spectral = waves.size() > 1 || u.options.wavelength_nm.has_value();
    return volume_.update_light(u.scene, u.light, u.options.volume, u.engine.water(), waves, spectral,
                                [&u]() { u.engine.bind_light(u.light, u.options, nullptr); }, u.engine.glass_exit_rays(u.light),
                                u.options, u.versions, u.due, work(u.work));
  }
  void end_frame(std::uint64_t frame) override { volume_.end_frame(frame); }
  EffectWork& work(FrameWork& w) const override { return w.media; }
  void product_versions(std::uint32_t, ReceiverTable::Versions&) const override {}  // none of the receivers' textures
  void memory(GpuMemory& m) const override { m.media = volume_.gpu_bytes(); }  // radiance and index grids

 private:
  VolumeEngine& volume_;
};

}  // namespace caustix::runtime
