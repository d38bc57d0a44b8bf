#pragma once
// Closed-form optics the tests check against, written independently of the
// runtime's shaders and the reference tracer.

#include <cmath>

namespace caustix::test {

inline constexpr double kPi = 3.14159265358979323846;

// Unpolarised Fresnel transmittance from air into a medium of index n.
inline double fresnel_t(double cos_i, double n) {
  const double sin_t = std::sqrt(1 - cos_i * cos_i) / n, cos_t = std::sqrt(1 - sin_t * sin_t);
  const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t), rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  return 1 - 0.5 * (rs * rs + rp * rp);
}

}  // namespace caustix::test
