// In-scatter images by photon tracing (reference.h, trace_inscatter;
// docs/reference.md "Media"). Single scattering only: a photon's power
// decays by e^(-sigma_t s) in every medium and what it loses to scattering
// is the source the camera sees; nothing is scattered twice.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "reference.h"
#include "world.h"

namespace caustix::reference {
namespace {

using Rgb = std::array<double, 3>;

double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

// One homogeneous medium: extinction sigma_t = sigma_s + sigma_a, and the
// phase function.
struct Coeff {
  Rgb st{0, 0, 0}, ss{0, 0, 0};
  Phase phase = Phase::kIsotropic;
  double k = 0;
  bool any() const { return st[0] > 0 || st[1] > 0 || st[2] > 0; }
  bool scatters() const { return ss[0] > 0 || ss[1] > 0 || ss[2] > 0; }
  // Pfeuti, "Viewing Pass": isotropic 1/(4 pi); Schlick
  // (1/(4 pi)) (1 - k^2) / (1 - k cos a)^2, a between the light's direction
  // of travel and the scattered direction.
  double phase_value(double cos_a) const {
    if (phase != Phase::kSchlick) return 1.0 / (4 * kPi);
    const double d = 1 - k * cos_a;
    return (1 - k * k) / (4 * kPi * d * d);
  }
};

Coeff coeff_of(const Vec3f& absorption, const Scattering& s) {
  Coeff c;
  for (std::size_t i = 0; i < 3; ++i) {
    c.ss[i] = s.coefficient[i];
    c.st[i] = double{s.coefficient[i]} + double{absorption[i]};
  }
  c.phase = s.phase;
  c.k = s.anisotropy;
  return c;
}

// Power a beam starting with `p` keeps after `len` in medium `m`.
Rgb attenuate(const Rgb& p, const Coeff& m, double len) {
  return {p[0] * std::exp(-m.st[0] * len), p[1] * std::exp(-m.st[1] * len), p[2] * std::exp(-m.st[2] * len)};
}
// Integral over [a, b] of p e^(-sigma_t s): a beam's power times length.
double power_length(double p, double st, double a, double b) {
  return st * (b - a) < 1e-9 ? p * (b - a) * std::exp(-st * a) : p * (std::exp(-st * a) - std::exp(-st * b)) / st;
}

// Parameter range [t0, t1] of the ray o + t d inside the box.
bool slab(const Box& b, const Vec3d& o, const Vec3d& d, double& t0, double& t1) {
  t0 = -1e300;
  t1 = 1e300;
  for (std::size_t k = 0; k < 3; ++k) {
    if (std::fabs(d[k]) < 1e-300) {
      if (o[k] < b.first[k] || o[k] > b.second[k]) return false;
      continue;
    }
    double a = (b.first[k] - o[k]) / d[k], c = (b.second[k] - o[k]) / d[k];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
  }
  return t0 < t1;
}

// Track-length estimate of the photons' power over the media (for the view
// rays that reach the media through glass): per voxel, the sum of power x
// length (RGB) and the luminance-weighted sum of directions.
struct Grid {
  Box box;
  int n[3] = {1, 1, 1};
  double h[3] = {1, 1, 1};
  std::vector<float> power, moment;  // 3 per voxel each

  Grid(const Box& b, int longest) : box(b) {
    const double ext[3] = {b.second[0] - b.first[0], b.second[1] - b.first[1], b.second[2] - b.first[2]};
    const double side = std::max({ext[0], ext[1], ext[2]}) / longest;
    for (int k = 0; k < 3; ++k) {
      n[k] = std::max(1, static_cast<int>(std::ceil(ext[k] / side - 1e-9)));
      h[k] = ext[k] / n[k];
    }
    const std::size_t voxels = std::size_t(n[0]) * std::size_t(n[1]) * std::size_t(n[2]);
    power.assign(3 * voxels, 0.0f);
    moment.assign(3 * voxels, 0.0f);
  }
  std::size_t index(int i, int j, int k) const { return (std::size_t(k) * std::size_t(n[1]) + std::size_t(j)) * std::size_t(n[0]) + std::size_t(i); }

