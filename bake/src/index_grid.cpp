// Pfeuti, "Voxelization": inside/outside coverage per voxel, Gaussian
// filtering, conversion to n; "Octree Construction": regions whose index
// varies by at most epsilon, so photons can take larger steps there.
// The slides voxelise on the GPU by sweeping the near plane; the baker does
// it exactly on the CPU (crossings of rows with the triangles), once.

#include "caustix/bake/index_grid.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace caustix::bake {
namespace {

struct Layout {
  std::array<std::uint32_t, 3> size{1, 1, 1};
  Vec3f origin{0, 0, 0};
  double voxel = 1;
};

Layout layout_of(const TriangleMesh& mesh, const IndexGridOptions& o) {
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& p : mesh.positions) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double{p[k]});
      hi[k] = std::max(hi[k], double{p[k]});
    }
  }
  Layout l;
  const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-12});
  l.voxel = longest / std::max<std::uint32_t>(o.resolution, 1);
  // Room for the filter's tail and one empty voxel, on every side.
  const auto pad = static_cast<std::uint32_t>(std::ceil(3.0 * o.blur)) + 1;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto inner = static_cast<std::uint32_t>(std::max(1.0, std::ceil((hi[k] - lo[k]) / l.voxel - 1e-9)));
    l.size[k] = inner + 2 * pad;
    const double centre = 0.5 * (lo[k] + hi[k]);
    l.origin[k] = static_cast<float>(centre - 0.5 * l.size[k] * l.voxel);
  }
  return l;
}

// Separable Gaussian along `axis`, zero beyond the grid.
void blur_axis(std::vector<float>& c, const std::array<std::uint32_t, 3>& size, int axis, float sigma) {
  const int radius = static_cast<int>(std::ceil(3.0f * sigma));
  std::vector<double> w(static_cast<std::size_t>(2 * radius + 1));
  double sum = 0;
  for (int i = -radius; i <= radius; ++i) sum += w[static_cast<std::size_t>(i + radius)] = std::exp(-0.5 * i * i / (sigma * sigma));
  for (double& x : w) x /= sum;
  const std::size_t stride = axis == 0 ? 1 : axis == 1 ? size[0] : std::size_t{size[0]} * size[1];
  const int n = static_cast<int>(size[static_cast<std::size_t>(axis)]);
  const std::size_t lines = c.size() / static_cast<std::size_t>(n);
  std::vector<float> out(c.size());
  tbb::parallel_for(std::size_t{0}, lines, [&](std::size_t line) {
    // The line's first voxel: `line` enumerates the other two axes.
    std::size_t base;
    if (axis == 0) base = line * size[0];
    else if (axis == 1) base = (line / size[0]) * size[0] * size[1] + line % size[0];
    else base = line;
    for (int i = 0; i < n; ++i) {
      double acc = 0;
      for (int t = std::max(-radius, -i); t <= std::min(radius, n - 1 - i); ++t) {
        acc += w[static_cast<std::size_t>(t + radius)] * c[base + static_cast<std::size_t>(i + t) * stride];
      }
      out[base + static_cast<std::size_t>(i) * stride] = static_cast<float>(acc);
    }
  });
  c.swap(out);
}

}  // namespace

std::uint64_t index_grid_voxels(const TriangleMesh& mesh, const IndexGridOptions& options) {
  const Layout l = layout_of(mesh, options);
  return std::uint64_t{l.size[0]} * l.size[1] * l.size[2];
}

