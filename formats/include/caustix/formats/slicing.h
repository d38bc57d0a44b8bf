#pragma once
// Reference-plane placement from a depth profile (Tipprasert 2006 §4.2.1 eq. 4-6..4-9
// and §4.7.2 eq. 4-21, 4-22). Pure functions on the histogram, shared by the
// baker (bake/depth_profile.h) and the runtime (re-slicing with other plane
// counts or epsilons, and re-profiling after a light or object moves).
//
// Uniform: n pieces give n + 1 planes at D_i = h/2 - (i - 1) h/n, each
// accepting |v - D_i| < h/(2n) (eq. 4-15).
// Smart: each run of adjacent non-empty levels is a sub-box of height
// h_i = h count_i / L (eq. 4-21) with n_i = max(1, ceil(h_i / (2 eps)))
// planes (eq. 4-22, rounded up so no window is wider than eps) at the
// centres of n_i equal slabs, each accepting half its slab.

#include <cstdint>
#include <string>
#include <vector>

#include "caustix/formats/level_map.h"

namespace caustix {

std::vector<SubBox> find_sub_boxes(const std::vector<std::uint32_t>& histogram);

std::vector<ReferencePlane> uniform_planes(double height, std::uint32_t pieces);

// If eps would need more than kMaxPlanes planes it is raised until they fit;
// `used_epsilon` receives the eps actually used.
std::vector<ReferencePlane> smart_planes(double height, std::uint32_t levels, const std::vector<SubBox>& boxes,
                                         double epsilon, double* used_epsilon);

}  // namespace caustix
