#pragma once
// caustix-reference: an independent CPU photon tracer for irradiance images
// (docs/architecture.md), used to measure the runtime's approximations. It reads
// scene.json and the meshes (not the .cxb), evaluates the water surface of
// the wave sum exactly (ray / height-field intersection by bracketing and
// Illinois regula falsi), refracts with Snell's law and the exact unpolarised Fresnel
// transmittance at the true normal, attenuates by e^(-K d) along the true
// path, and finds receivers by exact ray-mesh intersection (CGAL AABB tree).
//
// Estimator: photons are emitted over the water's extent (directional light:
// uniformly on a horizontal plane above the highest wave, each carrying
// E0 |L_y| A / N, A the emission window: only the part of the water from
// which light can reach the image region, a conservative bound; point light:
// toward uniform points of the extent, each carrying I cos / r^2 A / N). A photon that reaches the named receiver's
// first surface seen from above is binned into its pixel with weight
// flux |n_y| / pixel area, so a pixel holds the irradiance averaged over the
// part of the surface it covers (a one-pixel box kernel: unbiased for that
// average, blurred by at most one pixel against the point value).
// Photons run in B independent, seeded batches, in parallel; the image is
// their mean, and the batches' spread gives the noise estimate. Identical
// inputs give identical images whatever the thread count.
// Glass: Fresnel by Russian roulette at every interface, total internal
// reflection, absorption inside (docs/reference.md). A transparent mesh's
// surface is the one the baker tables: its normals smoothed only within
// creases (bake/glass_refine.h step 1; a prism's faces stay flat).

#include <cstdint>
#include <string>
#include <vector>

#include "caustix/common/status.h"

namespace caustix::reference {

struct Request {
  std::string scene_path;
  std::string receiver;
  double x0 = -1, z0 = -1, x1 = 1, z1 = 1;
  int width = 128, height = 128;
  double time = 0;
  std::uint64_t photons = 4'000'000;
  std::uint32_t batches = 8;
  std::uint64_t seed = 1;
  double glass_crease_deg = 30.0;  // as caustix-bake --glass-crease
  // Dispersion: > 0, every photon at this wavelength (nm) with
  // weight 1 (a monochromatic image). 0: in a scene with dispersion each
  // photon draws its wavelength uniformly from 380-780 nm and carries 400 nm
  // times the CIE-to-linear-sRGB density there (spectrum.h rgb_density: an
  // unbiased estimate of the spectral integral); without dispersion every
  // photon is at n_d and the random sequence is the one it always was.
  double wavelength_nm = 0;
};

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;    // mean over batches, divided by E0; row 0 at z0
  std::vector<float> sigma;  // per pixel: standard error of the mean luminance
  double e0 = 1;
  double relative_noise = 0;  // mean sigma / mean value over pixels holding light
  std::uint64_t photons = 0;
  std::uint64_t photons_landed = 0;
};

Result<Image> trace(const Request& request);

// In-scatter images (docs/architecture.md): orthographic along -z,
// columns along +x over [x0, x1], row 0 at y1; each pixel the pixel-box
// average of the single-scattered radiance reaching the camera, / E0.
// Estimator (docs/reference.md): photons traced exactly as above, their
// power decaying by e^(-sigma_t s) in every medium. Along each photon
// segment in a scattering medium, stratified jittered points x (a few per
// pixel crossed) deposit sigma_s p(cos a) Phi(x) ds e^(-tau_view) / pixel
// area into the pixel of x when the straight view ray from x toward +z
// meets no surface (tau_view then the exact optical depth to the medium's
// front); a view ray that meets glass first is traced from the camera
// instead, exactly through the glass (Fresnel by Russian roulette), and
// gathers along its bent path from a track-length grid of the photons'
// power over the medium (phase from the grid's mean photon direction: exact
// for isotropic media). Opaque surfaces stop view rays.
struct InscatterRequest {
  std::string scene_path;
  double x0 = -1, y0 = -1, x1 = 1, y1 = 1;
  int width = 128, height = 128;
  std::uint64_t photons = 4'000'000;
  std::uint32_t batches = 8;
  std::uint64_t seed = 1;
  double glass_crease_deg = 30.0;
  double time = 0;             // animation time (the water's waves)
  int grid = 64;               // voxels along the medium's longest side, for views through glass
  int view_samples = 4;        // per pixel axis, for views through glass
  double samples_per_pixel = 2;  // deposit points per pixel a photon segment crosses
  // Dispersion, as ReferenceRequest::wavelength_nm for the
  // photons: > 0 every photon and view ray at this wavelength, weight 1;
  // 0 in a scene that disperses, each photon at its own drawn wavelength,
  // view rays through glass at n_d (the track-length grid they gather from
  // sums every wavelength's photons; the runtime's view march refracts at
  // n_d too).
  double wavelength_nm = 0;
};

struct InscatterStats {
  double power_in = 0;    // photon power entering media (luminance-weighted, / E0)
  double scattered = 0;   // of which scattered (the single-scattering source)
  double absorbed = 0;
  double leaving = 0;     // left the media (to surfaces, out of the box, past glass)
};

Result<Image> trace_inscatter(const InscatterRequest& request, InscatterStats* stats = nullptr);

}  // namespace caustix::reference
