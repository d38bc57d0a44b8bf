#include "reference.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "caustix/formats/spectrum.h"
#include "world.h"

namespace caustix::reference {
namespace {

constexpr int kMaxInteractions = 64;  // glass interfaces followed per photon

}  // namespace

Result<Image> trace(const Request& q) {
  auto doc = bake::load_scene(q.scene_path);
  if (!doc) return doc.error();
  const SceneDesc& scene = doc->scene;
  if (!(q.x1 > q.x0) || !(q.z1 > q.z0) || q.width < 1 || q.height < 1 || q.width > 16384 || q.height > 16384 ||
      q.batches < 1 || q.photons < q.batches) {
    return make_error(ErrorCode::kUsage, "region, size, batches or photon count out of range");
  }
  std::optional<std::uint32_t> receiver;
  bool has_glass = false;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].name == q.receiver) receiver = i;
    if (scene.objects[i].role == Role::kBoth) {
      return make_error(ErrorCode::kInput, q.scene_path + ": object '" + scene.objects[i].name +
                                               "' is both receiver and transparent; the reference traces either, not both");
    }
    has_glass = has_glass || transmits(scene.objects[i].role);
  }
  if (!receiver) return make_error(ErrorCode::kUsage, "no object named '" + q.receiver + "' in " + q.scene_path);
  if (!is_receiver(scene.objects[*receiver].role)) {
    return make_error(ErrorCode::kUsage, "object '" + q.receiver + "' in " + q.scene_path + " is not a receiver");
  }

  // All objects in world space: one tree for first hits, one of the receiver
  // alone for the "first surface seen from above" test.
  auto loaded = load_world(*doc, q.glass_crease_deg);
  if (!loaded) return loaded.error();
  const World& world = *loaded;
  std::vector<std::array<std::uint32_t, 3>> rtris;
  std::vector<std::pair<Vec3d, Vec3d>> glass_boxes;
  double y_objects = -1e300;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    y_objects = std::max(y_objects, world.object_box[i].second[1]);
    if (is_caster(scene.objects[i].role)) glass_boxes.push_back(world.object_box[i]);
  }
  for (std::size_t t = 0; t < world.tris.size(); ++t) {
    if (world.owner[t] == *receiver) rtris.push_back(world.tris[t]);
  }
  // Rays leave a mesh's surface only at glass and mirrors.
  const bool bounces = std::any_of(scene.objects.begin(), scene.objects.end(),
                                   [](const Object& o) { return transmits(o.role) || is_mirror(o.role); });
  const FirstHits caster(world.pos, world.tris, world.owner, bounces);
  const FirstHits receiver_only(world.pos, rtris, std::vector<std::uint32_t>(rtris.size(), 0), false);
  const double top = world.object_box[*receiver].second[1], min_y = world.object_box[*receiver].first[1];
  double scene_size = 1;
  for (const auto& p : world.pos) scene_size = std::max({scene_size, std::fabs(p[0]), std::fabs(p[1]), std::fabs(p[2])});
  const double eps = 1e-7 * scene_size;
  const double y_clear = y_objects + 1e-9 * scene_size;  // see surface_above

  // Emission plane y_top: above the highest wave, or the highest object
  // when there is no water.
  const Water* water = scene.water ? &*scene.water : nullptr;
  const bool disperses = scene_disperses(scene) || q.wavelength_nm > 0;
  const Water flat{};
  const Surface surface{water ? *water : flat, q.time};
  const double y_top = water ? water->level + surface.amplitude_sum() + 1e-3 : y_objects + 1e-3;
  // Emission window, conservative so the estimate stays unbiased (it only
  // saves photons). With water: the water extent, and for directional
  // lights without glass only the part from which light can reach the
  // image region — the region shifted back along the flat-water refracted
  // direction over the receiver's depth range, padded by the largest
  // sideways deviation the steepest wave slope allows. Without water: the
  // projection onto the emission plane, along the light, of the image
  // region's box and of every glass object's box (light reaching the region
  // either comes straight or passed through, or off, some glass first).
  double slope = 0;
  if (water) {
    for (const Wave& wave : water->waves) slope += wave.amplitude * 2 * kPi / wave.wavelength;
  }
  auto window_for = [&](const Light& light) -> Rect {
    if (!water) {
      std::vector<std::pair<Vec3d, Vec3d>> boxes = glass_boxes;
      boxes.push_back({{q.x0, min_y, q.z0}, {q.x1, top, q.z1}});
      return project_boxes(boxes, light, y_top);
    }
    Rect win{water->extent[0], water->extent[1], water->extent[2], water->extent[3]};
    // Dispersion bends each wavelength its own way: the whole water.
    if (light.type != LightType::kDirectional || has_glass || disperses) return win;
    const Vec3d l = normalize({light.direction[0], light.direction[1], light.direction[2]});
    const auto t0 = refract(l, {0, 1, 0}, 1.0 / water->ior);
    if (!t0 || l[1] >= 0) return win;
    const double depth = std::max(0.0, y_top - min_y);
    // The horizontal run per unit depth of every refracted direction the
    // surface's normals allow (tilted up to atan(slope) from vertical, any
    // azimuth), over a fine grid of tilts and azimuths, widened by 2 % and
    // half a degree's worth against what falls between the samples. Light
    // that left the water window is never refracted, so no photon from
    // outside can reach the region.
    const double tilt_max = std::atan(slope);
    // The incident direction's run too: above the surface a photon drops
    // by up to the waves' height along l.
    double run_lo[2] = {l[0] / -l[1], l[2] / -l[1]}, run_hi[2] = {run_lo[0], run_lo[1]};
    constexpr int kTilts = 48, kAzimuths = 96;
    for (int it = 0; it <= kTilts; ++it) {
      const double tilt = tilt_max * it / kTilts;
      for (int ia = 0; ia < (it == 0 ? 1 : kAzimuths); ++ia) {
        const double az = 2 * kPi * ia / kAzimuths;
        const Vec3d nrm{std::sin(tilt) * std::cos(az), std::cos(tilt), std::sin(tilt) * std::sin(az)};
        const auto t = dot(l, nrm) < 0 ? refract(l, nrm, 1.0 / water->ior) : std::nullopt;
        if (!t || (*t)[1] > -0.05) {  // grazing or upward: no bound this way, take the whole water
          run_lo[0] = run_lo[1] = -1e300;
          run_hi[0] = run_hi[1] = 1e300;
          continue;
        }
        for (int k = 0; k < 2; ++k) {
          const double run = (*t)[2 * k] / -(*t)[1];
          run_lo[k] = std::min(run_lo[k], run);
          run_hi[k] = std::max(run_hi[k], run);
        }
      }
    }
    const double widen = 0.02 * (run_hi[0] - run_lo[0] + run_hi[1] - run_lo[1]) + std::tan(0.5 * kPi / 180);
    auto clamp_run = [](double r) { return std::clamp(r, -1e6, 1e6); };
    const double pad_lo[2] = {depth * std::max(0.0, clamp_run(run_hi[0]) + widen), depth * std::max(0.0, clamp_run(run_hi[1]) + widen)};
    const double pad_hi[2] = {depth * std::max(0.0, -clamp_run(run_lo[0]) + widen), depth * std::max(0.0, -clamp_run(run_lo[1]) + widen)};
    return {std::max(win[0], q.x0 - pad_lo[0] - 1e-6), std::max(win[1], q.z0 - pad_lo[1] - 1e-6),
            std::min(win[2], q.x1 + pad_hi[0] + 1e-6), std::min(win[3], q.z1 + pad_hi[1] + 1e-6)};
  };
  for (const Light& light : scene.lights) {
    if (light.type == LightType::kPoint && !(light.position[1] > y_top)) {
      return make_error(ErrorCode::kInput, q.scene_path + ": light '" + light.name +
                                               "' is not above the scene (and its water); the reference emits from above only");
    }
  }
  const double dx = (q.x1 - q.x0) / q.width, dz = (q.z1 - q.z0) / q.height;

  Image out;
  out.width = q.width;
  out.height = q.height;
  out.e0 = scene_e0(scene);
  const std::size_t pixels = static_cast<std::size_t>(q.width) * static_cast<std::size_t>(q.height);
  const std::uint64_t per_batch = q.photons / q.batches;
  std::vector<std::vector<double>> batch_images(q.batches, std::vector<double>(pixels * 3, 0.0));
  std::vector<std::uint64_t> landed(q.batches, 0);

  tbb::parallel_for(std::uint32_t{0}, q.batches, [&](std::uint32_t batch) {
    std::mt19937_64 rng(q.seed * 0x9E3779B97F4A7C15ull + batch + 1);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<double>& img = batch_images[batch];
    std::vector<std::uint32_t> inside;  // glass objects the photon is in (shells may overlap)
    for (std::uint32_t li = 0; li < scene.lights.size(); ++li) {
      const Light& light = scene.lights[li];
      const Rect win = window_for(light);
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
          // Toward a uniform point of the window on the emission plane.
          const Vec3d lp{light.position[0], light.position[1], light.position[2]};
          const Vec3d target{px, y_top, pz};
          const Vec3d to = add(target, lp, -1);
          const double r2 = dot(to, to);
          dir = normalize(to);
          origin = target;
          flux = light.intensity * -dir[1] / r2 * area / double(per_batch) *
                 spot_factor(light, {static_cast<float>(dir[0]), static_cast<float>(dir[1]), static_cast<float>(dir[2])});
        }
        std::array<double, 3> rgb{flux * light.color[0], flux * light.color[1], flux * light.color[2]};
        const double nm = photon_wavelength(q.wavelength_nm, disperses, [&] { return u01(rng); }, rgb);
        const double n_water = water ? water_index_at(*water, nm) : 1.0;
        bool in_water = false;
        bool on_mesh = false;  // the photon leaves a mesh's surface (FirstHits)
        inside.clear();
        for (int step = 0; step < kMaxInteractions; ++step) {
          // Above the water, the surface may come first: refract into it.
          const bool above_water = water && !in_water && inside.empty() && dir[1] < 0;
          const auto s = above_water ? surface.intersect(origin, dir) : std::nullopt;
          std::optional<bake::RayCaster::Hit> h;
          if (!s || !surface_above(origin, dir, *s, y_clear)) {
            const Vec3d from = add(origin, dir, eps);
            h = on_mesh ? caster.from_surface(from, dir) : caster.from_space(from, dir);
          }
          if (above_water) {
            if (s && (!h || *s < h->distance + eps)) {
              origin = add(origin, dir, *s);
              const auto entry = surface.enter(origin, dir, n_water);
              if (!entry) break;
              for (double& c : rgb) c *= entry->transmittance;
              dir = entry->dir;
              in_water = true;
              on_mesh = false;
              continue;
            }
          }
          if (!h) break;
          const double len = h->distance + eps;
          const Vec3d p = add(origin, dir, len);
          // Absorption along the segment: the glass the photon is in, else
          // the water it is in.
          for (std::size_t c = 0; c < 3; ++c) {
            const double k = !inside.empty() ? double{scene.objects[inside.back()].material.absorption[c]}
                             : in_water      ? double{water->absorption[c]}
                                             : 0.0;
            rgb[c] *= std::exp(-k * len);
          }
          const std::uint32_t obj = world.owner[h->triangle];
          const Object& o = scene.objects[obj];
          if (is_mirror(o.role)) {
            // A two-sided specular reflector: the smooth normal
            // turned to face the photon, the reflectance per channel.
            Vec3d nrm = world.normal_at(h->triangle, p);
            if (dot(nrm, dir) > 0) nrm = {-nrm[0], -nrm[1], -nrm[2]};
            for (std::size_t c = 0; c < 3; ++c) rgb[c] *= o.material.reflectance[c];
            origin = p;
            on_mesh = true;
            dir = normalize(add(dir, nrm, -2 * dot(dir, nrm)));
            continue;
          }
          if (!transmits(o.role)) {
            if (obj != *receiver) break;
            // Only the receiver's first surface seen from above counts.
            const double col = (p[0] - q.x0) / dx, row = (p[2] - q.z0) / dz;
            if (col < 0 || row < 0 || col >= q.width || row >= q.height) break;
            const auto above = receiver_only.from_space({p[0], top + 1.0, p[2]}, {0, -1, 0});
            if (!above || std::fabs((top + 1.0 - above->distance) - p[1]) > 1e-5 * (1 + std::fabs(p[1]))) break;
            const std::size_t i = static_cast<std::size_t>(row) * static_cast<std::size_t>(q.width) + static_cast<std::size_t>(col);
            const double w = std::fabs(world.geo_normal[h->triangle][1]) / (dx * dz) / out.e0;
            for (std::size_t c = 0; c < 3; ++c) img[3 * i + c] += rgb[c] * w;
            ++landed[batch];
            break;
          }
          // A glass interface.
          origin = p;
          on_mesh = true;
          dir = cross_interface(world, scene, h->triangle, p, dir, in_water ? n_water : 1.0, inside, u01(rng), nm, &rgb);
        }
      }
    }
  });

  reduce_batches(batch_images, out);
  out.photons = per_batch * q.batches * scene.lights.size();
  for (std::uint64_t l : landed) out.photons_landed += l;
  return out;
}

}  // namespace caustix::reference
