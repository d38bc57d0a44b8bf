#include "caustix/bake/light_transport.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "caustix/bake/ray_cast.h"
#include "caustix/formats/frame.h"
#include "caustix/formats/spectrum.h"

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
  std::vector<Vec3d> origin;      // per vertex: where its rays start (sample_origins)
  std::vector<char> flat;         // per vertex: every triangle of it lies in its tangent plane (flat_vertices)

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

// Where a vertex's rays start. A vertex on a crease (the corner of a prism)
// belongs to one face's copy (glass_refine.h); started exactly at the
// corner, its refracted ray starts on the other faces too and hits one at
// distance zero, or steps past it and leaks, so the table held no light for
// it. Where every triangle of the vertex lies in its tangent plane (within
// 1e-3 rad; Draco's 14-bit normals are good to about 1e-4), the start moves
// 1 % of the way towards the mean centroid of its triangles, which keeps it
// on its own face; the exit point changes by 1 % of a third of an edge.
// Vertices of curved surfaces stay: in the tangent plane they would float
// above their own facets. flat_vertices() says which are flat.
std::vector<char> flat_vertices(const TriangleMesh& mesh, const std::vector<Vec3d>& geo) {
  std::vector<char> flat(mesh.positions.size(), 1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::uint32_t v : mesh.triangles[t]) {
      if (dot(geo[t], unit(to_d(mesh.normals[v]))) < 1.0 - 5e-7) flat[v] = 0;
    }
  }
  return flat;
}

std::vector<Vec3d> sample_origins(const TriangleMesh& mesh, const std::vector<Vec3d>& pos, const std::vector<char>& flat) {
  std::vector<Vec3d> centre(pos.size(), Vec3d{0, 0, 0});
  std::vector<double> count(pos.size(), 0);
  for (const auto& tri : mesh.triangles) {
    const Vec3d c = mul(add(add(pos[tri[0]], pos[tri[1]]), pos[tri[2]]), 1.0 / 3.0);
    for (std::uint32_t v : tri) {
      centre[v] = add(centre[v], c);
      count[v] += 1;
    }
  }
  std::vector<Vec3d> origin(pos);
  for (std::size_t v = 0; v < pos.size(); ++v) {
    if (count[v] > 0 && flat[v]) origin[v] = add(pos[v], mul(sub(mul(centre[v], 1.0 / count[v]), pos[v]), 0.01));
  }
  return origin;
}

// Whether the surface bounds a convex solid: no vertex in front of any
// triangle's plane by more than the decoded mesh's quantisation can put it
// there. With corners moved by up to delta = 1e-4 of the diagonal (Draco
// keeps 11 bits or more), a plane's offset moves by delta and its normal
// turns by up to 2 delta / h, h the triangle's smallest altitude, so a point
// at distance r may read delta (1 + 2 r / h) in front of a flat or convex
// surface (the refined ball's 3 mm triangles read 0.36 mm). Light that
// leaves a convex object cannot meet it again, so its exit rays need no
// further cast (a third of the casts of a ball's table). O(triangles x
// vertices), parallel, stopping at the first point in front; at the table's
// size limit it stays well below the cost of tracing.
bool is_convex(const TriangleMesh& mesh, const std::vector<Vec3d>& pos, const std::vector<Vec3d>& geo, double diagonal) {
  const double delta = 1e-4 * diagonal;
  std::atomic<bool> convex{true};
  tbb::parallel_for(std::size_t{0}, mesh.triangles.size(), [&](std::size_t t) {
    if (!convex.load(std::memory_order_relaxed)) return;
    const auto& tri = mesh.triangles[t];
    const Vec3d& a = pos[tri[0]];
    const Vec3d e[3] = {sub(pos[tri[1]], a), sub(pos[tri[2]], pos[tri[1]]), sub(a, pos[tri[2]])};
    const Vec3d c = cross(e[0], e[2]);
    const double longest = std::sqrt(std::max({dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2])}));
    const double h = longest > 0 ? std::sqrt(dot(c, c)) / longest : 0;
    if (h <= 0) return;  // degenerate: no plane to be in front of
    const Vec3d& n = geo[t];
    for (const Vec3d& p : pos) {
      const Vec3d r = sub(p, a);
      if (dot(r, n) > delta * (1 + 2 * std::sqrt(dot(r, r)) / h)) {
        convex = false;
        return;
      }
    }
  });
  return convex;
}

}  // namespace

