#pragma once
// The error of an irradiance image against the reference, split by cause
// (caustix-compare --split). Every pixel falls in exactly one class, tried
// in this order:
//   outside     the receiver is seen nowhere in the pixel and the reference
//               has no light there
//   silhouette  the receiver covers part of the pixel, or none of it while
//               the reference has light there
//   self-shadow covered, facing away from the light (cosine < -0.2)
//   terminator  covered, grazing light (-0.2 <= cosine < 0.2)
//   cast-shadow covered, facing the light, and the reference below 10 % of
//               its mean over the covered lit pixels (another object's
//               shadow, the dark side of a fold)
//   fold        the reference changes by more than 2x within the pixel's
//               3 x 3 neighbourhood (caustic fold lines, shadow edges)
//   slope bins  the rest, by the mean normal's |n_y|: [0, 0.2), [0.2, 0.5),
//               [0.5, 0.8), [0.8, 0.95), [0.95, 1]
// "cosine" is the mean cosine between the normal and the direction towards
// the light, and coverage and |n_y| come from the judged image's auxiliary
// image (caustix-render --aux: R coverage, G |n_y|, B cosine).

#include <cstdint>
#include <string>
#include <vector>

#include "caustix/metrics/image_metrics.h"

namespace caustix::metrics {

struct ClassError {
  std::string name;
  std::size_t pixels = 0;
  double reference = 0;  // sum of the reference's luminance
  double abs_error = 0;  // sum |A - B| of luminance
  double signed_error = 0;
  double rel_l1() const { return reference > 0 ? abs_error / reference : 0; }
  double bias() const { return reference > 0 ? signed_error / reference : 0; }
};

struct ErrorSplit {
  std::vector<ClassError> classes;   // in the order above
  std::vector<std::uint8_t> class_of;  // per pixel, an index into classes
  double total_abs_error = 0, total_reference = 0;
  // The class's share of the image's whole L1 error.
  double share(const ClassError& c) const { return total_abs_error > 0 ? c.abs_error / total_abs_error : 0; }
};

// a: the judged image, b: the reference, aux: a's auxiliary image; all the
// same size (checked by the caller).
ErrorSplit split_error(const Image& a, const Image& b, const Image& aux);

}  // namespace caustix::metrics
