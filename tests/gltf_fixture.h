#pragma once
// glTF 2.0 files written by the tests (tests/gltf_import_test.cpp): a JSON
// document plus one binary buffer, saved as .gltf with the buffer embedded
// (a base64 data URI) or beside it, or as .glb. Only what the glTF 2.0
// specification requires is written, so that the files are what an
// exporter writes, not what the importer happens to accept.

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "caustix/common/mesh.h"

namespace caustix::test {

class GltfBuilder {
 public:
  nlohmann::json doc{{"asset", {{"version", "2.0"}, {"generator", "caustix tests"}}}};
  std::vector<std::uint8_t> bin;

  // A buffer view over `bytes` bytes (4-byte aligned, as §3.6.2.4 requires).
  int view(const void* data, std::size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    const std::size_t offset = bin.size();
    bin.resize(offset + bytes);
    std::memcpy(bin.data() + offset, data, bytes);
    return push("bufferViews", {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
  }
  template <typename T>
  int accessor(const std::vector<T>& values, int component_type, const char* type, std::size_t count,
               bool normalized = false) {
    nlohmann::json a{{"bufferView", view(values.data(), values.size() * sizeof(T))},
                     {"componentType", component_type}, {"count", count}, {"type", type}};
    if (normalized) a["normalized"] = true;
    return push("accessors", a);
  }
  int positions(const std::vector<std::array<float, 3>>& p) {
    std::array<float, 3> lo = p.front(), hi = p.front();
    for (const auto& v : p) {
      for (std::size_t k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[k]), hi[k] = std::max(hi[k], v[k]);
    }
    std::vector<float> flat;
    for (const auto& v : p) flat.insert(flat.end(), v.begin(), v.end());
    const int a = accessor(flat, 5126, "VEC3", p.size());
    doc["accessors"][a]["min"] = lo;  // required for POSITION (§3.7.2.1)
    doc["accessors"][a]["max"] = hi;
    return a;
  }
  int normals(const std::vector<std::array<float, 3>>& n) {
    std::vector<float> flat;
    for (const auto& v : n) flat.insert(flat.end(), v.begin(), v.end());
    return accessor(flat, 5126, "VEC3", n.size());
  }
  int indices(const std::vector<std::uint32_t>& i) { return accessor(i, 5125, "SCALAR", i.size()); }
  int material(const nlohmann::json& m) { return push("materials", m); }
  int mesh(const nlohmann::json& primitives, const std::string& name = "") {
    nlohmann::json m{{"primitives", primitives}};
    if (!name.empty()) m["name"] = name;
    return push("meshes", m);
  }
  int node(const nlohmann::json& n) { return push("nodes", n); }
  void scene(const std::vector<int>& roots) {
    doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }
  // A KHR_draco_mesh_compression primitive (POSITION and NORMAL, Draco
  // attribute ids 0 and 1) over `stream`, a Draco mesh of `vertices`
  // points and `triangles` triangles within [-half, half]^3: its accessors
  // have no buffer views, as the extension writes them.
  nlohmann::json draco_primitive(const std::vector<std::uint8_t>& stream, int vertices, int triangles, float half, int material = -1) {
    const int v = view(stream.data(), stream.size());
    const int pa = static_cast<int>(doc["accessors"].size());
    doc["accessors"].push_back({{"componentType", 5126}, {"count", vertices}, {"type", "VEC3"}, {"min", {-half, -half, -half}}, {"max", {half, half, half}}});
    doc["accessors"].push_back({{"componentType", 5126}, {"count", vertices}, {"type", "VEC3"}});
    doc["accessors"].push_back({{"componentType", 5125}, {"count", 3 * triangles}, {"type", "SCALAR"}});
    nlohmann::json prim{{"attributes", {{"POSITION", pa}, {"NORMAL", pa + 1}}},
                        {"indices", pa + 2},
                        {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", v}, {"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}}}}}};
    if (material >= 0) prim["material"] = material;
    return prim;
  }
  void use_extension(const std::string& name, bool required = false) {
    doc["extensionsUsed"].push_back(name);
    if (required) doc["extensionsRequired"].push_back(name);
  }

  // .gltf with the buffer as a data URI.
  void write_embedded(const std::filesystem::path& path) {
    nlohmann::json d = doc;
    d["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
    std::ofstream(path) << d.dump(1);
  }
  // .gltf with the buffer in a .bin file beside it.
  void write_external(const std::filesystem::path& path, const std::string& bin_name) {
    nlohmann::json d = doc;
    d["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}, {"uri", bin_name}}});
    std::ofstream(path) << d.dump(1);
    std::ofstream(path.parent_path() / bin_name, std::ios::binary).write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
  }
  // .glb: header, JSON chunk (space-padded), BIN chunk (zero-padded), §4.4.
  std::vector<std::uint8_t> glb() const {
    nlohmann::json d = doc;
    d["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
    std::string json = d.dump();
    while (json.size() % 4) json.push_back(' ');
    std::vector<std::uint8_t> b = bin;
    while (b.size() % 4) b.push_back(0);
    std::vector<std::uint8_t> out;
    const auto u32 = [&](std::uint32_t v) {
      for (int k = 0; k < 4; ++k) out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
    };
    u32(0x46546C67);  // "glTF"
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + b.size()));
    u32(static_cast<std::uint32_t>(json.size()));
    u32(0x4E4F534A);  // "JSON"
    out.insert(out.end(), json.begin(), json.end());
    u32(static_cast<std::uint32_t>(b.size()));
    u32(0x004E4942);  // "BIN\0"
    out.insert(out.end(), b.begin(), b.end());
    return out;
  }
  void write_glb(const std::filesystem::path& path) const {
    const auto bytes = glb();
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }

 private:
  int push(const char* array, const nlohmann::json& value) {
    doc[array].push_back(value);
    return static_cast<int>(doc[array].size()) - 1;
  }
  static std::string base64(const std::vector<std::uint8_t>& in) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < in.size(); i += 3) {
      const std::uint32_t v = (std::uint32_t{in[i]} << 16) | (i + 1 < in.size() ? std::uint32_t{in[i + 1]} << 8 : 0) |
                              (i + 2 < in.size() ? in[i + 2] : 0);
      out += k[(v >> 18) & 63];
      out += k[(v >> 12) & 63];
      out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
      out += i + 2 < in.size() ? k[v & 63] : '=';
    }
    return out;
  }
};

