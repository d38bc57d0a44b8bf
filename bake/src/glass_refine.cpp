#include "caustix/bake/glass_refine.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "caustix/common/mesh_topology.h"

namespace caustix::bake {
namespace {

using V3 = std::array<double, 3>;
constexpr double kDegree = 3.14159265358979323846 / 180.0;

V3 d3(const std::array<float, 3>& p) { return {p[0], p[1], p[2]}; }
V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 cross(const V3& a, const V3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double length(const V3& a) { return std::sqrt(dot(a, a)); }
V3 unit(const V3& a) {
  const double l = length(a);
  return l > 0 ? V3{a[0] / l, a[1] / l, a[2] / l} : V3{0, 0, 0};
}
// Angle between two unit vectors, degrees.
double angle_deg(const V3& a, const V3& b) { return std::acos(std::clamp(dot(a, b), -1.0, 1.0)) / kDegree; }

V3 face_normal(const TriangleMesh& m, std::size_t t) {
  const auto& tri = m.triangles[t];
  const V3 a = d3(m.positions[tri[0]]);
  return unit(cross(sub(d3(m.positions[tri[1]]), a), sub(d3(m.positions[tri[2]]), a)));
}

double edge_length(const TriangleMesh& m, std::uint32_t a, std::uint32_t b) {
  return length(sub(d3(m.positions[a]), d3(m.positions[b])));
}

// Each triangle's edge k (corner k -> k + 1) under welded ids, sorted so
// that the uses of one edge (by position) are adjacent.
struct EdgeUse {
  std::uint32_t lo, hi, tri, k;
  bool operator<(const EdgeUse& o) const {
    return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : tri != o.tri ? tri < o.tri : k < o.k;
  }
};
std::vector<EdgeUse> edge_uses(const TriangleMesh& m, const std::vector<std::uint32_t>& weld) {
  std::vector<EdgeUse> uses;
  uses.reserve(m.triangles.size() * 3);
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t a = weld[m.triangles[t][k]], b = weld[m.triangles[t][(k + 1) % 3]];
      uses.push_back({std::min(a, b), std::max(a, b), t, k});
    }
  }
  std::sort(uses.begin(), uses.end());
  return uses;
}

// Calls f(begin, end) for each run of uses of one edge.
template <class F>
void for_each_edge(const std::vector<EdgeUse>& uses, F&& f) {
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    f(i, j);
    i = j;
  }
}