  // Exact voxel traversal (Amanatides and Woo) of the beam o + s d over
  // [a, b], its power p at s = a decaying in medium m.
  void deposit(const Vec3d& o, const Vec3d& d, double a, double b, const Rgb& p, const Coeff& m) {
    double g0 = 0, g1 = 0;
    if (!slab(box, o, d, g0, g1)) return;
    const double s_begin = std::max(a, g0), s_end = std::min(b, g1);
    if (!(s_end > s_begin)) return;
    const Vec3d start = add(o, d, 0.5 * (s_begin + std::min(s_end, s_begin + 1e-9)));
    int cell[3], step[3];
    double next[3], delta[3];
    for (int k = 0; k < 3; ++k) {
      cell[k] = std::clamp(static_cast<int>((start[k] - box.first[k]) / h[k]), 0, n[k] - 1);
      step[k] = d[k] > 0 ? 1 : -1;
      if (std::fabs(d[k]) < 1e-300) {
        next[k] = delta[k] = 1e300;
        continue;
      }
      const double boundary = box.first[k] + (cell[k] + (d[k] > 0 ? 1 : 0)) * h[k];
      next[k] = (boundary - o[k]) / d[k];
      delta[k] = h[k] / std::fabs(d[k]);
    }
    double s = s_begin;
    while (s < s_end) {
      const int axis = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
      const double e = std::min(next[axis], s_end);
      if (e > s) {
        const std::size_t v = index(cell[0], cell[1], cell[2]);
        Rgb pl;
        for (std::size_t c = 0; c < 3; ++c) {
          pl[c] = power_length(p[c], m.st[c], s - a, e - a);
          power[3 * v + c] += static_cast<float>(pl[c]);
        }
        const double lum = luminance(pl);
        for (std::size_t c = 0; c < 3; ++c) moment[3 * v + c] += static_cast<float>(lum * d[c]);
      }
      s = e;
      cell[axis] += step[axis];
      next[axis] += delta[axis];
      if (cell[axis] < 0 || cell[axis] >= n[axis]) break;
    }
  }

