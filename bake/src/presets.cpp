#include "caustix/bake/presets.h"

#include <array>

namespace caustix::bake {
namespace {

// Each knob's effect on cost and error is measured in docs/tradeoff.md
// (docs/results/tradeoff_*.csv); the values below are read off those sweeps.
BakeOptions make(std::uint32_t planes, std::uint32_t levels, std::uint32_t position_map, double water_grid_scale,
                 std::uint32_t ltt_resolution, std::uint32_t caustics_map, std::uint32_t glass_map, const char* name) {
  BakeOptions o;
  o.level_maps.slicing.planes = planes;
  o.level_maps.slicing.levels = levels;
  o.level_maps.map_size = position_map;
  o.water_grid_scale = water_grid_scale;
  o.transport.resolution = ltt_resolution;
  o.render = RenderDefaults{name, caustics_map, glass_map, RenderDefaults{}.glass_planes};
  return o;
}

const std::array<Preset, 3> kPresets{{
    {"fast", "half the water grid, 8 planes, 256^2 maps, R = 12 transport tables",
     make(8, 16, 256, 0.5, 12, 256, 256, "fast")},
    {"balanced", "the built-in defaults: scene.json's water grid, 32 planes, 512^2 maps, R = 20 tables",
     make(32, 64, 512, 1.0, 20, 512, 512, "balanced")},
    {"accurate", "twice the water grid, 64 planes, 1024^2 maps, R = 32 tables",
     make(64, 256, 1024, 2.0, 32, 1024, 1024, "accurate")},
}};

}  // namespace

std::span<const Preset> presets() { return kPresets; }

const Preset* find_preset(std::string_view name) {
  for (const Preset& p : kPresets) {
    if (name == p.name) return &p;
  }
  return nullptr;
}

}  // namespace caustix::bake
