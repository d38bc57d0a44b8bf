#include "world.h"

#include <algorithm>

#include "caustix/bake/bake.h"
#include "caustix/bake/glass_refine.h"
#include "caustix/bake/mesh_import.h"
#include "caustix/formats/spectrum.h"

namespace caustix::reference {

Vec3d World::normal_at(std::uint32_t t, const Vec3d& p) const {
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

Result<World> load_world(bake::SceneDocument& doc, double glass_crease_deg) {
  World world;
  const SceneDesc& scene = doc.scene;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    const auto& imported = doc.imported[o.mesh_index];
    auto mesh = imported ? Result<bake::ImportedMesh>(*imported) : bake::import_mesh(doc.mesh_paths[o.mesh_index]);
    if (!mesh) return mesh.error();
    // As caustix-bake: glass that bounds no solid is thin-walled, a solid
    // wound inside out is turned.
    if (auto thin = bake::prepare_glass_mesh(doc.scene, o.mesh_index, mesh->mesh, doc.mesh_paths[o.mesh_index]); !thin) {
      return thin.error();
    }
    if (is_transparent(o.role)) {
      bake::GlassRefineOptions creases_only;
      creases_only.crease_deg = glass_crease_deg;
      creases_only.max_edge = 0;
      mesh->mesh = bake::refine_transparent_mesh(mesh->mesh, creases_only, nullptr);
    }
    const auto base = static_cast<std::uint32_t>(world.pos.size());
    const auto& m = o.transform;  // column-major
    const Vec3d c0{m[0], m[1], m[2]}, c1{m[4], m[5], m[6]}, c2{m[8], m[9], m[10]};
    const double det_sign = dot(c0, cross(c1, c2)) < 0 ? -1.0 : 1.0;
    Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const Vec3d& w : world_points(o.transform, mesh->mesh.positions)) {
      world.pos.push_back(w);
      for (std::size_t k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], w[k]);
        hi[k] = std::max(hi[k], w[k]);
      }
    }
    world.object_box.push_back({lo, hi});
    for (const Vec3d& wn : world_normals(o.transform, mesh->mesh.normals)) world.vertex_normal.push_back(wn);
    for (const auto& tri : mesh->mesh.triangles) {
      world.tris.push_back({base + tri[0], base + tri[1], base + tri[2]});
      world.owner.push_back(i);
      const Vec3d& a = world.pos[base + tri[0]];
      const Vec3d n = cross(add(world.pos[base + tri[1]], a, -1), add(world.pos[base + tri[2]], a, -1));
      world.geo_normal.push_back(normalize({n[0] * det_sign, n[1] * det_sign, n[2] * det_sign}));
    }
  }
  return world;
}

namespace {

// A thin-walled sheet (Role::kThin), traced as what it is: two
// parallel faces at one point, Fresnel at each (the same reflectance r at
// both: the inner face sees the refracted angle, and reflectance is
// reciprocal), the light bouncing between them until it leaves forward
// (transmitted, without bending, tinted once) or back (reflected). One
// uniform serves every choice: after a choice of probability q it is
// rescaled into [0, 1) within the branch taken.
Vec3d cross_thin_sheet(const World& world, const SceneDesc& scene, std::uint32_t triangle, const Vec3d& p, const Vec3d& dir,
                       const std::vector<std::uint32_t>& inside, double n_outside, double u, std::array<double, 3>* power) {
  const Material& m = scene.objects[world.owner[triangle]].material;
  const double n1 = inside.empty() ? n_outside : double{scene.objects[inside.back()].material.ior};
  Vec3d nrm = world.normal_at(triangle, p);
  if (dot(dir, nrm) > 0) nrm = {-nrm[0], -nrm[1], -nrm[2]};  // facing the photon
  const double cos_i = std::min(1.0, -dot(dir, nrm));
  const double r = 1.0 - fresnel_transmittance(cos_i, n1 / m.ior);
  const Vec3d reflected = normalize(add(dir, nrm, 2 * cos_i));
  if (u < r) return reflected;  // off the near face
  u = (u - r) / (1 - r);
  for (int bounce = 0; bounce < 256; ++bounce) {
    if (u < 1 - r) {  // out through the far face
      if (power) {
        for (std::size_t c = 0; c < 3; ++c) (*power)[c] *= m.tint[c];
      }
      return dir;
    }
    u = (u - (1 - r)) / r;     // back from the far face
    if (u < 1 - r) return reflected;  // out through the near face
    u = (u - (1 - r)) / r;     // back from the near face
  }
  return reflected;
}

}  // namespace

