#include "caustix/formats/mesh_decode.h"

#include <draco/compression/decode.h>

#include <algorithm>
#include <cmath>

namespace caustix {
namespace {

Error mesh_error(const MeshInfo& info, const std::string& msg) {
  return make_error(ErrorCode::kContainer, "mesh '" + info.source + "': " + msg);
}

}  // namespace

double position_error_bound(const std::array<float, 3>& lo, const std::array<float, 3>& hi, int bits) {
  double range = 0;
  for (int i = 0; i < 3; ++i) range = std::max(range, double{hi[static_cast<std::size_t>(i)]} - lo[static_cast<std::size_t>(i)]);
  if (range <= 0) range = 1;  // Draco's own convention for flat ranges
  const double delta = range / static_cast<double>((std::uint64_t{1} << bits) - 1);
  // Half a quantisation step, plus float rounding of min + q * delta.
  return 0.5 * delta + 4e-7 * (range + std::max(std::abs(double{lo[0]}), std::max(std::abs(double{lo[1]}), std::abs(double{lo[2]}))));
}

Result<TriangleMesh> decode_draco(std::span<const std::uint8_t> stream, const MeshInfo& info) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(stream.data()), stream.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok() || type.value() != draco::TRIANGULAR_MESH) {
    return mesh_error(info, "MESH chunk is not a Draco triangle mesh");
  }
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) return mesh_error(info, std::string("Draco decoding failed: ") + decoded.status().error_msg());
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();

  const draco::PointAttribute* pos = mesh->GetNamedAttribute(draco::GeometryAttribute::POSITION);
  const draco::PointAttribute* nrm = mesh->GetNamedAttribute(draco::GeometryAttribute::NORMAL);
  if (!pos || pos->num_components() != 3) return mesh_error(info, "no 3-component position attribute");
  if (!nrm || nrm->num_components() != 3) return mesh_error(info, "no 3-component normal attribute");
  // Texture coordinates are optional (receivers with a base-colour texture).
  const draco::PointAttribute* tex = mesh->GetNamedAttribute(draco::GeometryAttribute::TEX_COORD);
  if (tex && tex->num_components() != 2) return mesh_error(info, "texture coordinates with " + std::to_string(tex->num_components()) + " components (2 expected)");
  // Vertex colours are optional too (receivers with glTF's COLOR_0).
  const draco::PointAttribute* col = mesh->GetNamedAttribute(draco::GeometryAttribute::COLOR);
  if (col && col->num_components() != 4) return mesh_error(info, "vertex colours with " + std::to_string(col->num_components()) + " components (4 expected)");
  // Edgebreaker keeps every triangle but may split non-manifold vertices, so
  // the triangle count must match exactly and the vertex count is bounded.
  if (mesh->num_faces() != info.triangle_count || mesh->num_points() == 0 ||
      mesh->num_points() > 3 * std::uint64_t{info.triangle_count}) {
    return mesh_error(info, "decoded " + std::to_string(mesh->num_points()) + " vertices / " +
                                std::to_string(mesh->num_faces()) + " triangles, the scene records " +
                                std::to_string(info.vertex_count) + " / " + std::to_string(info.triangle_count));
  }

  TriangleMesh out;
  out.positions.resize(mesh->num_points());
  out.normals.resize(mesh->num_points());
  if (tex) out.uvs.resize(mesh->num_points());
  if (col) out.colors.resize(mesh->num_points());
  // Decoded positions may sit up to half a quantisation step outside the
  // source bounds (8 bits: 0.2 % of the extent); allow 1.5 times that.
  const double slack = 1.5 * position_error_bound(info.bounds_min, info.bounds_max, info.position_bits);
  for (draco::PointIndex i(0); i < mesh->num_points(); ++i) {
    auto& p = out.positions[i.value()];
    auto& n = out.normals[i.value()];
    if (!pos->ConvertValue<float, 3>(pos->mapped_index(i), p.data()) ||
        !nrm->ConvertValue<float, 3>(nrm->mapped_index(i), n.data())) {
      return mesh_error(info, "cannot read attributes of vertex " + std::to_string(i.value()));
    }
    for (std::size_t k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k]) || p[k] < info.bounds_min[k] - slack || p[k] > info.bounds_max[k] + slack) {
        return mesh_error(info, "vertex " + std::to_string(i.value()) + " lies outside the recorded bounds");
      }
    }
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!std::isfinite(len) || len < 0.5f) return mesh_error(info, "vertex " + std::to_string(i.value()) + " has an invalid normal");
    for (float& c : n) c /= len;
    if (tex) {
      auto& uv = out.uvs[i.value()];
      if (!tex->ConvertValue<float, 2>(tex->mapped_index(i), uv.data()) || !std::isfinite(uv[0]) || !std::isfinite(uv[1])) {
        return mesh_error(info, "vertex " + std::to_string(i.value()) + " has invalid texture coordinates");
      }
    }
    if (col) {
      // Quantisation may put a colour a step outside [0, 1]; clamped.
      auto& c = out.colors[i.value()];
      if (!col->ConvertValue<float, 4>(col->mapped_index(i), c.data())) return mesh_error(info, "cannot read the colour of vertex " + std::to_string(i.value()));
      for (float& x : c) {
        if (!std::isfinite(x) || x < -0.01f || x > 1.01f) return mesh_error(info, "vertex " + std::to_string(i.value()) + " has a colour outside [0, 1]");
        x = std::clamp(x, 0.0f, 1.0f);
      }
    }
  }
  out.triangles.resize(mesh->num_faces());
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
    const auto& face = mesh->face(f);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = face[k].value();
      if (v >= out.positions.size()) return mesh_error(info, "triangle " + std::to_string(f.value()) + " has an out-of-range index");
      out.triangles[f.value()][static_cast<std::size_t>(k)] = v;
    }
  }
  return out;
}

}  // namespace caustix