struct TransportTracer::Impl {
  Surface surface;
  std::unique_ptr<EmbreeCaster> embree;  // when asked for and started
  std::unique_ptr<RayCaster> cgal;       // the exact check, and the caster without Embree
  double eps, eta_in, eta_out;
  std::uint32_t max_bounces;
  bool convex = false;
  Impl(const Material& m, const TriangleMesh& mesh, std::uint32_t bounces, std::vector<Vec3d> pos, std::vector<Vec3d> geo, RayEngine rays)
      : surface{mesh, pos, geo, {}, flat_vertices(mesh, geo)}, eps(0), eta_in(1.0 / m.ior), eta_out(m.ior), max_bounces(bounces) {
    surface.origin = sample_origins(mesh, surface.pos, surface.flat);
    if (rays == RayEngine::kEmbree) embree = std::make_unique<EmbreeCaster>(surface.pos, mesh.triangles);
    if (embree && !embree->ok()) embree.reset();
    cgal = std::make_unique<RayCaster>(surface.pos, mesh.triangles, std::vector<std::uint32_t>(mesh.triangles.size(), 0));
  }
  // The first triangle along the ray. Embree's robust mode is watertight
  // across edges but can miss a ray through a vertex (10 of 22 120 in
  // GeometryKernel.EmbreeRaysThroughSharedEdgesAndVerticesHit; a sun
  // straight down through a UV sphere's poles is such a ray): a ray from
  // `inside` the closed object must hit it, so a miss there is asked of the
  // exact tree again.
  std::optional<RayCaster::Hit> first_hit(const Vec3d& o, const Vec3d& d, bool inside) const {
    if (!embree) return cgal->first_hit_triangle(o, d);
    auto hit = embree->first_hit_triangle(o, d);
    return hit || !inside ? hit : cgal->first_hit_triangle(o, d);
  }
  // Whether the object blocks the light before a vertex: Embree's "no" is
  // final. Its "yes" within 1000 eps (10^-3 of the box diagonal) of the
  // start, which a float origin a few ulps off the vertex gives for
  // directions grazing the faces around it (an 8 k-vertex ball: 1508
  // against CGAL's 32 of 1.16 M), is asked of the exact CGAL tree again;
  // a blocker farther away is real (a self-hit there would need a ray
  // within 3 10^-5 rad of a face's plane).
  bool blocked(const Vec3d& o, const Vec3d& d) const {
    if (!embree) return cgal->first_hit(o, d).has_value();
    const auto hit = embree->first_hit_triangle(o, d);
    return hit && (hit->distance > 1000 * eps || cgal->first_hit(o, d).has_value());
  }
};

TransportTracer::TransportTracer(const Material& material, const TriangleMesh& mesh, std::uint32_t max_bounces, RayEngine rays) {
  std::vector<Vec3d> pos, geo;
  pos.reserve(mesh.positions.size());
  for (const auto& p : mesh.positions) pos.push_back(to_d(p));
  for (const auto& t : mesh.triangles) geo.push_back(unit(cross(sub(pos[t[1]], pos[t[0]]), sub(pos[t[2]], pos[t[0]]))));
  Vec3d lo = pos[0], hi = pos[0];
  for (const auto& p : pos) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  const Vec3d ext = sub(hi, lo);
  impl_ = std::make_unique<Impl>(material, mesh, max_bounces, std::move(pos), std::move(geo), rays);
  // Offset that keeps a ray from hitting the surface it starts on.
  impl_->eps = 1e-6 * std::max(std::sqrt(dot(ext, ext)), 1e-6);
  impl_->convex = is_convex(mesh, impl_->surface.pos, impl_->surface.geo_normal, std::sqrt(dot(ext, ext)));
}

TransportTracer::~TransportTracer() = default;

bool TransportTracer::flat(std::uint32_t v) const { return impl_->surface.flat[v] != 0; }

