#pragma once
// Small hostile meshes for the import, topology and bake tests:
// a unit cube [0, 1]^3 with shared vertices, wound counter-clockwise seen
// from outside, and ways to break it; and a UV sphere.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "caustix/common/mesh.h"

namespace caustix::test {

enum class CubeFlaw { kNone, kFlippedFace, kInsideOut, kHole, kFin, kDuplicateFace };

inline TriangleMesh unit_cube(CubeFlaw flaw = CubeFlaw::kNone) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.positions.push_back({float(i >> 2), float((i >> 1) & 1), float(i & 1)});
  const std::array<std::array<std::uint32_t, 4>, 6> quads{{{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  auto& last = m.triangles.back();
  switch (flaw) {
    case CubeFlaw::kNone: break;
    case CubeFlaw::kFlippedFace: std::swap(last[1], last[2]); break;
    case CubeFlaw::kInsideOut: for (auto& t : m.triangles) std::swap(t[1], t[2]); break;
    case CubeFlaw::kHole: m.triangles.pop_back(); break;
    case CubeFlaw::kFin:  // a third triangle on the edge 0-1
      m.positions.push_back({-1, 0, 0.5f});
      m.triangles.push_back({0, 1, 8});
      break;
    case CubeFlaw::kDuplicateFace: m.triangles.push_back(m.triangles.front()); break;
  }
  m.normals.assign(m.positions.size(), {0, 1, 0});
  return m;
}

// The cube [-0.5, 0.5]^3 with each face an n x n grid of its own vertices
// (split seams, closed by position), outward counter-clockwise: flat faces
// with vertices inside them, which per-vertex light transport needs.
inline TriangleMesh subdivided_cube(int n) {
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {-1, 1}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      for (int i = 0; i <= n; ++i) {
        for (int k = 0; k <= n; ++k) {
          std::array<float, 3> p{};
          p[static_cast<std::size_t>(axis)] = 0.5f * static_cast<float>(side);
          p[static_cast<std::size_t>(u)] = static_cast<float>(i) / static_cast<float>(n) - 0.5f;
          p[static_cast<std::size_t>(v)] = static_cast<float>(k) / static_cast<float>(n) - 0.5f;
          m.positions.push_back(p);
          std::array<float, 3> normal{};
          normal[static_cast<std::size_t>(axis)] = static_cast<float>(side);
          m.normals.push_back(normal);
        }
      }
      const auto at = [&](int i, int k) { return base + static_cast<std::uint32_t>(i * (n + 1) + k); };
      for (int i = 0; i < n; ++i) {
        for (int k = 0; k < n; ++k) {
          // (u, v, axis) is right-handed: u x v = +axis, so (i,k) -> (i+1,k)
          // -> (i+1,k+1) winds counter-clockwise seen from +axis.
          std::array<std::uint32_t, 3> t0{at(i, k), at(i + 1, k), at(i + 1, k + 1)}, t1{at(i, k), at(i + 1, k + 1), at(i, k + 1)};
          if (side < 0) {
            std::swap(t0[1], t0[2]);
            std::swap(t1[1], t1[2]);
          }
          m.triangles.push_back(t0);
          m.triangles.push_back(t1);
        }
      }
    }
  }
  return m;
}

inline std::string to_obj(const TriangleMesh& m) {
  std::string s;
  for (const auto& p : m.positions) s += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  for (const auto& n : m.normals) s += "vn " + std::to_string(n[0]) + " " + std::to_string(n[1]) + " " + std::to_string(n[2]) + "\n";
  for (const auto& t : m.triangles) {
    s += "f";
    for (std::uint32_t i : t) s += " " + std::to_string(i + 1) + "//" + std::to_string(i + 1);
    s += "\n";
  }
  return s;
}

// A UV sphere of radius 1 with exact normals, `seg` segments x `rings`
// rings, wound outward (as assets/meshes/generate.py's sphere()).
inline TriangleMesh uv_sphere(int seg, int rings) {
  constexpr double kSpherePi = 3.14159265358979323846;
  TriangleMesh m;
  m.positions.push_back({0, 1, 0});
  for (int r = 1; r < rings; ++r) {
    const double th = kSpherePi * r / rings;
    for (int s = 0; s < seg; ++s) {
      const double ph = 2 * kSpherePi * s / seg;
      m.positions.push_back({static_cast<float>(std::sin(th) * std::cos(ph)), static_cast<float>(std::cos(th)),
                             static_cast<float>(std::sin(th) * std::sin(ph))});
    }
  }
  m.positions.push_back({0, -1, 0});
  m.normals = m.positions;
  const auto ring = [&](int r, int s) { return static_cast<std::uint32_t>(1 + (r - 1) * seg + s % seg); };
  const auto top = 0u, bottom = static_cast<std::uint32_t>(m.positions.size() - 1);
  for (int s = 0; s < seg; ++s) m.triangles.push_back({top, ring(1, s + 1), ring(1, s)});
  for (int r = 1; r < rings - 1; ++r) {
    for (int s = 0; s < seg; ++s) {
      m.triangles.push_back({ring(r, s), ring(r, s + 1), ring(r + 1, s + 1)});
      m.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r + 1, s)});
    }
  }
  for (int s = 0; s < seg; ++s) m.triangles.push_back({bottom, ring(rings - 1, s), ring(rings - 1, s + 1)});
  return m;
}

}  // namespace caustix::test