IndexGrid voxelize_index(std::uint32_t object, const TriangleMesh& mesh, float ior_inside, float ior_outside,
                         const IndexGridOptions& o, const std::function<bool(double)>& progress) {
  // Progress by step, in shares of the time measured at --volume-res 500
  // (508^3 voxels of glass_ball's sphere, 2 cores, 6.8 s): the rows 22 %,
  // the three blur passes 50 %, quantisation and the octree the rest.
  constexpr double kRowsShare = 0.22, kBlurredShare = 0.72;
  std::atomic<bool> stop{false};
  const auto said = [&](double f) {
    if (progress && !stop.load(std::memory_order_relaxed) && !progress(f)) stop = true;
    return !stop.load(std::memory_order_relaxed);
  };

  const Layout l = layout_of(mesh, o);
  IndexGrid g;
  g.object = object;
  g.size = l.size;
  g.origin = l.origin;
  g.voxel = static_cast<float>(l.voxel);
  g.ior_inside = ior_inside;
  g.ior_outside = ior_outside;
  g.blur = o.blur;
  g.epsilon = o.epsilon;
  const std::uint32_t nx = l.size[0], ny = l.size[1], nz = l.size[2];
  const double h = l.voxel;
  const std::uint32_t ss = std::max<std::uint32_t>(o.supersample, 1);

  // Triangles binned by the voxel rows (j, k) their y-z bounds touch.
  std::vector<std::vector<std::uint32_t>> bins(std::size_t{ny} * nz);
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    double ylo = 1e300, yhi = -1e300, zlo = 1e300, zhi = -1e300;
    for (std::uint32_t v : mesh.triangles[t]) {
      ylo = std::min(ylo, double{mesh.positions[v][1]});
      yhi = std::max(yhi, double{mesh.positions[v][1]});
      zlo = std::min(zlo, double{mesh.positions[v][2]});
      zhi = std::max(zhi, double{mesh.positions[v][2]});
    }
    auto cell = [&](double x, std::size_t k, std::uint32_t n) {
      return static_cast<std::uint32_t>(std::clamp((x - l.origin[k]) / h, 0.0, double(n - 1)));
    };
    for (std::uint32_t k = cell(zlo, 2, nz); k <= cell(zhi, 2, nz); ++k) {
      for (std::uint32_t j = cell(ylo, 1, ny); j <= cell(yhi, 1, ny); ++j) bins[std::size_t{k} * ny + j].push_back(t);
    }
  }

  // Exact inside length along x per voxel, over ss x ss rows per voxel
  // row. The rows sit off the voxel lattice by an irrational fraction so
  // that none runs exactly through a vertex or edge of a regular mesh.
  std::vector<float> cov(g.voxels(), 0.0f);
  std::atomic<std::size_t> rows_done{0};
  const std::size_t every = std::max<std::size_t>(1, bins.size() / 100);
  tbb::parallel_for(std::size_t{0}, bins.size(), [&](std::size_t row) {
    if (const std::size_t d = ++rows_done; d % every == 0) said(kRowsShare * double(d) / double(bins.size()));
    const auto& tris = bins[row];
    if (tris.empty() || stop.load(std::memory_order_relaxed)) return;
    const std::uint32_t j = static_cast<std::uint32_t>(row % ny), k = static_cast<std::uint32_t>(row / ny);
    std::vector<double> xs;
    std::vector<double> inside_len(nx, 0.0);
    for (std::uint32_t a = 0; a < ss; ++a) {
      for (std::uint32_t b = 0; b < ss; ++b) {
        const double y = l.origin[1] + (j + (a + 0.5 + 0.0137) / ss) * h;
        const double z = l.origin[2] + (k + (b + 0.5 + 0.0291) / ss) * h;
        xs.clear();
        for (std::uint32_t t : tris) {
          const auto& tri = mesh.triangles[t];
          const auto& p0 = mesh.positions[tri[0]];
          const auto& p1 = mesh.positions[tri[1]];
          const auto& p2 = mesh.positions[tri[2]];
          // Barycentric coordinates of (y, z) in the triangle's y-z shadow.
          const double e0 = (double{p1[1]} - y) * (double{p2[2]} - z) - (double{p2[1]} - y) * (double{p1[2]} - z);
          const double e1 = (double{p2[1]} - y) * (double{p0[2]} - z) - (double{p0[1]} - y) * (double{p2[2]} - z);
          const double e2 = (double{p0[1]} - y) * (double{p1[2]} - z) - (double{p1[1]} - y) * (double{p0[2]} - z);
          const bool pos = e0 >= 0 && e1 >= 0 && e2 >= 0, neg = e0 <= 0 && e1 <= 0 && e2 <= 0;
          const double area = e0 + e1 + e2;
          if (!(pos || neg) || area == 0) continue;
          xs.push_back((e0 * p0[0] + e1 * p1[0] + e2 * p2[0]) / area);
        }
        std::sort(xs.begin(), xs.end());
        // Parity: [xs[0], xs[1]], [xs[2], xs[3]], ... are inside; an odd
        // count (a row grazing the surface) drops the last crossing.
        for (std::size_t c = 0; c + 1 < xs.size(); c += 2) {
          const double u0 = (xs[c] - l.origin[0]) / h, u1 = (xs[c + 1] - l.origin[0]) / h;
          const auto i0 = static_cast<std::uint32_t>(std::clamp(std::floor(u0), 0.0, double(nx - 1)));
          const auto i1 = static_cast<std::uint32_t>(std::clamp(std::floor(u1), 0.0, double(nx - 1)));
          for (std::uint32_t i = i0; i <= i1; ++i) inside_len[i] += std::clamp(u1, double(i), double(i + 1)) - std::clamp(u0, double(i), double(i + 1));
        }
      }
    }
    for (std::uint32_t i = 0; i < nx; ++i) cov[g.index(i, j, k)] = static_cast<float>(inside_len[i] / (ss * ss));
  });

  if (!said(kRowsShare)) return g;
  if (o.blur > 0) {
    for (int axis = 0; axis < 3; ++axis) {
      blur_axis(cov, g.size, axis, o.blur);
      if (!said(kRowsShare + (kBlurredShare - kRowsShare) * (axis + 1) / 3)) return g;
    }
  }
  g.coverage.resize(cov.size());
  for (std::size_t v = 0; v < cov.size(); ++v) {
    g.coverage[v] = static_cast<std::uint16_t>(std::lround(std::clamp(cov[v], 0.0f, 1.0f) * 65535.0f));
  }

  // Octree, bottom-up over a min/max pyramid of the stored coverage: a node
  // of level k (an aligned cube of 2^k voxels, cells past the grid counting
  // as outside) is uniform when its 8 children are and its index range is
  // within epsilon. Each voxel keeps the level of its largest uniform
  // ancestor.
  const double dn = std::fabs(double{ior_inside} - double{ior_outside}) / 65535.0;
  g.level.assign(g.voxels(), 0);
  std::array<std::uint32_t, 3> dim = g.size;
  std::vector<std::uint16_t> lo(g.coverage), hi(g.coverage);
  std::vector<std::uint8_t> uniform(g.voxels(), 1);
  int halvings = 1;  // levels until one node covers the grid, for the progress
  while ((1u << halvings) < std::max({g.size[0], g.size[1], g.size[2]})) ++halvings;
  for (std::uint8_t level = 1; level <= kMaxOctreeLevel; ++level) {
    if (dim[0] == 1 && dim[1] == 1 && dim[2] == 1) break;  // the root covers the grid
    const std::array<std::uint32_t, 3> up{(dim[0] + 1) / 2, (dim[1] + 1) / 2, (dim[2] + 1) / 2};
    std::vector<std::uint16_t> lo2(std::size_t{up[0]} * up[1] * up[2]), hi2(lo2.size());
    std::vector<std::uint8_t> uni2(lo2.size());
    bool any = false;
    for (std::uint32_t k = 0; k < up[2]; ++k) {
      for (std::uint32_t j = 0; j < up[1]; ++j) {
        for (std::uint32_t i = 0; i < up[0]; ++i) {
          std::uint16_t mn = 65535, mx = 0;
          bool u = true;
          for (std::uint32_t c = 0; c < 8; ++c) {
            const std::uint32_t ci = 2 * i + (c & 1), cj = 2 * j + ((c >> 1) & 1), ck = 2 * k + ((c >> 2) & 1);
            if (ci >= dim[0] || cj >= dim[1] || ck >= dim[2]) {
              mn = 0;  // outside the grid: outside the object
              continue;
            }
            const std::size_t child = (std::size_t{ck} * dim[1] + cj) * dim[0] + ci;
            mn = std::min(mn, lo[child]);
            mx = std::max(mx, hi[child]);
            u = u && uniform[child];
          }
          const std::size_t node = (std::size_t{k} * up[1] + j) * up[0] + i;
          lo2[node] = mn;
          hi2[node] = std::max(mx, mn);
          uni2[node] = u && (hi2[node] - lo2[node]) * dn <= o.epsilon;
          any = any || uni2[node];
        }
      }
    }
    if (!any || !said(kBlurredShare + (1.0 - kBlurredShare) * level / halvings)) break;
    for (std::uint32_t k = 0; k < g.size[2]; ++k) {
      for (std::uint32_t j = 0; j < g.size[1]; ++j) {
        for (std::uint32_t i = 0; i < g.size[0]; ++i) {
          const std::size_t node = (std::size_t{k >> level} * up[1] + (j >> level)) * up[0] + (i >> level);
          if (uni2[node]) g.level[g.index(i, j, k)] = level;
        }
      }
    }
    dim = up;
    lo.swap(lo2);
    hi.swap(hi2);
    uniform.swap(uni2);
  }
  return g;
}

}  // namespace caustix::bake
