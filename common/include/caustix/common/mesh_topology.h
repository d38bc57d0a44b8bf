#pragma once
// Is a triangle mesh the closed, consistently wound surface of a solid?
// The baker needs that of transparent objects (light transport runs inside
// them) and says exactly what is wrong otherwise; the runtime culls back
// faces only of meshes that are. Closedness is geometric: vertices at
// exactly the same position count as one (meshes split seams for normals,
// OpenMesh splits non-manifold vertices on import, Draco may reorder them).
//
// Kernel: none needed. Closedness and winding are decided combinatorially
// on exactly equal positions (a sort, no tolerance), so no geometric
// predicate is involved; only the volume's sign is arithmetic (see below).
//
// Every undirected edge is used f times in one direction and g times in the
// other. The surface is closed and consistently wound when f == g for every
// edge (each directed edge has an opposite: two cubes sharing an edge pass,
// as they bound a solid). Otherwise the edge is
//   f + g == 1: open (a hole's boundary),
//   f + g == 2: inconsistently wound (its two triangles disagree),
//   f + g >  2: non-manifold (more than two triangles, unbalanced).
// Sorting, not maps: O(n log n) and flat memory for millions of triangles.

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include "caustix/common/mesh.h"

namespace caustix {

struct EdgeCensus {
  using Edge = std::pair<std::uint32_t, std::uint32_t>;  // vertex indices of the mesh, as wound by one triangle
  std::vector<Edge> open, inconsistent, non_manifold;
  // Enclosed volume by the divergence theorem (sum of p0 . (p1 x p2) / 6):
  // positive for an outward-wound closed surface, negative inside out.
  // Summed relative to the first vertex (the sum is the same about any
  // point for a closed surface): about the origin, a 1 cm cube 10 km out
  // sums terms of 10^12 m^3, each rounded by 10^-4, to a volume of 10^-6.
  double signed_volume = 0;
  bool closed() const { return open.empty() && inconsistent.empty() && non_manifold.empty(); }
};

// Weld: one id per distinct position, the smallest vertex index holding it.
inline std::vector<std::uint32_t> weld_positions(const TriangleMesh& m) {
  std::vector<std::uint32_t> order(m.positions.size()), id(m.positions.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return m.positions[a] < m.positions[b]; });
  for (std::size_t i = 0; i < order.size(); ++i) {
    id[order[i]] = i > 0 && m.positions[order[i]] == m.positions[order[i - 1]] ? id[order[i - 1]] : order[i];
  }
  return id;
}

inline EdgeCensus census_edges(const TriangleMesh& m) {
  EdgeCensus out;
  const std::vector<std::uint32_t> id = weld_positions(m);
  struct Use {
    std::uint32_t lo, hi;  // welded ids, lo < hi
    bool forward;          // wound lo -> hi
    bool operator<(const Use& o) const { return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : forward < o.forward; }
  };
  std::vector<Use> uses;
  uses.reserve(m.triangles.size() * 3);
  // Float differences are exact in double (for coordinates within 2^29 of
  // each other's magnitude), so only the products round.
  const std::array<float, 3> ref = m.positions.empty() ? std::array<float, 3>{0, 0, 0} : m.positions.front();
  const auto rel = [&](std::uint32_t v) {
    const auto& p = m.positions[v];
    return std::array<double, 3>{double{p[0]} - ref[0], double{p[1]} - ref[1], double{p[2]} - ref[2]};
  };
  for (const auto& t : m.triangles) {
    const auto p0 = rel(t[0]), p1 = rel(t[1]), p2 = rel(t[2]);
    out.signed_volume += (p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) + p0[1] * (p1[2] * p2[0] - p1[0] * p2[2]) +
                          p0[2] * (p1[0] * p2[1] - p1[1] * p2[0])) / 6.0;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t a = id[t[k]], b = id[t[(k + 1) % 3]];
      if (a != b) uses.push_back({std::min(a, b), std::max(a, b), a < b});
    }
  }
  std::sort(uses.begin(), uses.end());
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i, forward = 0;
    for (; j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi; ++j) forward += uses[j].forward;
    const std::size_t total = j - i, backward = total - forward;
    if (forward != backward) {
      const EdgeCensus::Edge e = uses[i].forward ? EdgeCensus::Edge{uses[i].lo, uses[i].hi} : EdgeCensus::Edge{uses[i].hi, uses[i].lo};
      (total == 1 ? out.open : total == 2 ? out.inconsistent : out.non_manifold).push_back(e);
    }
    i = j;
  }
  return out;
}

}  // namespace caustix