Vec3d cross_interface(const World& world, const SceneDesc& scene, std::uint32_t triangle, const Vec3d& p,
                      const Vec3d& dir, double n_outside, std::vector<std::uint32_t>& inside, double u01, double nm,
                      std::array<double, 3>* power) {
  const std::uint32_t obj = world.owner[triangle];
  if (is_thin(scene.objects[obj].role)) return cross_thin_sheet(world, scene, triangle, p, dir, inside, n_outside, u01, power);
  // Entering or leaving object `obj`. Indices on both sides from the glass
  // the photon is in.
  const bool entering = dot(dir, world.geo_normal[triangle]) < 0;
  const auto ior = [&](std::uint32_t k) {
    const Material& m = scene.objects[k].material;
    return double{nm > 0 ? index_at(m.ior, m.dispersion, static_cast<float>(nm)) : m.ior};
  };
  const auto pos_in = std::find(inside.begin(), inside.end(), obj);
  const double n1 = inside.empty() ? n_outside : ior(inside.back());
  // The medium beyond: the entered glass; on leaving, the one entered
  // before it, unless `obj` is not the innermost (then nothing changes).
  const double n2 = entering                                               ? ior(obj)
                    : pos_in == inside.end() || pos_in + 1 != inside.end() ? n1
                    : inside.size() > 1                                    ? ior(inside[inside.size() - 2])
                                                                           : n_outside;
  Vec3d nrm = world.normal_at(triangle, p);  // outward
  if (entering == (dot(dir, nrm) >= 0)) nrm = world.geo_normal[triangle];
  if (!entering) nrm = {-nrm[0], -nrm[1], -nrm[2]};  // facing the photon
  const double cos_i = -dot(dir, nrm);
  // Fresnel by Russian roulette: reflect with probability R, else refract
  // (total internal reflection: R = 1).
  const double tr = n1 == n2 ? 1.0 : fresnel_transmittance(cos_i, n1 / n2);
  const auto refracted = n1 == n2 ? std::optional<Vec3d>(dir) : refract(dir, nrm, n1 / n2);
  if (refracted && u01 < tr) {
    if (power) {
      for (std::size_t c = 0; c < 3; ++c) (*power)[c] *= scene.objects[obj].material.tint[c];
    }
    if (entering) inside.push_back(obj);
    else if (pos_in != inside.end()) inside.erase(pos_in);
    return normalize(*refracted);
  }
  return normalize(add(dir, nrm, 2 * cos_i));
}

Rect project_boxes(const std::vector<Box>& boxes, const Light& light, double y_top) {
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

void reduce_batches(const std::vector<std::vector<double>>& batch_images, Image& out) {
  const std::size_t batches = batch_images.size();
  const std::size_t pixels = static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height);
  out.rgb.assign(pixels * 3, 0.0f);
  out.sigma.assign(pixels, 0.0f);
  double noise_sum = 0, value_sum = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    double mean[3] = {0, 0, 0}, lum_sum = 0, lum_sq = 0;
    for (const auto& img : batch_images) {
      for (std::size_t c = 0; c < 3; ++c) mean[c] += img[3 * i + c] / double(batches);
      const double lum = 0.2126 * img[3 * i] + 0.7152 * img[3 * i + 1] + 0.0722 * img[3 * i + 2];
      lum_sum += lum;
      lum_sq += lum * lum;
    }
    for (std::size_t c = 0; c < 3; ++c) out.rgb[3 * i + c] = static_cast<float>(mean[c]);
    const double m = lum_sum / double(batches);
    const double var = batches > 1 ? std::max(0.0, (lum_sq - double(batches) * m * m) / double(batches - 1)) : 0.0;
    out.sigma[i] = static_cast<float>(std::sqrt(var / double(batches)));
    noise_sum += out.sigma[i];
    value_sum += m;
  }
  out.relative_noise = value_sum > 0 ? noise_sum / value_sum : 0;
}

FirstHits::FirstHits(const std::vector<Vec3d>& pos, const std::vector<std::array<std::uint32_t, 3>>& tris,
                     const std::vector<std::uint32_t>& owner, bool from_surfaces)
    : pos_(pos), tris_(tris), fast_(pos, tris) {
  if (from_surfaces || !fast_.ok()) exact_.emplace(pos, tris, owner);
}

std::optional<bake::RayCaster::Hit> FirstHits::from_space(const Vec3d& o, const Vec3d& d) const {
  if (!fast_.ok()) return exact_->first_hit_triangle(o, d);
  auto h = fast_.first_hit_triangle(o, d);
  if (!h) return h;
  // The distance to the hit triangle's plane in doubles (Embree's is in
  // floats); Embree's where the ray runs along the plane.
  const auto& t = tris_[h->triangle];
  const Vec3d n = cross(add(pos_[t[1]], pos_[t[0]], -1), add(pos_[t[2]], pos_[t[0]], -1));
  const double dn = dot(d, n);
  if (dn != 0) {
    const double s = dot(add(pos_[t[0]], o, -1), n) / dn;
    if (std::isfinite(s) && s >= 0) h->distance = s;
  }
  return h;
}

}  // namespace caustix::reference
