#pragma once
// Plain vector types of the on-disk scene model.

#include <array>

namespace caustix {

using Vec2f = std::array<float, 2>;
using Vec3f = std::array<float, 3>;
using Mat4f = std::array<float, 16>;  // column-major, object -> world

}  // namespace caustix
