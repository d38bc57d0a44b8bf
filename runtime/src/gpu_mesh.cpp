#include "gpu_mesh.h"

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

namespace caustix::runtime {

GpuMesh upload_mesh(const TriangleMesh& m) {
  GpuMesh g;
  std::vector<float> interleaved;
  interleaved.reserve(m.positions.size() * 6);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    interleaved.insert(interleaved.end(), m.positions[i].begin(), m.positions[i].end());
    interleaved.insert(interleaved.end(), m.normals[i].begin(), m.normals[i].end());
  }
  g.vertices = gl::make_buffer();
  glNamedBufferStorage(g.vertices.get(), static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data(), 0);
  g.indices = gl::make_buffer();
  glNamedBufferStorage(g.indices.get(), static_cast<GLsizeiptr>(m.triangles.size() * 12), m.triangles.data(), 0);
  g.index_count = static_cast<GLsizei>(m.triangles.size() * 3);
  g.vao = gl::make_vertex_array();
  const GLuint vao = g.vao.get();
  glVertexArrayVertexBuffer(vao, 0, g.vertices.get(), 0, 6 * sizeof(float));
  glVertexArrayElementBuffer(vao, g.indices.get());
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao, 0, 0);
  glEnableVertexArrayAttrib(vao, 1);
  glVertexArrayAttribFormat(vao, 1, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
  glVertexArrayAttribBinding(vao, 1, 0);
  g.closed = is_closed(m);
  return g;
}

bool is_closed(const TriangleMesh& m) {
  if (m.triangles.empty()) return false;
  std::map<std::array<float, 3>, std::uint32_t> weld;
  std::vector<std::uint32_t> id(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) id[i] = weld.emplace(m.positions[i], static_cast<std::uint32_t>(weld.size())).first->second;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(m.triangles.size() * 3);
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) edges.emplace_back(id[t[k]], id[t[(k + 1) % 3]]);
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (i + 1 < edges.size() && edges[i] == edges[i + 1]) return false;  // the same direction twice
    if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(edges[i].second, edges[i].first))) return false;
  }
  return true;
}

}  // namespace caustix::runtime