struct DisjointSets {
  std::vector<std::uint32_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {  // the smaller root wins: independent of the order of calls
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// Step 1 (header): one vertex per fan of triangles joined across smooth
// edges; split fans get their angle-weighted normals.
void split_creases(TriangleMesh& m, double crease_deg, GlassRefineReport& rep) {
  const std::vector<std::uint32_t> weld = weld_positions(m);
  const std::size_t n_tri = m.triangles.size();
  std::vector<V3> fn(n_tri);
  for (std::size_t t = 0; t < n_tri; ++t) fn[t] = face_normal(m, t);
  const std::vector<EdgeUse> uses = edge_uses(m, weld);

  // Corners 3t + k; those of one vertex index across a smooth edge join.
  DisjointSets fans(n_tri * 3);
  const auto corner_at = [&](std::uint32_t t, std::uint32_t welded) {
    for (std::uint32_t k = 0; k < 3; ++k) {
      if (weld[m.triangles[t][k]] == welded) return k;
    }
    return 3u;
  };
  for_each_edge(uses, [&](std::size_t i, std::size_t j) {
    const bool smooth = j - i == 2 && angle_deg(fn[uses[i].tri], fn[uses[i + 1].tri]) <= crease_deg;
    if (!smooth) {
      ++rep.crease_edges;
      return;
    }
    const std::uint32_t t1 = uses[i].tri, t2 = uses[i + 1].tri;
    for (std::uint32_t w : {uses[i].lo, uses[i].hi}) {
      const std::uint32_t k1 = corner_at(t1, w), k2 = corner_at(t2, w);
      if (k1 < 3 && k2 < 3 && m.triangles[t1][k1] == m.triangles[t2][k2]) fans.unite(3 * t1 + k1, 3 * t2 + k2);
    }
  });

  // The first fan of a vertex keeps its index, later ones get copies.
  const std::size_t n_in = m.positions.size();
  std::vector<std::uint32_t> vertex_of_fan(n_tri * 3, UINT32_MAX), first_fan(n_in, UINT32_MAX);
  std::vector<char> recompute(n_in, 0);
  for (std::uint32_t c = 0; c < n_tri * 3; ++c) {
    const std::uint32_t v = m.triangles[c / 3][c % 3], f = fans.find(c);
    if (first_fan[v] == UINT32_MAX) {
      first_fan[v] = f;
      vertex_of_fan[f] = v;
    } else if (vertex_of_fan[f] == UINT32_MAX) {
      vertex_of_fan[f] = static_cast<std::uint32_t>(m.positions.size());
      m.positions.push_back(m.positions[v]);
      m.normals.push_back(m.normals[v]);
      recompute[v] = 1;
      recompute.push_back(1);
    }
  }
  rep.crease_vertices = static_cast<std::uint32_t>(m.positions.size() - n_in);
  std::vector<V3> sum(m.positions.size(), V3{0, 0, 0});
  for (std::uint32_t c = 0; c < n_tri * 3; ++c) {
    const std::uint32_t t = c / 3, k = c % 3, u = vertex_of_fan[fans.find(c)];
    auto& tri = m.triangles[t];
    if (recompute[u]) {  // weight: the triangle's angle at the corner
      const V3 p = d3(m.positions[tri[k]]);
      const double w = std::acos(std::clamp(dot(unit(sub(d3(m.positions[tri[(k + 1) % 3]]), p)),
                                                unit(sub(d3(m.positions[tri[(k + 2) % 3]]), p))), -1.0, 1.0));
      for (int i = 0; i < 3; ++i) sum[u][static_cast<std::size_t>(i)] += w * fn[t][static_cast<std::size_t>(i)];
    }
  }
  for (std::uint32_t c = 0; c < n_tri * 3; ++c) m.triangles[c / 3][c % 3] = vertex_of_fan[fans.find(c)];
  for (std::size_t u = 0; u < m.positions.size(); ++u) {
    if (!recompute[u]) continue;
    const V3 n = unit(sum[u]);
    if (length(n) > 0) m.normals[u] = {static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2])};
  }
}

// Symmetric in a and b, so both sides of a seam get the same point.
std::array<float, 3> midpoint_position(const std::array<float, 3>& a, const std::array<float, 3>& b) {
  return {static_cast<float>(0.5 * (double{a[0]} + b[0])), static_cast<float>(0.5 * (double{a[1]} + b[1])),
          static_cast<float>(0.5 * (double{a[2]} + b[2]))};
}

// The rim's bound against the interior's (header).
constexpr double kRimFactor = 0.25;

// The angle between the normals at the ends of triangle t's edge k, degrees.
double edge_turn_deg(const TriangleMesh& m, std::uint32_t t, std::uint32_t k) {
  const auto& tri = m.triangles[t];
  return angle_deg(unit(d3(m.normals[tri[k]])), unit(d3(m.normals[tri[(k + 1) % 3]])));
}

// Largest normal turn along an edge longer than `min_length` (step 3's
// measure, for the report).
double largest_turn(const TriangleMesh& m, double min_length) {
  double turn = 0;
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
    for (std::uint32_t k = 0; k < 3; ++k) {
      if (edge_length(m, m.triangles[t][k], m.triangles[t][(k + 1) % 3]) > min_length) turn = std::max(turn, edge_turn_deg(m, t, k));
    }
  }
  return turn;
}