// A unit cube centred at the origin as exporters write it: 24 vertices, four
// per face with the face's normal (hard edges), wound outward.
struct SplitCube {
  std::vector<std::array<float, 3>> positions, normals;
  std::vector<std::uint32_t> indices;
  explicit SplitCube(float half = 0.5f) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int sign = -1; sign <= 1; sign += 2) {
        std::array<float, 3> n{0, 0, 0};
        n[static_cast<std::size_t>(axis)] = static_cast<float>(sign);
        const auto u = static_cast<std::size_t>((axis + 1) % 3), v = static_cast<std::size_t>((axis + 2) % 3);
        const auto base = static_cast<std::uint32_t>(positions.size());
        for (int c = 0; c < 4; ++c) {
          std::array<float, 3> p{};
          p[static_cast<std::size_t>(axis)] = sign * half;
          p[u] = (c == 1 || c == 2) ? half : -half;
          p[v] = (c >= 2) ? half : -half;
          positions.push_back(p);
          normals.push_back(n);
        }
        // (u, v, axis) is right-handed: counter-clockwise seen from +axis.
        if (sign > 0) indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        else indices.insert(indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
      }
    }
  }
  // The same cube as the baker's mesh type (to encode with Draco).
  TriangleMesh triangle_mesh() const {
    TriangleMesh tm;
    tm.positions = positions;
    tm.normals = normals;
    for (std::size_t i = 0; i < indices.size(); i += 3) tm.triangles.push_back({indices[i], indices[i + 1], indices[i + 2]});
    return tm;
  }
};

}  // namespace caustix::test
