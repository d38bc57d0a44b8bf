#pragma once
// Small hostile meshes for the import, topology and bake tests (issue 8):
// a unit cube [0, 1]^3 with shared vertices, wound counter-clockwise seen
// from outside, and ways to break it.

#include <array>
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

inline std::string to_obj(const TriangleMesh& m) {
  std::string s;
  for (const auto& p : m.positions) s += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  for (const auto& t : m.triangles) s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  return s;
}

}  // namespace caustix::test
