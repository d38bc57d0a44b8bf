#include "gpu_mesh.h"

#include <vector>

#include "caustix/common/mesh_topology.h"

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
  g.vertex_count = m.positions.size();
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
  if (!m.uvs.empty() && m.uvs.size() == m.positions.size()) {
    g.uvs = gl::make_buffer();
    glNamedBufferStorage(g.uvs.get(), static_cast<GLsizeiptr>(m.uvs.size() * 8), m.uvs.data(), 0);
    g.has_uvs = true;
    glVertexArrayVertexBuffer(vao, 1, g.uvs.get(), 0, 2 * sizeof(float));
    glEnableVertexArrayAttrib(vao, 2);
    glVertexArrayAttribFormat(vao, 2, 2, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 2, 1);
  }
  if (!m.colors.empty() && m.colors.size() == m.positions.size()) {
    g.colors = gl::make_buffer();
    g.has_colors = true;
    glNamedBufferStorage(g.colors.get(), static_cast<GLsizeiptr>(m.colors.size() * 16), m.colors.data(), 0);
    glVertexArrayVertexBuffer(vao, 2, g.colors.get(), 0, 4 * sizeof(float));
    glEnableVertexArrayAttrib(vao, 3);
    glVertexArrayAttribFormat(vao, 3, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 3, 2);
  }
  g.closed = !m.triangles.empty() && census_edges(m).closed();
  return g;
}

}  // namespace caustix::runtime