  // Trilinear fluence (power x length / volume, W/m^2) and mean photon
  // direction at x.
  void sample(const Vec3d& x, Rgb& fluence, Vec3d& mean_dir) const {
    fluence = {0, 0, 0};
    Vec3d m{0, 0, 0};
    double f[3];
    int i0[3];
    for (int k = 0; k < 3; ++k) {
      const double u = (x[k] - box.first[k]) / h[k] - 0.5;
      i0[k] = static_cast<int>(std::floor(u));
      f[k] = u - i0[k];
    }
    const double volume = h[0] * h[1] * h[2];
    for (int c = 0; c < 8; ++c) {
      int idx[3];
      double w = 1;
      for (int k = 0; k < 3; ++k) {
        const int bit = (c >> k) & 1;
        idx[k] = std::clamp(i0[k] + bit, 0, n[k] - 1);
        w *= bit ? f[k] : 1 - f[k];
      }
      const std::size_t v = index(idx[0], idx[1], idx[2]);
      for (std::size_t ch = 0; ch < 3; ++ch) {
        fluence[ch] += w * power[3 * v + ch] / volume;
        m[ch] += w * moment[3 * v + ch];
      }
    }
    const double l = std::sqrt(dot(m, m));
    mean_dir = l > 0 ? Vec3d{m[0] / l, m[1] / l, m[2] / l} : Vec3d{0, -1, 0};
  }
};

constexpr int kMaxInteractions = 64;

}  // namespace

Result<Image> trace_inscatter(const InscatterRequest& q, InscatterStats* stats) {
  auto doc = bake::load_scene(q.scene_path);
  if (!doc) return doc.error();
  const SceneDesc& scene = doc->scene;
  if (!(q.x1 > q.x0) || !(q.y1 > q.y0) || q.width < 1 || q.height < 1 || q.width > 16384 || q.height > 16384 ||
      q.batches < 1 || q.photons < q.batches || q.grid < 2 || q.grid > 512 || q.view_samples < 1 ||
      q.view_samples > 64 || !(q.samples_per_pixel > 0 && q.samples_per_pixel <= 64) ||
      !(q.wavelength_nm == 0 || (q.wavelength_nm >= kMinWavelength && q.wavelength_nm <= kMaxWavelength))) {
    return make_error(ErrorCode::kUsage, "region, size, batches, photon count, grid, samples or wavelength out of range");
  }
  const bool disperses = scene_disperses(scene) || q.wavelength_nm > 0;
  if (!scene_scatters(scene)) {
    return make_error(ErrorCode::kInput, q.scene_path + ": nothing in the scene scatters light (no medium, water or glass with \"scattering\")");
  }
  if (scene.water && scene.medium) {
    return make_error(ErrorCode::kInput, q.scene_path + ": the in-scatter reference traces water or a medium box, not both in one scene yet");
  }
  for (const Object& o : scene.objects) {
    if (o.role == Role::kBoth) {
      return make_error(ErrorCode::kInput, q.scene_path + ": object '" + o.name +
                                               "' is both receiver and transparent; the reference traces either, not both");
    }
  }
  auto loaded = load_world(*doc, q.glass_crease_deg);
  if (!loaded) return loaded.error();
  const World& world = *loaded;
  const bake::RayCaster caster(world.pos, world.tris, world.owner);

  // What the photons can reach: the medium box and every glass object
  // (light refracted into the box, or scattered inside milky glass).
  std::vector<Box> targets;
  std::optional<Box> medium_box;
  Coeff medium;
  if (scene.medium) {
    const auto& e = scene.medium->extent;
    medium_box = Box{{e[0], e[1], e[2]}, {e[3], e[4], e[5]}};
    targets.push_back(*medium_box);
    medium = coeff_of(scene.medium->absorption, scene.medium->scattering);
  }
  // Water (light shafts): the medium under the surface within the water
  // grid's extent. Photons enter it through the exact wave surface; in-scatter
  // view rays are not bent by the surface (docs/volume.md).
  const Water* water = scene.water ? &*scene.water : nullptr;
  const Water flat{};
  const Surface surface{water ? *water : flat, q.time};
  std::optional<Box> water_box;
  Coeff water_coeff;
  if (water) {
    double floor_y = 1e300;
    for (const Box& b : world.object_box) floor_y = std::min(floor_y, b.first[1]);
    floor_y = std::min(floor_y, double{water->level}) - 1.0;
    water_box = Box{{water->extent[0], floor_y, water->extent[1]},
                    {water->extent[2], water->level + surface.amplitude_sum() + 1e-3, water->extent[3]}};
    water_coeff = coeff_of(water->absorption, water->scattering);
    if (water_coeff.scatters()) targets.push_back(*water_box);
  }
  std::vector<Coeff> glass(scene.objects.size());
  bool has_glass = false;
  double y_top = medium_box ? medium_box->second[1] : -1e300;
  double scene_size = 1;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    y_top = std::max(y_top, world.object_box[i].second[1]);
    for (std::size_t k = 0; k < 3; ++k) {
      scene_size = std::max({scene_size, std::fabs(world.object_box[i].first[k]), std::fabs(world.object_box[i].second[k])});
    }
    if (!transmits(o.role)) continue;
    has_glass = true;
    glass[i] = coeff_of(o.material.absorption, o.material.scattering);
    targets.push_back(world.object_box[i]);
  }
  if (water_box) y_top = std::max(y_top, water_box->second[1]);
  y_top += 1e-3;
  const double eps = 1e-7 * scene_size;
  for (const Light& light : scene.lights) {
    if (light.type == LightType::kPoint && !(light.position[1] > y_top)) {
      return make_error(ErrorCode::kInput, q.scene_path + ": light '" + light.name +
                                               "' is not above the scene; the reference emits from above only");
    }
  }
  const double e0 = scene_e0(scene);

