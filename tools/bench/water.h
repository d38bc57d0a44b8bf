#pragma once
// caustix-bench water: ms per frame of each effect of the water surface
// (seed 001) on a baked scene, side by side in one run, and the cost of the
// refraction/reflection textures by size against the seed's table 3.

#include <string>

namespace caustix::bench {

int water_effects(const std::string& cxb, int width, int height, int warmup, int frames, const std::string& csv);

}  // namespace caustix::bench