TransportEntry TransportTracer::trace(std::uint32_t v, const Dir3& omega, std::uint64_t* rays) const {
  const Impl& m = *impl_;
  const Surface& s = m.surface;
  const double eps = m.eps;
  TransportEntry e;
  const Vec3d p = s.origin[v];
  const Vec3d n = unit(to_d(s.mesh.normals[v]));
  std::uint64_t casts = 1;
  // Does the object itself block this direction before the vertex?
  if (m.blocked(add(p, mul(omega, eps)), omega)) {
    e.status = TransportStatus::kOccluded;
    if (rays) *rays += casts;
    return e;
  }
  const double cos_i = std::max(dot(omega, n), 0.0);
  // Entry: refraction at the vertex normal (Tipprasert 2006 eq. 2-8), Fresnel.
  Vec3d d = *refract(mul(omega, -1.0), n, m.eta_in);  // air -> glass never reflects totally
  double transmittance = fresnel_transmittance(cos_i, m.eta_in);
  double path = 0;
  Vec3d o = p;
  // The light is followed until it leaves the object for good, the way
  // caustix-reference follows a photon: `depth` counts the shells of this
  // object the light is inside (a teapot's lid, spout and handle overlap
  // its body: one glass, so crossing into a second shell is no interface),
  // and light that leaves and meets the object again enters it again.
  // `events` counts what bends the path inside (total internal reflections
  // and re-entries; at most max_bounces), which keeps every entry's path
  // below table.max_path: each straight piece inside is at most the box
  // diagonal. The entry's `bounces` is that count, the path's class for the
  // look-up's interpolation.
  std::uint32_t depth = 1, events = 0;
  e.status = TransportStatus::kTrapped;
  // Shell crossings count no event; the step cap (8 casts per event, the
  // entry and the exit included) only stops a ray that a broken mesh keeps
  // between shells, which then counts as trapped.
  for (std::uint32_t step = 0; step < 8 * (m.max_bounces + 2); ++step) {
    const bool gone = depth == 0 && m.convex;  // left a convex object: it cannot meet it again
    casts += gone ? 0 : 1;
    const auto hit = gone ? std::nullopt : m.first_hit(add(o, mul(d, eps)), d, depth > 0);
    if (!hit) {
      if (depth > 0) break;  // numerically leaked through a seam: counted as trapped
      e.status = TransportStatus::kLeaves;
      e.exit = o;
      e.direction = d;
      e.transmittance = transmittance;
      e.path = path;
      e.bounces = static_cast<std::uint8_t>(events);
      break;
    }
    const double len = hit->distance + eps;
    const Vec3d q = add(o, mul(d, len));
    if (depth > 0) path += len;
    o = q;
    const bool entering = dot(d, s.geo_normal[hit->triangle]) < 0;
    if (entering && depth > 0) {  // into an overlapping shell: same glass on both sides
      ++depth;
      continue;
    }
    if (!entering && depth != 1) {  // out of an overlapping shell, or of one it is not in
      depth = depth > 0 ? depth - 1 : 0;
      continue;
    }
    // A real interface: air -> glass (re-entry) or glass -> air. The smooth
    // normal where it agrees with the side the light comes from.
    Vec3d nn = s.normal_at(hit->triangle, q);
    if ((dot(nn, d) < 0) != entering) nn = s.geo_normal[hit->triangle];
    if (entering) {
      if (++events > m.max_bounces) break;
      transmittance *= fresnel_transmittance(-dot(d, nn), m.eta_in);
      d = *refract(d, nn, m.eta_in);
      depth = 1;
      continue;
    }
    if (auto out = refract(d, mul(nn, -1.0), m.eta_out)) {
      transmittance *= fresnel_transmittance(dot(d, nn), m.eta_out);
      d = *out;
      depth = 0;
      continue;
    }
    // Total internal reflection (reflectance 1): follow it inside.
    if (++events > m.max_bounces) break;
    d = unit(sub(d, mul(nn, 2.0 * dot(d, nn))));
  }
  if (rays) *rays += casts;
  return e;
}

std::vector<float> transport_wavelengths(std::uint32_t count) {
  std::vector<float> nm;
  for (std::uint32_t k = 0; k < count && count >= 2; ++k) {
    nm.push_back(kMinWavelength + (kMaxWavelength - kMinWavelength) * static_cast<float>(k) / static_cast<float>(count - 1));
  }
  return nm;
}

