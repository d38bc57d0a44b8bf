#include "reference.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "caustix/bake/glass_refine.h"
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

namespace {

Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// The scene's triangles in world space, with what a photon needs at a hit.
struct World {
  std::vector<Vec3d> pos;
  std::vector<std::array<std::uint32_t, 3>> tris;
  std::vector<std::uint32_t> owner;
  std::vector<Vec3d> geo_normal;     // per triangle, outward (sign of det(M) applied)
  std::vector<Vec3d> vertex_normal;  // per vertex, world (cofactor matrix), outward
  // Smooth normal at p on triangle t (barycentric blend of the vertex
  // normals): the surface the mesh's normals describe, as a renderer
  // shades it. The flat normal where the blend degenerates.
  Vec3d normal_at(std::uint32_t t, const Vec3d& p) const {
    const auto& v = tris[t];
    const Vec3d e1 = add(pos[v[1]], pos[v[0]], -1), e2 = add(pos[v[2]], pos[v[0]], -1), ep = add(p, pos[v[0]], -1);
    const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2), dp1 = dot(ep, e1), dp2 = dot(ep, e2);
    const double den = d11 * d22 - d12 * d12;
    if (!(den > 0)) return geo_normal[t];
    const double wb = (d22 * dp1 - d12 * dp2) / den, wc = (d11 * dp2 - d12 * dp1) / den, wa = 1 - wb - wc;
    Vec3d n{0, 0, 0};
    n = add(n, vertex_normal[v[0]], wa);
    n = add(n, vertex_normal[v[1]], wb);
    n = add(n, vertex_normal[v[2]], wc);
    const double l = std::sqrt(dot(n, n));
    return l > 1e-12 ? Vec3d{n[0] / l, n[1] / l, n[2] / l} : geo_normal[t];
  }
};

// Bounding rectangle on the plane y = y_top of the points that reach the
// boxes [lo, hi] along the light: parallel projection for a directional
// light, central projection from a point light above the plane.
using Rect = std::array<double, 4>;  // x0, z0, x1, z1
Rect project_boxes(const std::vector<std::pair<Vec3d, Vec3d>>& boxes, const Light& light, double y_top) {
  Rect r{1e300, 1e300, -1e300, -1e300};
  for (const auto& [lo, hi] : boxes) {
    for (int c = 0; c < 8; ++c) {
      const Vec3d p{c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]};
      Vec3d q;
      if (light.type == LightType::kDirectional) {
        const Vec3d d = normalize({light.direction[0], light.direction[1], light.direction[2]});
        q = add(p, d, (y_top - p[1]) / d[1]);  // back up the ray to the plane (d[1] < 0)
      } else {
        const Vec3d l{light.position[0], light.position[1], light.position[2]};
        q = add(l, add(p, l, -1), (l[1] - y_top) / (l[1] - p[1]));
      }
      r = {std::min(r[0], q[0]), std::min(r[1], q[2]), std::max(r[2], q[0]), std::max(r[3], q[2])};
    }
  }
  return r;
}