// Steps 2 and 3 (header): one halving round over the flat triangles' long
// edges and the curved ones' turning edges. Returns false when no edge
// needed splitting.
bool split_edges(TriangleMesh& m, std::vector<char>& flat, double h, double turn_deg, GlassRefineReport& rep) {
  const std::vector<std::uint32_t> weld = weld_positions(m);
  const std::vector<EdgeUse> uses = edge_uses(m, weld);
  // Vertices on a crease: their position is held by another vertex too.
  std::vector<std::uint32_t> holders(m.positions.size(), 0);
  for (std::uint32_t w : weld) ++holders[w];
  const auto on_crease = [&](std::uint32_t v) { return holders[weld[v]] > 1; };
  std::vector<char> split(m.triangles.size() * 3, 0);
  bool any = false;
  for_each_edge(uses, [&](std::size_t i, std::size_t j) {
    const double length = edge_length(m, uses[i].lo, uses[i].hi);
    bool flat_side = false, rim = false, turns = false;
    for (std::size_t u = i; u < j; ++u) {
      flat_side = flat_side || flat[uses[u].tri];
      for (std::uint32_t v : m.triangles[uses[u].tri]) rim = rim || on_crease(v);
      turns = turns || (turn_deg > 0 && length > h * kRimFactor && edge_turn_deg(m, uses[u].tri, uses[u].k) > turn_deg);
    }
    const bool long_flat = flat_side && length > (rim ? h * kRimFactor : h);
    if (!long_flat && !turns) return;
    // Far from the origin floats may not hold a point between the two ends.
    const auto mid = midpoint_position(m.positions[uses[i].lo], m.positions[uses[i].hi]);
    if (mid == m.positions[uses[i].lo] || mid == m.positions[uses[i].hi]) return;
    for (std::size_t u = i; u < j; ++u) split[3 * uses[u].tri + uses[u].k] = 1;
    rep.curved_edges_split += long_flat ? 0u : 1u;
    any = true;
  });
  if (!any) return false;

  // Midpoints per vertex-index edge: the two sides of a seam get a vertex
  // each, at the same position (the mean is symmetric in a and b).
  std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
  const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
    auto [it, inserted] = midpoints.try_emplace(key, static_cast<std::uint32_t>(m.positions.size()));
    if (inserted) {
      const V3 n = unit({double{m.normals[a][0]} + m.normals[b][0], double{m.normals[a][1]} + m.normals[b][1],
                         double{m.normals[a][2]} + m.normals[b][2]});
      m.positions.push_back(midpoint_position(m.positions[a], m.positions[b]));
      m.normals.push_back(length(n) > 0 ? std::array<float, 3>{static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2])}
                                        : m.normals[a]);
      ++rep.edges_split;
    }
    return it->second;
  };

  std::vector<std::array<std::uint32_t, 3>> tris;
  std::vector<char> tris_flat;
  tris.reserve(m.triangles.size() * 2);
  const auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, char f) {
    tris.push_back({a, b, c});
    tris_flat.push_back(f);
  };
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto v = m.triangles[t];
    const char* s = &split[3 * t];
    const int count = s[0] + s[1] + s[2];
    const char f = flat[t];
    if (count == 0) {
      emit(v[0], v[1], v[2], f);
    } else if (count == 3) {
      const std::uint32_t m01 = midpoint(v[0], v[1]), m12 = midpoint(v[1], v[2]), m20 = midpoint(v[2], v[0]);
      emit(v[0], m01, m20, f);
      emit(m01, v[1], m12, f);
      emit(m20, m12, v[2], f);
      emit(m01, m12, m20, f);
    } else if (count == 1) {  // rotate the split edge to a -> b
      const std::size_t k = s[0] ? 0 : s[1] ? 1 : 2;
      const std::uint32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3], mab = midpoint(a, b);
      emit(a, mab, c, f);
      emit(mab, b, c, f);
    } else {  // rotate the unsplit edge to c -> a; the quad a, m_ab, m_bc, c cut along its shorter diagonal
      const std::size_t k = !s[0] ? 0 : !s[1] ? 1 : 2;
      const std::uint32_t c = v[k], a = v[(k + 1) % 3], b = v[(k + 2) % 3];
      const std::uint32_t mab = midpoint(a, b), mbc = midpoint(b, c);
      emit(mab, b, mbc, f);
      if (edge_length(m, a, mbc) <= edge_length(m, mab, c)) {
        emit(a, mab, mbc, f);
        emit(a, mbc, c, f);
      } else {
        emit(a, mab, c, f);
        emit(mab, mbc, c, f);
      }
    }
  }
  m.triangles = std::move(tris);
  flat = std::move(tris_flat);
  return true;
}

