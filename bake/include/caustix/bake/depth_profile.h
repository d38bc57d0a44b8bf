#pragma once
// Reference planes (Tipprasert 2006 §4.2.1, eq. 4-6..4-9) and the depth profile with
// smart slicing (§4.7.2, eq. 4-21, 4-22).
//
// Uniform slicing follows the thesis exactly: n pieces give n + 1 planes at
// D_i = h/2 - (i - 1) h/n, i = 1..n+1, each accepting |v - D_i| < h/(2n)
// (eq. 4-15: half the plane spacing).
//
// Smart slicing: the position map's depths are binned into L levels (level 0
// nearest the light); levels holding no texel are empty; each run of
// adjacent valid levels is a sub-box of height h_i = h * count_i / L
// (eq. 4-21). A sub-box gets n_i = max(1, ceil(h_i / (2 eps))) planes
// (eq. 4-22 with the ratio rounded up, so no acceptance window is wider than
// the eps asked for), at the centres of n_i equal slabs, each accepting half
// its slab: the windows tile exactly the valid levels, so each receiver
// point is accepted by exactly one plane.

#include <cstdint>
#include <optional>
#include <string>

#include "caustix/formats/level_map.h"

namespace caustix::bake {

struct SlicingOptions {
  std::uint32_t planes = 32;       // n: uniform slicing into n pieces (n + 1 planes)
  std::optional<double> epsilon;   // metres; default: h / (2n), the uniform slicing's
  std::uint32_t levels = 64;       // L
  Slicing slicing = Slicing::kSmart;
};

// Fills histogram, sub-boxes, both plane sets, epsilon and slicing of `map`
// (whose frame and depth must be set). If eps would need more than
// kMaxPlanes smart planes, it is raised to fit and `warning` says so.
void build_depth_profile(LevelMap& map, const SlicingOptions& options, std::string* warning);

}  // namespace caustix::bake
