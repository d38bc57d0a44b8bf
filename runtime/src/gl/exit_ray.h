#pragma once
// A ray of light leaving a transparent object (world space) with the flux
// it carries per unit of incident irradiance: the glass's CPU sample of its
// light-transport tables (GlassEngine::exit_sample), which places the glass's
// focus windows and the media's focus grids. Internal to the
// runtime.

#include <glm/glm.hpp>

namespace caustix::runtime {

struct ExitRay {
  glm::vec3 exit, direction;
  float flux;
};

}  // namespace caustix::runtime