double longest_flat_edge(const TriangleMesh& m, const std::vector<char>& flat) {
  double longest = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    if (!flat[t]) continue;
    for (std::size_t k = 0; k < 3; ++k) longest = std::max(longest, edge_length(m, m.triangles[t][k], m.triangles[t][(k + 1) % 3]));
  }
  return longest;
}

}  // namespace

TriangleMesh refine_transparent_mesh(const TriangleMesh& mesh, const GlassRefineOptions& options, GlassRefineReport* report) {
  GlassRefineReport rep;
  rep.vertices_in = static_cast<std::uint32_t>(mesh.positions.size());
  rep.triangles_in = static_cast<std::uint32_t>(mesh.triangles.size());
  TriangleMesh m = mesh;
  split_creases(m, options.crease_deg, rep);

  std::vector<char> flat(m.triangles.size(), 0);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const V3 fn = face_normal(m, t);
    bool f = length(fn) > 0;
    for (std::uint32_t v : m.triangles[t]) f = f && angle_deg(unit(d3(m.normals[v])), fn) <= options.flat_deg;
    flat[t] = f ? 1 : 0;
    rep.flat_triangles += f ? 1u : 0u;
  }
  rep.longest_flat_edge_in = longest_flat_edge(m, flat);

  V3 lo = d3(m.positions.front()), hi = lo;
  for (const auto& p : m.positions) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double{p[k]});
      hi[k] = std::max(hi[k], double{p[k]});
    }
  }
  rep.max_edge_m = options.max_edge * length(sub(hi, lo));
  // Each round halves the longest flat edge and the largest turn; 40
  // rounds reach 2^-40 of them.
  rep.max_turn_in = largest_turn(m, rep.max_edge_m * kRimFactor);
  const double turn_deg = rep.max_edge_m > 0 ? options.max_turn_deg : 0;  // step 3 needs the length bound
  if (rep.max_edge_m > 0) {
    while (rep.rounds < 40 && split_edges(m, flat, rep.max_edge_m, turn_deg, rep)) {
      ++rep.rounds;
      if (m.positions.size() > options.max_vertices) {
        rep.stopped_at_vertex_limit = true;
        break;
      }
    }
  }
  rep.longest_flat_edge_out = longest_flat_edge(m, flat);
  rep.max_turn_out = largest_turn(m, rep.max_edge_m * kRimFactor);
  rep.vertices_out = static_cast<std::uint32_t>(m.positions.size());
  rep.triangles_out = static_cast<std::uint32_t>(m.triangles.size());
  if (report) *report = rep;
  return m;
}

std::string describe_refinement(const GlassRefineReport& r, const GlassRefineOptions& o) {
  char line[512];
  std::snprintf(line, sizeof line,
                "refined for the light-transport table (--glass-crease %g, --glass-edge %g, --glass-turn %g): %u -> %u "
                "vertices, %u -> %u triangles; %u crease edge(s) gave %u vertex copies with their faces' normals; "
                "edges of flat triangles %.4g -> %.4g (bound %.4g); largest normal turn along an edge %.3g -> %.3g "
                "degrees (%u curved edge(s) split); %u halving round(s)%s",
                o.crease_deg, o.max_edge, o.max_turn_deg, r.vertices_in, r.vertices_out, r.triangles_in, r.triangles_out,
                r.crease_edges, r.crease_vertices, r.longest_flat_edge_in, r.longest_flat_edge_out, r.max_edge_m,
                r.max_turn_in, r.max_turn_out, r.curved_edges_split, r.rounds,
                r.stopped_at_vertex_limit ? "; stopped at the table's vertex limit" : "");
  return line;
}

}  // namespace caustix::bake