  // The grid covers the medium and the scattering glass: where view rays
  // through glass gather.
  std::optional<Box> grid_box;
  if (has_glass) {
    for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
      const bool around = (medium_box && medium.scatters()) || (water_box && water_coeff.scatters());
      if (!glass[i].scatters() && !around) continue;
      Box b = glass[i].scatters() ? world.object_box[i] : medium_box ? *medium_box : *water_box;
      if (!grid_box) grid_box = b;
      for (std::size_t k = 0; k < 3; ++k) {
        grid_box->first[k] = std::min(grid_box->first[k], b.first[k]);
        grid_box->second[k] = std::max(grid_box->second[k], b.second[k]);
      }
    }
  }

  const double dx = (q.x1 - q.x0) / q.width, dy = (q.y1 - q.y0) / q.height;
  const double pixel = std::min(dx, dy);
  const std::size_t pixels = std::size_t(q.width) * std::size_t(q.height);
  const std::uint64_t per_batch = q.photons / q.batches;
  std::vector<std::vector<double>> batch_images(q.batches, std::vector<double>(pixels * 3, 0.0));
  std::vector<InscatterStats> batch_stats(q.batches);

  // The medium a photon or view ray is in: the innermost glass, else the
  // medium box over its slab.
  struct Piece {
    const Coeff* m = nullptr;
    double a = 0, b = 0;
  };
  // in_water: a photon that crossed the surface; view rays are in water
  // below the rest level (the surface does not bend them).
  auto piece_of = [&](const std::vector<std::uint32_t>& inside, const Vec3d& o, const Vec3d& d, double len,
                      bool in_water) {
    Piece piece;
    if (!inside.empty()) {
      piece = {&glass[inside.back()], 0, len};
    } else if (water_box && in_water) {
      double t0 = 0, t1 = 0;
      if (slab(*water_box, o, d, t0, t1)) piece = {&water_coeff, std::max(0.0, t0), std::min(len, t1)};
    } else if (medium_box) {
      double t0 = 0, t1 = 0;
      if (slab(*medium_box, o, d, t0, t1)) piece = {&medium, std::max(0.0, t0), std::min(len, t1)};
    }
    if (piece.m && (!piece.m->any() || !(piece.b > piece.a))) piece.m = nullptr;
    return piece;
  };
  // Whether the straight view ray from x toward the camera (+z) is free:
  // a ray cast only where some object's box lies in front of x.
  auto seen_directly = [&](const Vec3d& x) {
    for (const Box& b : world.object_box) {
      if (x[0] >= b.first[0] && x[0] <= b.second[0] && x[1] >= b.first[1] && x[1] <= b.second[1] && x[2] < b.second[2]) {
        return !caster.first_hit(x, {0, 0, 1}).has_value();
      }
    }
    return true;
  };

  tbb::parallel_for(std::uint32_t{0}, q.batches, [&](std::uint32_t batch) {
    std::mt19937_64 rng(q.seed * 0x9E3779B97F4A7C15ull + batch + 1);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<double>& img = batch_images[batch];
    InscatterStats& st = batch_stats[batch];
    std::optional<Grid> grid;
    if (grid_box) grid.emplace(*grid_box, q.grid);
    std::vector<std::uint32_t> inside;

    // Photons (the light side).
    for (const Light& light : scene.lights) {
      const Rect win = project_boxes(targets, light, y_top);
      if (!(win[2] > win[0]) || !(win[3] > win[1])) continue;
      const double area = (win[2] - win[0]) * (win[3] - win[1]);
      for (std::uint64_t n = 0; n < per_batch; ++n) {
        const double px = win[0] + (win[2] - win[0]) * u01(rng), pz = win[1] + (win[3] - win[1]) * u01(rng);
        Vec3d origin{px, y_top, pz}, dir;
        double flux;
        if (light.type == LightType::kDirectional) {
          dir = normalize({light.direction[0], light.direction[1], light.direction[2]});
          if (dir[1] >= 0) continue;
          flux = light.irradiance * -dir[1] * area / double(per_batch);
        } else {
          const Vec3d lp{light.position[0], light.position[1], light.position[2]};
          const Vec3d to = add(origin, lp, -1);
          const double r2 = dot(to, to);
          dir = normalize(to);
          flux = light.intensity * -dir[1] / r2 * area / double(per_batch) *
                 spot_factor(light, {static_cast<float>(dir[0]), static_cast<float>(dir[1]), static_cast<float>(dir[2])});
        }
        Rgb power{flux * light.color[0] / e0, flux * light.color[1] / e0, flux * light.color[2] / e0};
        const double nm = photon_wavelength(q.wavelength_nm, disperses, [&] { return u01(rng); }, power);
        const double n_water = water ? water_index_at(*water, nm) : 1.0;
        bool in_medium = false, in_water = false;
        inside.clear();
        for (int step = 0; step < kMaxInteractions; ++step) {
          const auto h = caster.first_hit_triangle(add(origin, dir, eps), dir);
          // Above the water, the surface may come first: refract into it,
          // as the irradiance estimator does.
          if (water && !in_water && inside.empty() && dir[1] < 0) {
            const auto sh = surface.intersect(origin, dir);
            const Vec3d hit = sh ? add(origin, dir, *sh) : origin;
            const bool in_extent = hit[0] >= water_box->first[0] && hit[0] <= water_box->second[0] &&
                                   hit[2] >= water_box->first[2] && hit[2] <= water_box->second[2];
            if (sh && in_extent && (!h || *sh < h->distance + eps)) {
              const auto entry = surface.enter(hit, dir, n_water);
              if (!entry) break;
              for (double& c : power) c *= entry->transmittance;
              origin = hit;
              dir = entry->dir;
              in_water = true;
              continue;
            }
          }
          const double len = h ? h->distance + eps : 1e30;
          const Piece piece = piece_of(inside, origin, dir, len, in_water);
          if (piece.m) {
            const Coeff& m = *piece.m;
            if (!in_medium) st.power_in += luminance(power);
            in_medium = true;
            const double length = piece.b - piece.a;
            if (m.scatters()) {
              // Stratified, jittered points along the piece: about
              // samples_per_pixel per pixel its image crosses.
              const double projected = length * std::hypot(dir[0], dir[1]);
              const double count = std::clamp(std::ceil(q.samples_per_pixel * std::max(projected / pixel, 1.0)), 1.0, 1e6);
              const auto samples = static_cast<std::uint64_t>(count);
              const double ds = length / count;
              const double cos_a = dir[2];  // travel vs. the scattered direction toward the camera (+z)
              const double phase = m.phase_value(cos_a) / (dx * dy);
              for (std::uint64_t i = 0; i < samples; ++i) {
                const double s = (double(i) + u01(rng)) * ds;
                const Vec3d x = add(origin, dir, piece.a + s);
                const double col = (x[0] - q.x0) / dx, row = (q.y1 - x[1]) / dy;
                if (col < 0 || row < 0 || col >= q.width || row >= q.height) continue;
                if (!seen_directly(x)) continue;
                // Only the medium box, or the water, lies between x and the
                // camera.
                const double view = piece.m == &medium      ? std::max(0.0, medium_box->second[2] - x[2])
                                    : piece.m == &water_coeff ? std::max(0.0, water_box->second[2] - x[2])
                                                              : 0.0;
                const std::size_t pix = std::size_t(row) * std::size_t(q.width) + std::size_t(col);
                for (std::size_t c = 0; c < 3; ++c) {
                  img[3 * pix + c] += power[c] * std::exp(-m.st[c] * (s + view)) * m.ss[c] * phase * ds;
                }
              }
            }
            if (grid) grid->deposit(origin, dir, piece.a, piece.b, power, m);
            // What the piece took, split between scattering and absorption.
            const Rgb after = attenuate(power, m, length);
            Rgb scattered{0, 0, 0}, absorbed{0, 0, 0};
            for (std::size_t c = 0; c < 3; ++c) {
              if (!(m.st[c] > 0)) continue;
              const double lost = (power[c] - after[c]) / m.st[c];
              scattered[c] = lost * m.ss[c];
              absorbed[c] = lost * (m.st[c] - m.ss[c]);
            }
            st.scattered += luminance(scattered);
            st.absorbed += luminance(absorbed);
            power = after;
            if (piece.b < len) {  // left the medium before the next surface
              st.leaving += luminance(power);
              in_medium = false;
            }
          } else if (in_medium) {
            st.leaving += luminance(power);  // into clear glass or air
            in_medium = false;
          }
          if (!h) break;
          const Vec3d p = add(origin, dir, len);
          if (!transmits(scene.objects[world.owner[h->triangle]].role)) break;
          dir = cross_interface(world, scene, h->triangle, p, dir, in_water ? n_water : 1.0, inside, u01(rng), nm, &power);
          origin = p;
        }
        if (in_medium) st.leaving += luminance(power);  // absorbed by a surface, or out of the loop
      }
    }

    // View rays that meet glass before the media (the camera side).
    if (!grid) return;
    double z_front = medium_box ? medium_box->second[2] : water_box ? water_box->second[2] : -1e300;
    for (const Box& b : world.object_box) z_front = std::max(z_front, b.second[2]);
    z_front += 1.0;
    const double step_len = 0.5 * std::min({grid->h[0], grid->h[1], grid->h[2]});
    const double spp = double(q.view_samples) * double(q.view_samples);
    const double view_water = water ? water_index_at(*water, q.wavelength_nm) : 1.0;  // n_d unless monochromatic
    for (int row = 0; row < q.height; ++row) {
      for (int col = 0; col < q.width; ++col) {
        Rgb sum{0, 0, 0};
        for (int sy = 0; sy < q.view_samples; ++sy) {
          for (int sx = 0; sx < q.view_samples; ++sx) {
            Vec3d origin{q.x0 + (col + (sx + u01(rng)) / q.view_samples) * dx,
                         q.y1 - (row + (sy + u01(rng)) / q.view_samples) * dy, z_front};
            Vec3d dir{0, 0, -1};
            auto h = caster.first_hit_triangle(origin, dir);
            if (!h || !transmits(scene.objects[world.owner[h->triangle]].role)) continue;
            // Extinction in front of the glass.
            Rgb tau{0, 0, 0};
            Rgb through{1, 1, 1};  // the glass surfaces' tints crossed so far
            inside.clear();
            const auto wet = [&](const Vec3d& x) { return water && x[1] < water->level; };
            if (const Piece front = piece_of(inside, origin, dir, h->distance, wet(add(origin, dir, h->distance))); front.m) {
              for (std::size_t c = 0; c < 3; ++c) tau[c] += front.m->st[c] * (front.b - front.a);
            }
            origin = add(origin, dir, h->distance);
            dir = cross_interface(world, scene, h->triangle, origin, dir, wet(origin) ? view_water : 1.0, inside, u01(rng), q.wavelength_nm,
                                  &through);
            for (int k = 0; k < kMaxInteractions; ++k) {
              h = caster.first_hit_triangle(add(origin, dir, eps), dir);
              const double len = h ? h->distance + eps : 1e30;
              const Piece piece = piece_of(inside, origin, dir, len, wet(origin));
              if (piece.m) {
                const Coeff& m = *piece.m;
                if (m.scatters()) {
                  const double length = piece.b - piece.a;
                  const double count = std::clamp(std::ceil(length / step_len), 1.0, 1e6);
                  const double ds = length / count;
                  for (std::uint64_t i = 0; i < static_cast<std::uint64_t>(count); ++i) {
                    const double s = (double(i) + u01(rng)) * ds;
                    Rgb fluence;
                    Vec3d mean_dir;
                    grid->sample(add(origin, dir, piece.a + s), fluence, mean_dir);
                    const double phase = m.phase_value(-dot(mean_dir, dir));
                    for (std::size_t c = 0; c < 3; ++c) {
                      sum[c] += through[c] * m.ss[c] * phase * fluence[c] * std::exp(-(tau[c] + m.st[c] * s)) * ds;
                    }
                  }
                }
                for (std::size_t c = 0; c < 3; ++c) tau[c] += m.st[c] * (piece.b - piece.a);
              }
              if (!h) break;
              const Vec3d p = add(origin, dir, len);
              if (!transmits(scene.objects[world.owner[h->triangle]].role)) break;
              dir = cross_interface(world, scene, h->triangle, p, dir, wet(p) ? view_water : 1.0, inside, u01(rng), q.wavelength_nm, &through);
              origin = p;
            }
          }
        }
        const std::size_t pix = std::size_t(row) * std::size_t(q.width) + std::size_t(col);
        for (std::size_t c = 0; c < 3; ++c) img[3 * pix + c] += sum[c] / spp;
      }
    }
  });

  Image out;
  out.width = q.width;
  out.height = q.height;
  out.e0 = e0;
  reduce_batches(batch_images, out);
  out.photons = per_batch * q.batches * scene.lights.size();
  if (stats) {
    *stats = {};
    for (const InscatterStats& s : batch_stats) {
      stats->power_in += s.power_in / q.batches;
      stats->scattered += s.scattered / q.batches;
      stats->absorbed += s.absorbed / q.batches;
      stats->leaving += s.leaving / q.batches;
    }
  }
  return out;
}

}  // namespace caustix::reference
