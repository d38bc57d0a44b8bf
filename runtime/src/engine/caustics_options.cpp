#include "caustix/runtime/caustics_options.h"

namespace caustix::runtime {

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
  for (CausticsMethod m : {CausticsMethod::kLevelMap, CausticsMethod::kUniform, CausticsMethod::kVolumetric, CausticsMethod::kSplat,
                          CausticsMethod::kNone}) {
    if (name == to_string(m)) return m;
  }
  return std::nullopt;
}

const char* to_string(GlassMethod m) { return m == GlassMethod::kTable ? "table" : "caustic-map"; }

std::optional<GlassMethod> parse_glass_method(const std::string& name) {
  for (GlassMethod m : {GlassMethod::kTable, GlassMethod::kCausticMap}) {
    if (name == to_string(m)) return m;
  }
  return std::nullopt;
}

const char* to_string(GlassView v) { return v == GlassView::kTable ? "table" : "nearby"; }

std::optional<GlassView> parse_glass_view(const std::string& name) {
  for (GlassView v : {GlassView::kTable, GlassView::kNearby}) {
    if (name == to_string(v)) return v;
  }
  return std::nullopt;
}

const char* to_string(ShadowFilter f) { return f == ShadowFilter::kPcf ? "pcf" : "vsm"; }

std::optional<ShadowFilter> parse_shadow_filter(const std::string& name) {
  for (ShadowFilter f : {ShadowFilter::kPcf, ShadowFilter::kVsm}) {
    if (name == to_string(f)) return f;
  }
  return std::nullopt;
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
}

CausticsOptions default_caustics_options(const SceneDesc& scene) {
  CausticsOptions o;
  if (scene.render) apply_render_defaults(o, *scene.render);
  return o;
}

}  // namespace caustix::runtime
