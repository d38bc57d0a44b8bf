#pragma once
// A triangle mesh in GL buffers (interleaved position + normal, uint32
// indices; texture coordinates and vertex colours, where the mesh has them,
// in buffers of their own as attributes 2 and 3, so that passes reading
// `vertices` as storage see the same 24-byte records either way). Internal
// to the runtime.

#include "caustix/common/mesh.h"
#include "gl_objects.h"

namespace caustix::runtime {

struct GpuMesh {
  gl::VertexArray vao;
  gl::Buffer vertices;
  gl::Buffer indices;
  gl::Buffer uvs;     // vec2 per vertex, or none
  gl::Buffer colors;  // vec4 per vertex, or none
  GLsizei index_count = 0;
  // Closed and consistently wound (common/mesh_topology.h): back faces are never seen from outside, so passes
  // that cut it open (Mihalik 2008 §5.1, fig. 3) may cull them.
  bool closed = false;

  std::uint64_t vertex_count = 0;  // interleaved position + normal, 24 bytes each
  bool has_uvs = false;            // 8 bytes more per vertex
  bool has_colors = false;         // 16 bytes more per vertex
  std::uint64_t gpu_bytes() const {
    return (24 + (has_uvs ? 8 : 0) + (has_colors ? 16 : 0)) * vertex_count + 4 * static_cast<std::uint64_t>(index_count);
  }

  void draw() const {
    glBindVertexArray(vao.get());
    glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
  }
};

GpuMesh upload_mesh(const TriangleMesh& mesh);

}  // namespace caustix::runtime
