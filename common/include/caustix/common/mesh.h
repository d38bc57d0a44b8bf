#pragma once
// An indexed triangle mesh in object space: what the baker imports and the
// runtime decodes. Plain data; invariants are established by the importer
// (bake/mesh_import.h) and checked again by the decoder.

#include <array>
#include <cstdint>
#include <vector>

namespace caustix {

struct TriangleMesh {
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 3>> normals;  // unit, one per position
  // Texture coordinates (glTF's TEXCOORD_0: (0, 0) is the image's first
  // texel, top-left): empty, or one per position. Only receivers with a
  // base-colour texture keep them.
  std::vector<std::array<float, 2>> uvs;
  // Vertex colours (glTF's COLOR_0: linear RGBA, each in [0, 1]): empty, or
  // one per position. Only receivers keep them; they multiply the base
  // colour.
  std::vector<std::array<float, 4>> colors;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise = front
};

}  // namespace caustix
