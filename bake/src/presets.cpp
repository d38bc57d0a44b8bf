#include "caustix/bake/presets.h"

#include <array>

namespace caustix::bake {
namespace {

// Each knob's effect on cost and error is measured in docs/tradeoff.md
// (docs/results/tradeoff_*.csv); the values below are read off those sweeps.
BakeOptions make(std::uint32_t planes, std::uint32_t levels, std::uint32_t position_map, double water_grid_scale,
                 std::uint32_t ltt_resolution, double glass_turn, std::uint32_t caustics_map, std::uint32_t glass_map,
                 std::uint32_t volume_res, float octree_eps, std::uint32_t volume_photons, std::uint32_t volume_grid,
                 std::uint32_t cmap_photons, std::uint32_t cmap_map, std::uint32_t cmap_levels, std::uint32_t water_texture,
                 bool glass_spectral_coarse, const char* name) {
  BakeOptions o;
  o.level_maps.slicing.planes = planes;
  o.level_maps.slicing.levels = levels;
  o.level_maps.map_size = position_map;
  o.water_grid_scale = water_grid_scale;
  o.transport.resolution = ltt_resolution;
  o.glass_refine.max_turn_deg = glass_turn;
  o.index_grid.resolution = volume_res;
  o.index_grid.epsilon = octree_eps;
  o.render = RenderDefaults{name,          caustics_map, glass_map, RenderDefaults{}.glass_planes, volume_photons, volume_grid,
                            cmap_photons, cmap_map,     cmap_levels, RenderDefaults{}.cmap_photon_budget};
  if (cmap_levels > 0) o.render->cmap_photon_budget = 1u << 19;
  o.render->water_texture = water_texture;
  o.render->glass_spectral_coarse = glass_spectral_coarse ? 1 : 0;
  return o;
}

// The water grid is the lever with the largest effect on both cost and
// error (accurate sits at its knee: thesis_teapot 0.0183 / 0.0173 / 0.0171
// at 2x / 3x / 4x per axis, for 1.0 / 1.5 / 2.3 times the frame time of 2x
// on llvmpipe); planes beyond 4-8 buy nothing measurable on the canonical
// scenes and cost time; the caustics map must keep a floor 16 m wide (wavy_pool)
// at 512^2 or finer (1024^2 halves its error but costs 1.7x on the teapot
// for nothing there); the position map is cheapest at 512^2 or more; glass
// textures above 512^2 and curved-glass refinement (--glass-turn 5) buy
// glass_ball's focal spot (error 0.0301 -> 0.0217 together) at about 3x
// the frame time on llvmpipe (docs/tradeoff.md), so only accurate has them.
// Media (docs/volume.md, docs/results/tradeoff_fog_ball.csv): the photon
// count stops paying at 128^2-256^2 per light (the track-length deposits
// need few photons); the radiance grid is the lever (fog_ball 4.4 / 3.7 /
// 3.3 % at 16 / 32 / 64 voxels); the index grid and its octree threshold
// barely move the image and cost the bake little. Caustic maps
// (docs/caustic-maps.md, docs/results/caustic_maps.csv): the caustic map's
// size is the lever (glass_ball 6.3 / 4.5 % at 512^2 / 1024^2); photons
// beyond the map's texels buy little, so accurate traces an adaptive 1024^2
// grid within 2^19 photons and fast halves both. Dispersive glass's focus
// windows (docs/glass-focus.md, "A window per wavelength"): at half their texels
// a side the dispersive ball's frame with the light turning costs +22.6 %
// instead of +26.2 % on llvmpipe (the bound is 25 %), its lines
// within 1 cm move by 0.6-1.6 points and its d line's brightest 2 mm by 20
// points, so accurate draws them at their own texels.
const std::array<Preset, 3> kPresets{{
    {"fast", "half the water grid per axis, 4 planes, 512^2 maps, R = 12 transport tables, 256^2 glass textures; media: "
             "48-voxel index grids (octree eps 0.02), 128^2 photons, 32-voxel radiance grid; caustic maps: 256^2 photons, 256^2 map; "
             "water textures at most 256^2; dispersive glass's focus windows at half their texels",
     make(4, 64, 512, 0.5, 12, 0, 512, 256, 48, 0.02f, 128, 32, 256, 256, 0, 256, true, "fast")},
    {"balanced", "scene.json's water grid, 8 planes, 512^2 maps, R = 20 transport tables, 512^2 glass textures; media: "
                 "64-voxel index grids (octree eps 0.01), 256^2 photons, 64-voxel radiance grid; caustic maps: 512^2 photons, 512^2 map; "
                 "water textures at most 512^2; dispersive glass's focus windows at half their texels",
     make(8, 64, 512, 1.0, 20, 0, 512, 512, 64, 0.01f, 256, 64, 512, 512, 0, 512, true, "balanced")},
    {"accurate",
     "three times the water grid per axis, 16 planes, 1024^2 maps, R = 32 transport tables, curved glass refined to 5 "
     "degrees per edge, 1024^2 glass textures; media: 96-voxel index grids (octree eps 0.005), 512^2 photons, "
     "96-voxel radiance grid; caustic maps: adaptive over a 1024^2 grid (2 levels, at most 2^19 photons), 1024^2 map; "
     "water textures a texel per pixel; dispersive glass's focus windows at their own texels",
     make(16, 256, 1024, 3.0, 32, 5, 1024, 1024, 96, 0.005f, 512, 96, 1024, 1024, 2, 0, false, "accurate")},
}};

}  // namespace

std::span<const Preset> presets() { return kPresets; }

const Preset* find_preset(std::string_view name) {
  for (const Preset& p : kPresets) {
    if (name == p.name) return &p;
  }
  return nullptr;
}

void apply_preset(const Preset& preset, BakeOptions& opt, const std::function<bool(std::string_view flag)>& given) {
  const BakeOptions& p = preset.options;
  auto unless_given = [&](std::string_view flag, auto& value, const auto& preset_value) {
    if (!given || !given(flag)) value = preset_value;
  };
  auto& lm = opt.level_maps;
  unless_given("--position-bits", opt.draco.position_bits, p.draco.position_bits);
  unless_given("--normal-bits", opt.draco.normal_bits, p.draco.normal_bits);
  unless_given("--draco-speed", opt.draco.speed, p.draco.speed);
  unless_given("--planes", lm.slicing.planes, p.level_maps.slicing.planes);
  unless_given("--levels", lm.slicing.levels, p.level_maps.slicing.levels);
  unless_given("--map-size", lm.map_size, p.level_maps.map_size);
  unless_given("--water-grid-scale", opt.water_grid_scale, p.water_grid_scale);
  unless_given("--ltt-resolution", opt.transport.resolution, p.transport.resolution);
  unless_given("--ltt-bounces", opt.transport.max_bounces, p.transport.max_bounces);
  unless_given("--ltt-bits", opt.transport.bits, p.transport.bits);
  unless_given("--ltt-wavelengths", opt.transport.wavelengths, p.transport.wavelengths);
  unless_given("--glass-crease", opt.glass_refine.crease_deg, p.glass_refine.crease_deg);
  unless_given("--glass-edge", opt.glass_refine.max_edge, p.glass_refine.max_edge);
  unless_given("--glass-turn", opt.glass_refine.max_turn_deg, p.glass_refine.max_turn_deg);
  unless_given("--epsilon", lm.slicing.epsilon, p.level_maps.slicing.epsilon);
  opt.render = p.render;
}

}  // namespace caustix::bake