constexpr int kMaxInteractions = 64;  // glass interfaces followed per photon

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
  bool has_glass = false;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].name == q.receiver) receiver = i;
    if (scene.objects[i].role == Role::kBoth) {
      return make_error(ErrorCode::kInput, q.scene_path + ": object '" + scene.objects[i].name +
                                               "' is both receiver and transparent; the reference traces either, not both");
    }
    has_glass = has_glass || is_transparent(scene.objects[i].role);
  }
  if (!receiver) return make_error(ErrorCode::kUsage, "no object named '" + q.receiver + "' in " + q.scene_path);
  if (!is_receiver(scene.objects[*receiver].role)) {
    return make_error(ErrorCode::kUsage, "object '" + q.receiver + "' in " + q.scene_path + " is not a receiver");
  }

  // All objects in world space: one tree for first hits, one of the receiver
  // alone for the "first surface seen from above" test.
  World world;
  std::vector<Vec3d> rpos;
  std::vector<std::array<std::uint32_t, 3>> rtris;
  std::vector<std::pair<Vec3d, Vec3d>> glass_boxes;
  double y_objects = -1e300;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    auto mesh = bake::import_mesh(doc->mesh_paths[o.mesh_index]);
    if (!mesh) return mesh.error();
    if (is_transparent(o.role)) {
      bake::GlassRefineOptions creases_only;
      creases_only.crease_deg = q.glass_crease_deg;
      creases_only.max_edge = 0;
      mesh->mesh = bake::refine_transparent_mesh(mesh->mesh, creases_only, nullptr);
    }
    const auto base = static_cast<std::uint32_t>(world.pos.size());
    const auto rbase = static_cast<std::uint32_t>(rpos.size());
    const auto& m = o.transform;  // column-major
    const Vec3d c0{m[0], m[1], m[2]}, c1{m[4], m[5], m[6]}, c2{m[8], m[9], m[10]};
    const double det_sign = dot(c0, cross(c1, c2)) < 0 ? -1.0 : 1.0;
    const Vec3d k0 = cross(c1, c2), k1 = cross(c2, c0), k2 = cross(c0, c1);  // cofactor columns
    Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const Vec3d& w : world_points(o.transform, mesh->mesh.positions)) {
      world.pos.push_back(w);
      if (i == *receiver) rpos.push_back(w);
      for (std::size_t k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], w[k]);
        hi[k] = std::max(hi[k], w[k]);
      }
    }
    y_objects = std::max(y_objects, hi[1]);
    if (is_transparent(o.role)) glass_boxes.push_back({lo, hi});
    for (const auto& n : mesh->mesh.normals) {
      world.vertex_normal.push_back(normalize(add(add(Vec3d{k0[0] * n[0] * det_sign, k0[1] * n[0] * det_sign, k0[2] * n[0] * det_sign},
                                                      k1, n[1] * det_sign),
                                                  k2, n[2] * det_sign)));
    }
    for (const auto& tri : mesh->mesh.triangles) {
      world.tris.push_back({base + tri[0], base + tri[1], base + tri[2]});
      world.owner.push_back(i);
      const Vec3d& a = world.pos[base + tri[0]];
      const Vec3d n = cross(add(world.pos[base + tri[1]], a, -1), add(world.pos[base + tri[2]], a, -1));
      world.geo_normal.push_back(normalize({n[0] * det_sign, n[1] * det_sign, n[2] * det_sign}));
      if (i == *receiver) rtris.push_back({rbase + tri[0], rbase + tri[1], rbase + tri[2]});
    }
  }
  const bake::RayCaster caster(world.pos, world.tris, world.owner);
  const bake::RayCaster receiver_only(rpos, rtris, std::vector<std::uint32_t>(rtris.size(), 0));
  double top = -1e30, min_y = 1e30;
  for (const auto& p : rpos) {
    top = std::max(top, p[1]);
    min_y = std::min(min_y, p[1]);
  }
  double scene_size = 1;
  for (const auto& p : world.pos) scene_size = std::max({scene_size, std::fabs(p[0]), std::fabs(p[1]), std::fabs(p[2])});
  const double eps = 1e-7 * scene_size;

  // Emission plane y_top: above the highest wave, or the highest object
  // when there is no water.
  const Water* water = scene.water ? &*scene.water : nullptr;
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
    if (light.type != LightType::kDirectional || has_glass) return win;
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
          flux = light.intensity * -dir[1] / r2 * area / double(per_batch);
        }
        std::array<double, 3> rgb{flux * light.color[0], flux * light.color[1], flux * light.color[2]};
        bool in_water = false;
        inside.clear();
        for (int step = 0; step < kMaxInteractions; ++step) {
          const auto h = caster.first_hit_triangle(add(origin, dir, eps), dir);
          // Above the water, the surface may come first: refract into it
          // with Snell (eq. 2-8) and the exact Fresnel transmittance at the
          // true normal (the reflected part leaves for the sky).
          if (water && !in_water && inside.empty() && dir[1] < 0) {
            const auto s = surface.intersect(origin, dir);
            if (s && (!h || *s < h->distance + eps)) {
              const Vec3d hit = add(origin, dir, *s);
              double gx = 0, gz = 0;
              surface.height(hit[0], hit[2], &gx, &gz);
              const Vec3d nrm = normalize({-gx, 1, -gz});
              const double cos_i = -dot(dir, nrm);
              const auto t = refract(dir, nrm, 1.0 / water->ior);
              if (cos_i <= 0 || !t) break;
              const double tr = fresnel_transmittance(cos_i, 1.0 / water->ior);
              for (double& c : rgb) c *= tr;
              origin = hit;
              dir = normalize(*t);
              in_water = true;
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
          if (!is_transparent(o.role)) {
            if (obj != *receiver) break;
            // Only the receiver's first surface seen from above counts.
            const auto above = receiver_only.first_hit({p[0], top + 1.0, p[2]}, {0, -1, 0});
            if (!above || std::fabs((top + 1.0 - *above) - p[1]) > 1e-5 * (1 + std::fabs(p[1]))) break;
            const double col = (p[0] - q.x0) / dx, row = (p[2] - q.z0) / dz;
            if (col < 0 || row < 0 || col >= q.width || row >= q.height) break;
            const std::size_t i = static_cast<std::size_t>(row) * static_cast<std::size_t>(q.width) + static_cast<std::size_t>(col);
            const double w = std::fabs(world.geo_normal[h->triangle][1]) / (dx * dz) / out.e0;
            for (std::size_t c = 0; c < 3; ++c) img[3 * i + c] += rgb[c] * w;
            ++landed[batch];
            break;
          }
          // A glass interface: entering or leaving object `obj`. Indices on
          // both sides from the glass the photon is in (overlapping shells
          // of one material are one solid: no interface between them).
          const bool entering = dot(dir, world.geo_normal[h->triangle]) < 0;
          const double n_outside = in_water ? double{water->ior} : 1.0;
          const auto ior = [&](std::uint32_t k) { return double{scene.objects[k].material.ior}; };
          const auto pos_in = std::find(inside.begin(), inside.end(), obj);
          const double n1 = inside.empty() ? n_outside : ior(inside.back());
          // The medium beyond: the entered glass; on leaving, the one entered
          // before it, unless `obj` is not the innermost (then nothing changes).
          const double n2 = entering                                            ? ior(obj)
                            : pos_in == inside.end() || pos_in + 1 != inside.end() ? n1
                            : inside.size() > 1                                  ? ior(inside[inside.size() - 2])
                                                                                 : n_outside;
          Vec3d nrm = world.normal_at(h->triangle, p);  // outward
          if (entering == (dot(dir, nrm) >= 0)) nrm = world.geo_normal[h->triangle];
          if (!entering) nrm = {-nrm[0], -nrm[1], -nrm[2]};  // facing the photon
          const double cos_i = -dot(dir, nrm);
          // Fresnel at every interface, by Russian roulette: reflect with
          // probability R, else refract (total internal reflection: R = 1);
          // the photon keeps its flux, so the estimate is unbiased.
          const double tr = n1 == n2 ? 1.0 : fresnel_transmittance(cos_i, n1 / n2);
          origin = p;
          const auto refracted = n1 == n2 ? std::optional<Vec3d>(dir) : refract(dir, nrm, n1 / n2);
          if (refracted && u01(rng) < tr) {
            dir = normalize(*refracted);
            if (entering) inside.push_back(obj);
            else if (pos_in != inside.end()) inside.erase(pos_in);
          } else {
            dir = normalize(add(dir, nrm, 2 * cos_i));
          }
        }
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