LightTransportTable trace_transport_table(std::uint32_t object, const Material& material, const TriangleMesh& mesh,
                                          const TransportOptions& opt, TransportReport* report, float wavelength_nm,
                                          const std::function<bool(double)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  Material at = material;
  if (wavelength_nm > 0) at.ior = index_at(material.ior, material.dispersion, wavelength_nm);
  const TransportTracer tracer(at, mesh, opt.max_bounces, opt.rays);

  LightTransportTable table;
  table.object = object;
  table.wavelength_nm = wavelength_nm;
  table.resolution = opt.resolution;
  table.max_bounces = opt.max_bounces;
  table.precision_bits = opt.bits;
  table.ior = at.ior;
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
  // Each straight segment inside is at most the box diagonal long.
  table.max_path = static_cast<float>(std::sqrt(dot(ext, ext)) * (opt.max_bounces + 1));
  const std::size_t per_vertex = std::size_t{opt.resolution} * opt.resolution;
  table.words.assign(mesh.positions.size() * per_vertex * 4, 0);

  table.switches.assign(mesh.positions.size() * per_vertex * 2, 0);
  std::atomic<std::uint64_t> rays{0}, leaving{0}, trapped{0}, occluded{0}, reflected{0}, switch_edges{0}, done{0};
  std::atomic<bool> stop{false};
  // Progress about every 1 % of the vertices (and the last).
  const std::uint64_t every = std::max<std::uint64_t>(1, mesh.positions.size() / 100);
  tbb::parallel_for(std::size_t{0}, mesh.positions.size(), [&](std::size_t v) {
    if (stop.load(std::memory_order_relaxed)) return;
    const Vec3d n = unit(to_d(mesh.normals[v]));
    std::uint64_t local_rays = 0, n_leave = 0, n_trap = 0, n_occ = 0, n_refl = 0;
    for (std::uint32_t row = 0; row < opt.resolution; ++row) {
      for (std::uint32_t col = 0; col < opt.resolution; ++col) {
        const TransportEntry e = tracer.trace(static_cast<std::uint32_t>(v), grid_direction(n, opt.resolution, row, col), &local_rays);
        n_leave += e.status == TransportStatus::kLeaves ? 1 : 0;
        n_trap += e.status == TransportStatus::kTrapped ? 1 : 0;
        n_occ += e.status == TransportStatus::kOccluded ? 1 : 0;
        n_refl += e.status == TransportStatus::kLeaves && e.bounces > 0 ? 1 : 0;
        table.store(table.entry_index(static_cast<std::uint32_t>(v), row, col), e);
      }
    }
    // Where two neighbouring grid directions leave unalike (the path class
    // switches between them), the switch found by bisection along the grid
    // edge, so that the runtime can cut a triangle whose corners lie on
    // both sides at the switch (docs/glass-tables.md, "The prism's left band
    // edge"). The class of the stored entry decides each half.
    // Only on flat faces, where a switch draws a straight, sharp band edge
    // (a prism's, a cube's; docs/glass-tables.md): on curved glass the bisection
    // would cost a scan-like blob's table 3 times its rays.
    std::uint64_t n_switch = 0;
    const bool bisect = opt.switches && tracer.flat(static_cast<std::uint32_t>(v));
    for (std::uint32_t row = 0; row < (bisect ? opt.resolution : 0); ++row) {
      for (std::uint32_t col = 0; col < opt.resolution; ++col) {
        const std::size_t i = table.entry_index(static_cast<std::uint32_t>(v), row, col);
        const TransportEntry a = table.load(i);
        for (std::uint32_t axis = 0; axis < 2; ++axis) {
          const std::uint32_t r2 = row + axis, c2 = col + 1 - axis;
          if (r2 >= opt.resolution || c2 >= opt.resolution) continue;
          const TransportEntry b = table.load(table.entry_index(static_cast<std::uint32_t>(v), r2, c2));
          if (a.status != TransportStatus::kLeaves || b.status != TransportStatus::kLeaves || leave_alike(a, b)) continue;
          double lo = 0, hi = 1;
          for (std::uint32_t step = 0; step < kSwitchSteps; ++step) {
            const double f = 0.5 * (lo + hi);
            const Dir3 w = grid_direction_at(n, opt.resolution, row + f * axis, col + f * (1 - axis));
            (leave_alike(tracer.trace(static_cast<std::uint32_t>(v), w, &local_rays), a) ? lo : hi) = f;
          }
          table.switches[2 * i + axis] = static_cast<std::uint8_t>(std::clamp(std::lround(128 * (lo + hi)), 1L, 255L));
          ++n_switch;
        }
      }
    }
    switch_edges += n_switch;
    rays += local_rays;
    leaving += n_leave;
    trapped += n_trap;
    occluded += n_occ;
    reflected += n_refl;
    const std::uint64_t d = ++done;
    if (progress && (d % every == 0 || d == mesh.positions.size()) && !progress(double(d) / double(mesh.positions.size()))) {
      stop = true;
    }
  });

  if (report) {
    report->object = object;
    report->wavelength_nm = wavelength_nm;
    report->vertices = table.vertex_count;
    report->entries = table.vertex_count * per_vertex;
    report->leaving = leaving;
    report->trapped = trapped;
    report->occluded = occluded;
    report->reflected = reflected;
    report->switch_edges = switch_edges;
    report->rays = rays;
    report->raw_bytes = report->entries * 16;
    report->position_error_m = table.position_error_bound();
    report->direction_error_rad = table.direction_error_bound();
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  if (switch_edges == 0) table.switches.clear();
  return table;
}

}  // namespace caustix::bake
