#pragma once
// The reference tracer's scene in world space: every object's triangles with
// the normals a photon needs at a hit, and the exact glass interface (Snell,
// Fresnel by Russian roulette, total internal reflection). Shared by the
// irradiance estimator (reference.cpp) and the in-scatter estimator
// (inscatter.cpp).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "caustix/bake/ray_cast.h"
#include "caustix/bake/scene_json.h"
#include "caustix/common/status.h"
#include "caustix/formats/frame.h"
#include "caustix/formats/spectrum.h"
#include "reference.h"

namespace caustix::reference {

constexpr double kPi = 3.14159265358979323846;

inline Vec3d add(const Vec3d& a, const Vec3d& b, double s = 1) { return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]}; }
inline double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline Vec3d normalize(const Vec3d& v) {
  const double n = std::sqrt(dot(v, v));
  return {v[0] / n, v[1] / n, v[2] / n};
}

using Box = std::pair<Vec3d, Vec3d>;  // lo, hi

// The root of f in [a, b], where f(a) and f(b) differ in sign: Illinois
// regula falsi, falling back to the midpoint whenever the secant leaves the
// bracket; stops when the bracket is within 1e-14 of its position, or
// cannot shrink in doubles.
template <class F>
double refine(const F& f, double a, double fa, double b, double fb) {
  int kept = 0;  // which end stayed last time: -1 a, +1 b
  for (int it = 0; it < 100 && b - a > 1e-14 * (1 + std::fabs(a)); ++it) {
    double m = (a * fb - b * fa) / (fb - fa);
    if (!(m > a && m < b)) m = 0.5 * (a + b);
    if (!(m > a && m < b)) break;
    const double fm = f(m);
    if (fm == 0) return m;
    if ((fm > 0) == (fb > 0)) {
      b = m;
      fb = fm;
      if (kept == -1) fa *= 0.5;
      kept = -1;
    } else {
      a = m;
      fa = fm;
      if (kept == +1) fb *= 0.5;
      kept = +1;
    }
  }
  return 0.5 * (a + b);
}

// Whether the point at distance s along the ray o + s d, going down, lies
// above y_clear (the top of every object's box, with a margin against
// rounding): then no triangle can be met before it, and a photon reaching
// the water surface there needs no ray cast -- the tracer's costliest
// step -- to know that the surface comes first.
inline bool surface_above(const Vec3d& o, const Vec3d& d, double s, double y_clear) { return o[1] + s * d[1] > y_clear; }

// The water surface, evaluated exactly (formats/scene.h's wave sum).
struct Surface {
  const Water& w;
  double time;
  double height(double x, double z, double* dhdx = nullptr, double* dhdz = nullptr) const {
    double h = w.level, gx = 0, gz = 0;
    for (const Wave& wave : w.waves) {
      const double k = 2 * kPi / wave.wavelength;
      const double arg = k * (wave.direction[0] * x + wave.direction[1] * z) - k * wave.speed * time + wave.phase;
      h += wave.amplitude * std::sin(arg);
      gx += wave.amplitude * k * std::cos(arg) * wave.direction[0];
      gz += wave.amplitude * k * std::cos(arg) * wave.direction[1];
    }
    if (dhdx) *dhdx = gx;
    if (dhdz) *dhdz = gz;
    return h;
  }
  double amplitude_sum() const {
    double a = 0;
    for (const Wave& wave : w.waves) a += wave.amplitude;
    return a;
  }
  double shortest_wavelength() const {
    double l = 1e30;
    for (const Wave& wave : w.waves) l = std::min(l, double{wave.wavelength});
    return l;
  }
  // A photon meeting the surface at `hit` along `dir` refracts into the
  // water with Snell (eq. 2-8) and the exact unpolarised Fresnel
  // transmittance at the true normal (the reflected part leaves for the
  // sky); nothing when it cannot enter. `ior`: the water's index at the
  // photon's wavelength (0: its n_d).
  struct Entry {
    Vec3d dir;
    double transmittance;
  };
  std::optional<Entry> enter(const Vec3d& hit, const Vec3d& dir, double ior = 0) const {
    if (ior <= 0) ior = w.ior;
    double gx = 0, gz = 0;
    height(hit[0], hit[2], &gx, &gz);
    const Vec3d nrm = normalize({-gx, 1, -gz});
    const double cos_i = -dot(dir, nrm);
    const auto t = refract(dir, nrm, 1.0 / ior);
    if (cos_i <= 0 || !t) return std::nullopt;
    return Entry{normalize(*t), fresnel_transmittance(cos_i, 1.0 / ior)};
  }
  // First crossing of the ray o + s d (going down) with the surface:
  // bracketed by steps short against the shortest wavelength, then refined
  // by regula falsi with the Illinois modification (the end that stays has
  // its value halved, so both ends close in, superlinearly): some ten
  // evaluations of the wave sum to the root within 1e-14 of s, where
  // bisection took sixty.
  std::optional<double> intersect(const Vec3d& o, const Vec3d& d) const {
    const double amp = amplitude_sum();
    if (amp == 0) return (o[1] - w.level) / -d[1];  // flat water: the plane
    const double s_max = (o[1] - (w.level - amp - 1e-6)) / -d[1];
    const double horizontal = std::hypot(d[0], d[2]);
    const double step = std::min(w.waves.empty() ? 1e30 : shortest_wavelength() / 32 / std::max(horizontal, 1e-9),
                                 std::max(2 * amp, 1e-6) / 16 / -d[1]);
    auto f = [&](double s) { return o[1] + s * d[1] - height(o[0] + s * d[0], o[2] + s * d[2]); };
    double a = 0, fa = f(0);
    for (double b = std::min(step, s_max);; b = std::min(b + step, s_max)) {
      const double fb = f(b);
      if ((fa > 0) != (fb > 0)) return refine(f, a, fa, b, fb);
      if (b >= s_max) return std::nullopt;
      a = b;
      fa = fb;
    }
  }
};


