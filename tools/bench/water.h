#pragma once
// caustix-bench water: ms per frame of each effect of the water surface
// (Mihalik 2008) on a baked scene, side by side in one run, and the cost of the
// refraction/reflection textures by size against Mihalik 2008's table 3.

#include <string>

namespace caustix::bench {

int water_effects(const std::string& cxb, int width, int height, int warmup, int frames, const std::string& csv);

// caustix-bench water-sim: the interactive water's cost (water_sim.h) per
// 60 Hz frame, side by side in one run: the step alone over grids of n x n
// vertices (4 m pools, c = 0.6 m/s), and on the baked scene `cxb` (if
// given) the step, the bodies' push, the hand-over to the engine and the
// whole light side (Engine::update) with simulated water against the
// scene's wave list.
int water_sim_cost(const std::string& cxb, int frames, const std::string& csv);

}  // namespace caustix::bench
