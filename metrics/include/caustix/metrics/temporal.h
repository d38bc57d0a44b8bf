#pragma once
// Frame-to-frame statistics of an image stack: how much of the change from
// one frame to the next follows the motion smoothly and how much is noise
// or snapping (docs/temporal.md).
//
// rho = sum |I[k+1] - 2 I[k] + I[k-1]| / sum |I[k+1] - I[k]|, over every
// pixel's luminance and every k. Change that follows a smooth motion has
// first differences proportional to the step s and second differences to
// s^2, so rho falls in proportion to s: halving the step halves it. Change
// that is per-frame noise, or a placement that snaps, does not shrink with
// the step: rho stays where it was. The ratio of rho at half a step to rho
// at the step is 0.5 for smooth motion and 1 for noise.

#include <array>
#include <optional>
#include <vector>

#include "caustix/metrics/image_metrics.h"

namespace caustix::metrics {

struct TemporalStats {
  int frames = 0;
  double rho = 0;
  // Largest change from one frame to the next, relative to the stack's
  // mean: of the total luminance (the flux), of the brightest pixel, and
  // of the brightest pixel's second difference.
  double flux_jump = 0, peak_jump = 0, peak_second = 0;
  // With a region and a radius: the luminance power within the radius of
  // the focus, its largest change from one frame to the next relative to
  // its mean. The focus is the centre whose circle holds the most light,
  // followed from frame to frame as a local maximum: in the first frame
  // from where mean-shift steps from the brightest pixel settle, then from
  // the last frame's centre. At a maximum the power is stationary, so a
  // centre a little off changes it only to second order. Pixels count by
  // the share of their area inside the circle, so that the measure moves
  // continuously with the centre.
  std::optional<double> focus_jump;
};

// At least three frames of equal size. `region` is the images' world
// rectangle (x0, z0, x1, z1), needed for the focus.
TemporalStats temporal_stats(const std::vector<Image>& frames, const std::optional<std::array<double, 4>>& region = {},
                             double focus_radius = 0);

}  // namespace caustix::metrics
