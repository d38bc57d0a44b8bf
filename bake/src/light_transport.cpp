#include "caustix/bake/light_transport.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>

#include "caustix/bake/ray_cast.h"
#include "caustix/formats/frame.h"

namespace caustix::bake {
namespace {

Vec3d add(const Vec3d& a, const Vec3d& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3d mul(const Vec3d& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3d unit(const Vec3d& v) { return mul(v, 1.0 / std::sqrt(std::max(dot(v, v), 1e-300))); }
Vec3d to_d(const Vec3f& v) { return {v[0], v[1], v[2]}; }

struct Surface {
  const TriangleMesh& mesh;
  std::vector<Vec3d> pos;
  std::vector<Vec3d> geo_normal;  // per triangle, outward (counter-clockwise front)

  // Smooth (Phong-interpolated) outward normal at point p of triangle t,
  // which the refraction uses so that a tessellated sphere refracts like a
  // sphere; the geometric normal where interpolation degenerates.
  Vec3d normal_at(std::uint32_t t, const Vec3d& p) const {
    const auto& tri = mesh.triangles[t];
    const Vec3d a = pos[tri[0]], b = pos[tri[1]], c = pos[tri[2]];
    const Vec3d n = cross(sub(b, a), sub(c, a));
    const double area2 = dot(n, n);
    if (area2 <= 0) return geo_normal[t];
    const double wa = dot(cross(sub(b, p), sub(c, p)), n) / area2;
    const double wb = dot(cross(sub(c, p), sub(a, p)), n) / area2;
    const double wc = 1.0 - wa - wb;
    Vec3d s{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const Vec3f& nk = mesh.normals[tri[static_cast<std::size_t>(k)]];
      const double w = k == 0 ? wa : k == 1 ? wb : wc;
      s = add(s, mul(to_d(nk), w));
    }
    const Vec3d u = unit(s);
    return dot(u, geo_normal[t]) > 0.05 ? u : geo_normal[t];
  }
};

}  // namespace

std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary_edges(const TriangleMesh& mesh) {
  // Closedness is geometric: vertices at exactly the same position count as
  // one (meshes split seams for normals, and OpenMesh splits non-manifold
  // "pinch" vertices on import).
  std::map<Vec3f, std::uint32_t> first;
  std::vector<std::uint32_t> canon(mesh.positions.size());
  for (std::uint32_t i = 0; i < mesh.positions.size(); ++i) canon[i] = first.try_emplace(mesh.positions[i], i).first->second;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : mesh.triangles) {
    for (std::size_t k = 0; k < 3; ++k) ++directed[{canon[t[k]], canon[t[(k + 1) % 3]]}];
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (const auto& [e, n] : directed) {
    if (!directed.contains({e.second, e.first})) out.push_back(e);
  }
  return out;
}

LightTransportTable trace_transport_table(std::uint32_t object, const Material& material, const TriangleMesh& mesh,
                                          const TransportOptions& opt, TransportReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  Surface s{mesh, {}, {}};
  s.pos.reserve(mesh.positions.size());
  for (const auto& p : mesh.positions) s.pos.push_back(to_d(p));
  for (const auto& t : mesh.triangles) s.geo_normal.push_back(unit(cross(sub(s.pos[t[1]], s.pos[t[0]]), sub(s.pos[t[2]], s.pos[t[0]]))));
  const RayCaster caster(s.pos, mesh.triangles, std::vector<std::uint32_t>(mesh.triangles.size(), 0));

  LightTransportTable table;
  table.object = object;
  table.resolution = opt.resolution;
  table.max_bounces = opt.max_bounces;
  table.ior = material.ior;
  table.absorption = material.absorption;
  table.vertex_count = static_cast<std::uint32_t>(mesh.positions.size());
  table.exit_min = table.exit_max = mesh.positions[0];
  for (const auto& p : mesh.positions) {
    for (std::size_t k = 0; k < 3; ++k) {
      table.exit_min[k] = std::min(table.exit_min[k], p[k]);
      table.exit_max[k] = std::max(table.exit_max[k], p[k]);
    }
  }
  const Vec3d ext = sub(to_d(table.exit_max), to_d(table.exit_min));
  const double diagonal = std::sqrt(dot(ext, ext));
  // Each straight segment inside is at most the box diagonal long.
  table.max_path = static_cast<float>(diagonal * (opt.max_bounces + 1));
  const std::size_t per_vertex = std::size_t{opt.resolution} * opt.resolution;
  table.words.assign(mesh.positions.size() * per_vertex * 4, 0);

  // Offsets that keep a ray from hitting the surface it starts on.
  const double eps = 1e-6 * std::max(diagonal, 1e-6);
  const double eta_in = 1.0 / material.ior, eta_out = material.ior;
  std::atomic<std::uint64_t> rays{0}, leaving{0}, trapped{0}, occluded{0}, reflected{0};

  tbb::parallel_for(std::size_t{0}, mesh.positions.size(), [&](std::size_t v) {
    const Vec3d p = s.pos[v];
    const Vec3d n = unit(to_d(mesh.normals[v]));
    std::uint64_t local_rays = 0, n_leave = 0, n_trap = 0, n_occ = 0, n_refl = 0;
    for (std::uint32_t row = 0; row < opt.resolution; ++row) {
      for (std::uint32_t col = 0; col < opt.resolution; ++col) {
        TransportEntry e;
        const Vec3d omega = grid_direction(n, opt.resolution, row, col);  // towards the light
        // Does the object itself block this direction before the vertex?
        ++local_rays;
        if (caster.first_hit(add(p, mul(omega, eps)), omega)) {
          e.status = TransportStatus::kOccluded;
          table.store(table.entry_index(static_cast<std::uint32_t>(v), row, col), e);
          ++n_occ;
          continue;
        }
        const double cos_i = std::max(dot(omega, n), 0.0);
        // Entry: refraction at the vertex normal (seed 000 eq. 2-8), Fresnel.
        Vec3d d = *refract(mul(omega, -1.0), n, eta_in);  // air -> glass never reflects totally
        double transmittance = fresnel_transmittance(cos_i, eta_in);
        double path = 0;
        Vec3d o = p;
        e.status = TransportStatus::kTrapped;
        for (std::uint32_t bounce = 0; bounce <= opt.max_bounces; ++bounce) {
          ++local_rays;
          const auto hit = caster.first_hit_triangle(add(o, mul(d, eps)), d);
          if (!hit) break;  // numerically leaked through a seam: counted as trapped
          const double len = hit->distance + eps;
          const Vec3d q = add(o, mul(d, len));
          path += len;
          Vec3d nn = s.normal_at(hit->triangle, q);
          if (dot(nn, d) <= 0) nn = s.geo_normal[hit->triangle];
          if (dot(nn, d) <= 0) break;  // hit from outside: not a closed surface here
          const Vec3d inward = mul(nn, -1.0);
          if (auto out = refract(d, inward, eta_out)) {
            transmittance *= fresnel_transmittance(dot(d, nn), eta_out);
            e.status = TransportStatus::kLeaves;
            e.exit = q;
            e.direction = *out;
            e.bounces = static_cast<std::uint8_t>(bounce);
            break;
          }
          // Total internal reflection (reflectance 1): follow it inside.
          d = unit(sub(d, mul(nn, 2.0 * dot(d, nn))));
          o = q;
        }
        if (e.status == TransportStatus::kLeaves) {
          e.transmittance = transmittance;
          e.path = path;
          ++n_leave;
          n_refl += e.bounces > 0 ? 1 : 0;
        } else {
          ++n_trap;
        }
        table.store(table.entry_index(static_cast<std::uint32_t>(v), row, col), e);
      }
    }
    rays += local_rays;
    leaving += n_leave;
    trapped += n_trap;
    occluded += n_occ;
    reflected += n_refl;
  });

  if (report) {
    report->object = object;
    report->vertices = table.vertex_count;
    report->entries = table.vertex_count * per_vertex;
    report->leaving = leaving;
    report->trapped = trapped;
    report->occluded = occluded;
    report->reflected = reflected;
    report->rays = rays;
    report->raw_bytes = report->entries * 16;
    report->position_error_m = table.position_error_bound();
    report->direction_error_rad = LightTransportTable::direction_error_bound();
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return table;
}

}  // namespace caustix::bake
