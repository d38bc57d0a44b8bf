#pragma once
// The wavelengths the camera's refracted view rays take through dispersive
// water and glass (docs/dispersion.md, "The view through water
// and glass"): the view passes shade each pixel once per sample at the
// medium's index there and add the results with the samples' RGB weights,
// as the light passes do. Internal to the runtime.

#include <vector>

#include <epoxy/gl.h>
#include <glm/glm.hpp>

#include "caustix/formats/spectrum.h"
#include "gl_objects.h"

namespace caustix::runtime {

// water.frag.glsl and glass_nearby.frag.glsl declare u_waves[32].
static_assert(kMaxWavelengths == 32, "the view shaders' u_waves[] holds kMaxWavelengths samples");

// What the last Engine::update() traced: its wavelength samples and
// whether they are a monochromatic image's (CausticsOptions::wavelength_nm).
struct ViewSpectrum {
  std::vector<WavelengthSample> waves = wavelength_samples(1);
  bool monochromatic = false;
};

// One entry per sample: xyz its bin's RGB weight, w the medium's index at
// its wavelength. A medium without dispersion gets the single sample
// (1, 1, 1, n_d), and so does one traced wavelength of an RGB image: n_d
// exactly, not the index formula at the d line (1.4e-6 off per unit of
// dispersion), as the light passes take it.
inline std::vector<glm::vec4> view_samples(const ViewSpectrum& s, float n_d, float dispersion) {
  if (dispersion <= 0.0f || (!s.monochromatic && s.waves.size() == 1))
    return {glm::vec4(1.0f, 1.0f, 1.0f, n_d)};
  std::vector<glm::vec4> out;
  out.reserve(s.waves.size());
  for (const WavelengthSample& w : s.waves) out.emplace_back(w.rgb[0], w.rgb[1], w.rgb[2], index_at(n_d, dispersion, w.nm));
  return out;
}

// Sets u_wave_count and u_waves[].
inline void set_view_samples(const gl::Program& p, const std::vector<glm::vec4>& samples) {
  p.set("u_wave_count", static_cast<int>(samples.size()));
  glProgramUniform4fv(p.id(), p.loc("u_waves"), static_cast<GLsizei>(samples.size()), &samples[0][0]);
}

} // namespace caustix::runtime
