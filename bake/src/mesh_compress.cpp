#include "caustix/bake/mesh_compress.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <tuple>
#include <type_traits>

namespace caustix::bake {


MeshInfo describe_mesh(const TriangleMesh& mesh, const DracoOptions& options) {
  MeshInfo info;
  info.vertex_count = static_cast<std::uint32_t>(mesh.positions.size());
  info.triangle_count = static_cast<std::uint32_t>(mesh.triangles.size());
  info.position_bits = static_cast<std::uint8_t>(options.position_bits);
  info.normal_bits = static_cast<std::uint8_t>(options.normal_bits);
  if (mesh.positions.empty()) return info;
  info.bounds_min = info.bounds_max = mesh.positions[0];
  for (const auto& p : mesh.positions) {
    for (std::size_t k = 0; k < 3; ++k) {
      info.bounds_min[k] = std::min(info.bounds_min[k], p[k]);
      info.bounds_max[k] = std::max(info.bounds_max[k], p[k]);
    }
  }
  return info;
}

Result<std::vector<std::uint8_t>> encode_draco(const TriangleMesh& in, const DracoOptions& opt) {
  if (opt.position_bits < 8 || opt.position_bits > 30 || opt.normal_bits < 6 || opt.normal_bits > 30 ||
      opt.speed < 0 || opt.speed > 10) {
    return make_error(ErrorCode::kUsage, "Draco options out of range");
  }
  draco::Mesh mesh;
  const auto n = static_cast<std::uint32_t>(in.positions.size());
  mesh.set_num_points(n);

  auto add = [&](draco::GeometryAttribute::Type type, const auto& values) {
    constexpr auto kComponents = static_cast<std::int8_t>(std::tuple_size_v<typename std::decay_t<decltype(values)>::value_type>);
    draco::GeometryAttribute ga;
    ga.Init(type, nullptr, kComponents, draco::DT_FLOAT32, false, sizeof(float) * kComponents, 0);
    const int id = mesh.AddAttribute(ga, /*identity_mapping=*/true, n);
    for (std::uint32_t i = 0; i < n; ++i) {
      mesh.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(i), values[i].data());
    }
  };
  add(draco::GeometryAttribute::POSITION, in.positions);
  add(draco::GeometryAttribute::NORMAL, in.normals);
  if (!in.uvs.empty()) add(draco::GeometryAttribute::TEX_COORD, in.uvs);
  if (!in.colors.empty()) add(draco::GeometryAttribute::COLOR, in.colors);
  for (const auto& t : in.triangles) {
    mesh.AddFace(draco::Mesh::Face{draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
  }

  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, opt.position_bits);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, opt.normal_bits);
  // Texture coordinates: 16 bits over their range (a 1/65535 step of a
  // 0..8 tiling range is 1/30 of a texel of a 1024 image).
  encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 16);
  // Vertex colours: 10 bits over their range, finer than an 8-bit colour.
  encoder.SetAttributeQuantization(draco::GeometryAttribute::COLOR, 10);
  encoder.SetSpeedOptions(opt.speed, opt.speed);
  encoder.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
  draco::EncoderBuffer buffer;
  const draco::Status st = encoder.EncodeMeshToBuffer(mesh, &buffer);
  if (!st.ok()) return make_error(ErrorCode::kInternal, std::string("Draco encoding failed: ") + st.error_msg());
  const auto* data = reinterpret_cast<const std::uint8_t*>(buffer.data());
  return std::vector<std::uint8_t>(data, data + buffer.size());
}

}  // namespace caustix::bake
