#pragma once
// Volume caustics and single scattering in participating media (Pfeuti:
// Sun, Zhou, Stollnitz, Shi and Guo, "Interactive Relighting of Dynamic
// Refractive Objects", SIGGRAPH 2008; docs/volume.md). Per light, photons
// are generated over the window of the light that covers the media (or on
// the animated water surface, refracted with Fresnel), marched along
// curved paths through the transparent objects' baked index grids with
// steps as large as their octrees allow (volume_photons.comp.glsl), and
// deposit the power they lose to scattering, with their direction, into a
// radiance grid over the media; the viewing pass marches the camera's
// rays through it (volume_view.frag.glsl). Internal to the runtime.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/formats/index_grid.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"
#include "gl_objects.h"
#include "scene_inputs.h"
#include "exit_ray.h"
#include "made_from.h"

namespace caustix::runtime {

class WaterSurface;

class VolumeEngine {
 public:
  // At most this many transparent objects in a scene with media (their
  // index grids are sampled from one sampler array).
  static constexpr std::size_t kMaxObjects = 4;

  // Null (and no error) when nothing in the scene scatters. `grids` are
  // the scene's IGRD chunks (one per transparent object); `scene_min_y`
  // the lowest point of the objects' world bounds (the water's medium ends
  // there); `lighting_prefix` is #version plus caustix.glsl with the
  // engine's bindings.
  static Result<std::unique_ptr<VolumeEngine>> create(const SceneDesc& scene, const std::vector<IndexGrid>& grids, float scene_min_y,
                                                      const std::string& lighting_prefix);
  ~VolumeEngine();

  // Clears last frame's statistics; re-allocates the grids if the options
  // changed their size (kUsage beyond kMaxRadianceVoxels).
  // The options' ranges, when enabled (a usage error).
  static Status check(const VolumeOptions& options);
  Status begin_frame(const SceneDesc& scene, const VolumeOptions& options);
  // Photons of light `li` into its radiance grid. `bind_light` binds the
  // light's block and shadow maps (caustix.glsl). `water` is the animated
  // surface when the scene has water. The photons are marched once per
  // sample of `waves` (traced_wavelengths), carrying the light's
  // colour times the sample's RGB weights, every index (water, glass) at
  // the sample's wavelength when `spectral` (else n_d).
  // Remade only when the light, the transforms, the water or the options
  // (`caustics`, which holds `options`) changed since (`versions`), and
  // only when `due` unless none exists; counted into `work`.
  // `focus_rays` (called only when the light is remade; may be empty)
  // gives the light's rays out of the glass: where they concentrate,
  // the focus grid takes the photons' deposits at finer voxels.
  Status update_light(const SceneDesc& scene, std::uint32_t li, const VolumeOptions& options, const WaterSurface* water,
                      const std::vector<WavelengthSample>& waves, bool spectral, const std::function<void()>& bind_light,
                      const std::function<std::vector<ExitRay>()>& focus_rays, const CausticsOptions& caustics,
                      const SceneVersions& versions, bool due, EffectWork& work);
  // The viewing pass into the bound framebuffer and viewport, through
  // `view_proj` (any camera). With `scene_color` (of the viewport's size,
  // any format gl/scene_inputs.h accepts) each pixel becomes colour x T +
  // L x scale, else L x scale is added; rays stop behind `scene_depth`.
  // `reader` copies what the bound framebuffer holds or is multisampled.
  Status draw(const SceneDesc& scene, const glm::mat4& view_proj, const gl::SceneTexture& scene_color,
              const gl::SceneTexture& scene_depth, gl::SceneReader& reader, float scale, const VolumeOptions& options);

  // Sends this frame's tallies back (after the lights' update_light).
  void end_frame(std::uint64_t frame);
  // The tallies of the latest frame whose read-back arrived (never
  // waiting), or with `wait` of the last frame (a stall).
  VolumeStats stats(bool wait);
  std::uint64_t gpu_bytes() const;

 private:
  VolumeEngine() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::runtime
