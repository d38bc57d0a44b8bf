#include "reference.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "caustix/bake/mesh_import.h"
#include "caustix/bake/ray_cast.h"
#include "caustix/bake/scene_json.h"
#include "caustix/formats/frame.h"

namespace caustix::reference {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3d add(const Vec3d& a, const Vec3d& b, double s = 1) { return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]}; }
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d normalize(const Vec3d& v) {
  const double n = std::sqrt(dot(v, v));
  return {v[0] / n, v[1] / n, v[2] / n};
}

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
  // First crossing of the ray o + s d (going down) with the surface:
  // bracketed by steps short against the shortest wavelength, then bisected.
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
      if ((fa > 0) != (fb > 0)) {
        for (int it = 0; it < 60; ++it) {
          const double m = 0.5 * (a + b), fm = f(m);
          ((fa > 0) == (fm > 0) ? a : b) = m;
          if ((fa > 0) == (fm > 0)) fa = fm;
        }
        return 0.5 * (a + b);
      }
      if (b >= s_max) return std::nullopt;
      a = b;
      fa = fb;
    }
  }
};

}  // namespace

Result<Image> trace(const Request& q) {
  auto doc = bake::load_scene_json(q.scene_path);
  if (!doc) return doc.error();
  const SceneDesc& scene = doc->scene;
  if (!(q.x1 > q.x0) || !(q.z1 > q.z0) || q.width < 1 || q.height < 1 || q.width > 16384 || q.height > 16384 ||
      q.batches < 1 || q.photons < q.batches) {
    return make_error(ErrorCode::kUsage, "region, size, batches or photon count out of range");
  }
  std::optional<std::uint32_t> receiver;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].name == q.receiver) receiver = i;
    if (is_transparent(scene.objects[i].role)) {
      return make_error(ErrorCode::kInput, q.scene_path + ": object '" + scene.objects[i].name +
                                               "' is transparent; the reference does not trace glass yet (issue 5)");
    }
  }
  if (!receiver) return make_error(ErrorCode::kUsage, "no object named '" + q.receiver + "' in " + q.scene_path);
  if (!scene.water) return make_error(ErrorCode::kInput, q.scene_path + ": the reference traces water scenes (no water here)");

  // All objects in world space: one tree for first hits, one of the receiver
  // alone for the "first surface seen from above" test.
  std::vector<Vec3d> pos, rpos;
  std::vector<std::array<std::uint32_t, 3>> tris, rtris;
  std::vector<std::uint32_t> owner;
  std::vector<Vec3d> tri_normal;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    auto mesh = bake::import_mesh(doc->mesh_paths[o.mesh_index]);
    if (!mesh) return mesh.error();
    const auto base = static_cast<std::uint32_t>(pos.size());
    const auto rbase = static_cast<std::uint32_t>(rpos.size());
    for (const Vec3d& w : world_points(o.transform, mesh->mesh.positions)) {
      pos.push_back(w);
      if (i == *receiver) rpos.push_back(w);
    }
    for (const auto& tri : mesh->mesh.triangles) {
      tris.push_back({base + tri[0], base + tri[1], base + tri[2]});
      owner.push_back(i);
      const Vec3d& a = pos[base + tri[0]];
      const Vec3d& b = pos[base + tri[1]];
      const Vec3d& c = pos[base + tri[2]];
      const Vec3d e1 = add(b, a, -1), e2 = add(c, a, -1);
      tri_normal.push_back(normalize({e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]}));
      if (i == *receiver) rtris.push_back({rbase + tri[0], rbase + tri[1], rbase + tri[2]});
    }
  }
  const bake::RayCaster world(pos, tris, owner);
  const bake::RayCaster receiver_only(rpos, rtris, std::vector<std::uint32_t>(rtris.size(), 0));
  double top = -1e30;
  for (const auto& p : rpos) top = std::max(top, p[1]);

  const Water& water = *scene.water;
  const Surface surface{water, q.time};
  const double y_top = water.level + surface.amplitude_sum() + 1e-3;
  // Emission window: the water extent, and for directional lights only the
  // part from which light can reach the image region — the region shifted
  // back along the flat-water refracted direction over the receiver's depth
  // range, padded by the largest sideways deviation the steepest wave slope
  // allows. Conservative, so the estimate stays unbiased; it only saves
  // photons.
  double min_y = 1e30;
  for (const auto& p : rpos) min_y = std::min(min_y, p[1]);
  double slope = 0;
  for (const Wave& wave : water.waves) slope += wave.amplitude * 2 * kPi / wave.wavelength;
  auto window_for = [&](const Light& light) {
    std::array<double, 4> win{water.extent[0], water.extent[1], water.extent[2], water.extent[3]};
    if (light.type != LightType::kDirectional) return win;
    const Vec3d l = normalize({light.direction[0], light.direction[1], light.direction[2]});
    const auto t0 = refract(l, {0, 1, 0}, 1.0 / water.ior);
    if (!t0 || l[1] >= 0) return win;
    const double depth = std::max(0.0, y_top - min_y);
    const double sx = (*t0)[0] / -(*t0)[1] * depth, sz = (*t0)[2] / -(*t0)[1] * depth;
    const double theta0 = std::acos(std::min(1.0, -(*t0)[1]));
    const double pad = depth * (std::tan(std::min(theta0 + std::atan(slope), 1.45)) + std::tan(theta0)) + 1e-6;
    win = {std::max(win[0], q.x0 - std::max(0.0, sx) - pad), std::max(win[1], q.z0 - std::max(0.0, sz) - pad),
           std::min(win[2], q.x1 - std::min(0.0, sx) + pad), std::min(win[3], q.z1 - std::min(0.0, sz) + pad)};
    return win;
  };
  const double dx = (q.x1 - q.x0) / q.width, dz = (q.z1 - q.z0) / q.height;

  Image out;
  out.width = q.width;
  out.height = q.height;
  for (const Light& l : scene.lights) {
    if (l.type == LightType::kDirectional) {
      out.e0 = l.irradiance;
      break;
    }
  }
  if (!(out.e0 > 0)) out.e0 = 1;
  const std::size_t pixels = static_cast<std::size_t>(q.width) * static_cast<std::size_t>(q.height);
  const std::uint64_t per_batch = q.photons / q.batches;
  std::vector<std::vector<double>> batch_images(q.batches, std::vector<double>(pixels * 3, 0.0));
  std::vector<std::uint64_t> landed(q.batches, 0);

  tbb::parallel_for(std::uint32_t{0}, q.batches, [&](std::uint32_t batch) {
    std::mt19937_64 rng(q.seed * 0x9E3779B97F4A7C15ull + batch + 1);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<double>& img = batch_images[batch];
    for (std::uint32_t li = 0; li < scene.lights.size(); ++li) {
      const Light& light = scene.lights[li];
      const auto win = window_for(light);
      if (!(win[2] > win[0]) || !(win[3] > win[1])) continue;
      const double area = (win[2] - win[0]) * (win[3] - win[1]);
      for (std::uint64_t n = 0; n < per_batch; ++n) {
        const double px = win[0] + (win[2] - win[0]) * u01(rng), pz = win[1] + (win[3] - win[1]) * u01(rng);
        Vec3d origin, dir;
        double flux;
        if (light.type == LightType::kDirectional) {
          dir = normalize({light.direction[0], light.direction[1], light.direction[2]});
          if (dir[1] >= 0) continue;
          origin = {px, y_top, pz};
          flux = light.irradiance * -dir[1] * area / double(per_batch);
        } else {
          const Vec3d lp{light.position[0], light.position[1], light.position[2]};
          if (lp[1] <= y_top) continue;  // the reference emits point lights from above the water only
          // Toward a uniform point of the extent at the top plane.
          const Vec3d target{px, y_top, pz};
          const Vec3d to = add(target, lp, -1);
          const double r2 = dot(to, to);
          dir = normalize(to);
          origin = target;
          flux = light.intensity * -dir[1] / r2 * area / double(per_batch);
        }
        const auto s = surface.intersect(origin, dir);
        if (!s) continue;
        const Vec3d hit = add(origin, dir, *s);
        double gx = 0, gz = 0;
        surface.height(hit[0], hit[2], &gx, &gz);
        const Vec3d nrm = normalize({-gx, 1, -gz});
        const double cos_i = -dot(dir, nrm);
        if (cos_i <= 0) continue;
        // Snell (eq. 2-8) and Fresnel at the true surface normal.
        const double eta = 1.0 / water.ior;
        const double k = 1 - eta * eta * (1 - cos_i * cos_i);
        const Vec3d t = normalize(add(Vec3d{eta * dir[0], eta * dir[1], eta * dir[2]}, nrm, eta * cos_i - std::sqrt(k)));
        flux *= fresnel_transmittance(cos_i, 1.0 / water.ior);
        const auto h = world.first_hit_triangle(add(hit, t, 1e-7), t);
        if (!h || owner[h->triangle] != *receiver) continue;
        const Vec3d p = add(hit, t, 1e-7 + h->distance);
        // Only the receiver's first surface seen from above counts.
        const auto above = receiver_only.first_hit({p[0], top + 1.0, p[2]}, {0, -1, 0});
        if (!above || std::fabs((top + 1.0 - *above) - p[1]) > 1e-5 * (1 + std::fabs(p[1]))) continue;
        const double path = h->distance + 1e-7;
        const double col = (p[0] - q.x0) / dx, row = (p[2] - q.z0) / dz;
        if (col < 0 || row < 0 || col >= q.width || row >= q.height) continue;
        const std::size_t i = static_cast<std::size_t>(row) * static_cast<std::size_t>(q.width) + static_cast<std::size_t>(col);
        const double weight = flux * std::fabs(tri_normal[h->triangle][1]) / (dx * dz) / out.e0;
        for (std::size_t c = 0; c < 3; ++c) {
          img[3 * i + c] += weight * light.color[c] * std::exp(-double{water.absorption[c]} * path);
        }
        ++landed[batch];
      }
    }
  });

  // Mean over batches (in batch order: deterministic) and its standard error.
  out.rgb.assign(pixels * 3, 0.0f);
  out.sigma.assign(pixels, 0.0f);
  double noise_sum = 0, value_sum = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    double mean[3] = {0, 0, 0}, lum_sum = 0, lum_sq = 0;
    for (std::uint32_t b = 0; b < q.batches; ++b) {
      const auto& img = batch_images[b];
      for (std::size_t c = 0; c < 3; ++c) mean[c] += img[3 * i + c] / q.batches;
      const double lum = 0.2126 * img[3 * i] + 0.7152 * img[3 * i + 1] + 0.0722 * img[3 * i + 2];
      lum_sum += lum;
      lum_sq += lum * lum;
    }
    for (std::size_t c = 0; c < 3; ++c) out.rgb[3 * i + c] = static_cast<float>(mean[c]);
    const double m = lum_sum / q.batches;
    const double var = q.batches > 1 ? std::max(0.0, (lum_sq - q.batches * m * m) / (q.batches - 1)) : 0.0;
    out.sigma[i] = static_cast<float>(std::sqrt(var / q.batches));
    noise_sum += out.sigma[i];
    value_sum += m;
  }
  out.relative_noise = value_sum > 0 ? noise_sum / value_sum : 0;
  out.photons = per_batch * q.batches * scene.lights.size();
  for (std::uint64_t l : landed) out.photons_landed += l;
  return out;
}

}  // namespace caustix::reference