struct World {
  std::vector<Vec3d> pos;
  std::vector<std::array<std::uint32_t, 3>> tris;
  std::vector<std::uint32_t> owner;
  std::vector<Vec3d> geo_normal;     // per triangle, outward (sign of det(M) applied)
  std::vector<Vec3d> vertex_normal;  // per vertex, world (cofactor matrix), outward
  std::vector<Box> object_box;       // per object, world axis-aligned bounds
  // Smooth normal at p on triangle t (barycentric blend of the vertex
  // normals): the surface the mesh's normals describe, as a renderer
  // shades it. The flat normal where the blend degenerates.
  Vec3d normal_at(std::uint32_t t, const Vec3d& p) const;
};

// First hits for the photon loops, by where a ray starts.
// - Off every mesh (emitted above the scene, leaving the water surface, or
//   looking down from above a receiver): Embree 3 in its robust
//   (watertight) mode, several times the CGAL tree's rays per second
//   (docs/reference.md), with the distance then recomputed in doubles on
//   the hit triangle's plane, so that the hit point is as exact as CGAL's.
// - Leaving a mesh's surface (a glass interface or a mirror): CGAL's tree
//   in doubles with exact predicates (bake/ray_cast.h). Embree takes the
//   origin in floats, which can put it on the wrong side of the surface it
//   leaves (about 1e-7 of the scene's size) and meet that surface again.
//   The tree is built only for a caller that casts such rays
//   (`from_surfaces`), or when Embree could not start: then every ray goes
//   to CGAL.
class FirstHits {
 public:
  FirstHits(const std::vector<Vec3d>& pos, const std::vector<std::array<std::uint32_t, 3>>& tris,
            const std::vector<std::uint32_t>& owner, bool from_surfaces);
  std::optional<bake::RayCaster::Hit> from_space(const Vec3d& origin, const Vec3d& dir) const;
  // Only with `from_surfaces`.
  std::optional<bake::RayCaster::Hit> from_surface(const Vec3d& origin, const Vec3d& dir) const {
    return exact_->first_hit_triangle(origin, dir);
  }

 private:
  const std::vector<Vec3d>& pos_;
  const std::vector<std::array<std::uint32_t, 3>>& tris_;
  bake::EmbreeCaster fast_;
  std::optional<bake::RayCaster> exact_;
};

// Imports every object's mesh and places it in the world. A transparent
// mesh's surface is the one the baker tables: its normals smoothed only
// within creases (bake/glass_refine.h step 1; a prism's faces stay flat).
// Transparent objects whose mesh bounds no solid become thin-walled in
// doc.scene (bake::make_open_glass_thin), as caustix-bake makes them.
Result<World> load_world(bake::SceneDocument& doc, double glass_crease_deg);

// A photon (or view ray) at point p, travelling along dir, meets the glass
// triangle h.triangle: refracts or reflects by Russian roulette on the exact
// unpolarised Fresnel transmittance (total internal reflection: reflects),
// keeping its flux, so estimates stay unbiased. `inside` lists the glass
// objects it is in (overlapping shells of one material are one solid);
// n_outside is the index around the glass; nm the photon's wavelength
// (dispersion: each glass's index at it; 0: every index n_d).
// Returns the new direction.
// A thin-walled object (Role::kThin) is crossed as a sheet: reflected, or
// transmitted without bending (its inner reflections traced), `inside`
// unchanged.
// A photon carrying `power` (when given) keeps the surface's tint
// (Material::tint) of it when it is transmitted, not when reflected.
Vec3d cross_interface(const World& world, const SceneDesc& scene, std::uint32_t triangle, const Vec3d& p,
                      const Vec3d& dir, double n_outside, std::vector<std::uint32_t>& inside, double u01, double nm = 0,
                      std::array<double, 3>* power = nullptr);

// A photon's wavelength (dispersion; reference.h's
// wavelength_nm): `fixed` when > 0, weight 1 (a monochromatic image); else,
// in a scene that disperses, drawn uniformly from 380-780 nm with `power`
// times 400 nm x the CIE-to-linear-sRGB density there (an unbiased
// estimate of the spectral integral); else 0 (every index n_d) and no
// number drawn. `u01` draws a uniform number.
template <class Draw>
double photon_wavelength(double fixed, bool disperses, Draw&& u01, std::array<double, 3>& power) {
  if (fixed > 0 || !disperses) return fixed;
  const double nm = kMinWavelength + (kMaxWavelength - kMinWavelength) * u01();
  const auto w = rgb_density(nm);
  for (std::size_t c = 0; c < 3; ++c) power[c] *= (kMaxWavelength - kMinWavelength) * w[c];
  return nm;
}
// The water's index at `nm` (0: its ior, n_d).
inline double water_index_at(const Water& water, double nm) {
  return nm > 0 ? double{index_at(water.ior, water.dispersion, static_cast<float>(nm))} : double{water.ior};
}

// Bounding rectangle on the plane y = y_top of the points that reach the
// boxes along the light: parallel projection for a directional light,
// central projection from a point light above the plane.
using Rect = std::array<double, 4>;  // x0, z0, x1, z1
Rect project_boxes(const std::vector<Box>& boxes, const Light& light, double y_top);

// The image as the mean of independent batch images (RGB, in batch order:
// deterministic), with each pixel's standard error of the mean luminance
// and the relative noise over the pixels holding light.
void reduce_batches(const std::vector<std::vector<double>>& batch_images, Image& out);

}  // namespace caustix::reference
