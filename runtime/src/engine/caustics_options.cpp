#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"

#include <initializer_list>
#include <string>

namespace caustix::runtime {
namespace {

// The value among `all` whose to_string() is `name`.
template <class E>
std::optional<E> by_name(const std::string& name, std::initializer_list<E> all) {
  for (E e : all) {
    if (name == to_string(e)) return e;
  }
  return std::nullopt;
}

}  // namespace

const char* to_string(CausticsMethod m) {
  switch (m) {
    case CausticsMethod::kLevelMap: return "levelmap";
    case CausticsMethod::kUniform: return "uniform";
    case CausticsMethod::kVolumetric: return "volumetric";
    case CausticsMethod::kSplat: return "splat";
    case CausticsMethod::kNone: return "none";
  }
  return "?";
}

std::optional<CausticsMethod> parse_method(const std::string& name) {
  return by_name(name, {CausticsMethod::kLevelMap, CausticsMethod::kUniform, CausticsMethod::kVolumetric, CausticsMethod::kSplat,
                        CausticsMethod::kNone});
}

const char* to_string(GlassMethod m) { return m == GlassMethod::kTable ? "table" : "caustic-map"; }

std::optional<GlassMethod> parse_glass_method(const std::string& name) {
  return by_name(name, {GlassMethod::kTable, GlassMethod::kCausticMap});
}

const char* to_string(GlassView v) { return v == GlassView::kTable ? "table" : "nearby"; }

std::optional<GlassView> parse_glass_view(const std::string& name) { return by_name(name, {GlassView::kTable, GlassView::kNearby}); }

const char* to_string(ShadowFilter f) { return f == ShadowFilter::kPcf ? "pcf" : "vsm"; }

std::optional<ShadowFilter> parse_shadow_filter(const std::string& name) {
  return by_name(name, {ShadowFilter::kPcf, ShadowFilter::kVsm});
}

void apply_render_defaults(CausticsOptions& o, const RenderDefaults& render) {
  o.map_size = render.caustics_map_size;
  o.glass_map_size = render.glass_map_size;
  o.glass_planes = render.glass_planes;
  o.volume.photons = render.volume_photons;
  o.volume.grid = render.volume_grid;
  o.caustic_map.photons = render.cmap_photons;
  o.caustic_map.map_size = render.cmap_map_size;
  o.caustic_map.adaptive_levels = render.cmap_adaptive_levels;
  o.caustic_map.photon_budget = render.cmap_photon_budget;
  o.glass_focus_spectral_coarse = render.glass_spectral_coarse != 0;
  // The light side's memory budget by preset (not recorded in the file:
  // a runtime policy): fast half of balanced's, accurate twice.
  const std::uint64_t mib = std::uint64_t{1} << 20;
  o.memory_budget = render.preset == "fast" ? 64 * mib : render.preset == "accurate" ? 256 * mib : 128 * mib;
}

CausticsOptions default_caustics_options(const SceneDesc& scene) {
  CausticsOptions o;
  if (scene.render) apply_render_defaults(o, *scene.render);
  return o;
}

WaterLook default_water_look(const SceneDesc& scene) {
  WaterLook look;
  if (scene.render) look.max_texture_size = static_cast<int>(scene.render->water_texture);
  return look;
}

std::vector<WavelengthSample> traced_wavelengths(const SceneDesc& scene, const CausticsOptions& o) {
  if (o.wavelength_nm) return {WavelengthSample{*o.wavelength_nm, {1, 1, 1}}};
  return wavelength_samples(scene_disperses(scene) ? o.wavelengths : 1);
}

std::vector<WavelengthSample> water_wavelengths(const Water& water, const CausticsOptions& o) {
  if (o.wavelength_nm) return {WavelengthSample{*o.wavelength_nm, {1, 1, 1}}};
  return wavelength_samples(water.dispersion > 0 ? o.wavelengths : 1);
}

float water_index(const Water& water, const CausticsOptions& o) {
  return o.wavelength_nm ? index_at(water.ior, water.dispersion, *o.wavelength_nm) : water.ior;
}

Status check_wavelengths(const SceneDesc& scene, const CausticsOptions& o) {
  if (o.wavelengths < 1 || o.wavelengths > kMaxWavelengths) {
    return make_error(ErrorCode::kUsage, "caustics options: wavelengths must be 1.." + std::to_string(kMaxWavelengths) + ", got " +
                                             std::to_string(o.wavelengths));
  }
  if (!o.wavelength_nm) return Status::success();
  const float nm = *o.wavelength_nm;
  if (!(nm >= kMinWavelength && nm <= kMaxWavelength)) {
    return make_error(ErrorCode::kUsage, "caustics options: wavelength_nm must be in [380, 780] nm, got " + std::to_string(nm));
  }
  if (o.glass_method == GlassMethod::kTable && o.method != CausticsMethod::kNone) {
    for (const Object& obj : scene.objects) {
      if (is_transparent(obj.role) && obj.material.dispersion > 0 && obj.material.spectral_tables == 0) {
        return make_error(ErrorCode::kUsage, "caustics options: wavelength_nm: glass '" + obj.name +
                                                 "' disperses, and its light-transport table is baked at n_d only "
                                                 "(--ltt-wavelengths 0); use the caustic-map glass method for a monochromatic "
                                                 "image, or bake tables at other wavelengths");
      }
    }
  }
  return Status::success();
}

}  // namespace caustix::runtime
