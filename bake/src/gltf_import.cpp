// glTF 2.0 import through tinygltf (docs/scene-format.md, "glTF scenes").
// tinygltf parses the JSON, the GLB container and the buffers (data URIs and
// external files); it trusts the indices it hands out, so every index,
// accessor range and the node hierarchy are checked here before use, and
// Draco-compressed primitives are decoded here (tinygltf's own Draco path
// indexes buffer views unchecked).

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <draco/compression/decode.h>

#include "caustix/bake/gltf_import.h"
#include "caustix/formats/spectrum.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <tuple>
#include <map>
#include <set>

#include "caustix/common/mesh_topology.h"
#include "caustix/formats/file_io.h"
#include "mesh_soup.h"

namespace caustix::bake {

namespace {

using Mat4d = std::array<double, 16>;  // column-major
using V3 = std::array<double, 3>;

constexpr Mat4d kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
constexpr double kPi = 3.14159265358979323846;
// glTF's lights are photometric (lux, candela); caustix's radiometric
// (W/m^2, W/sr). 683 lm/W is the definition of the candela at 555 nm and
// what Blender's exporter uses both ways.
constexpr double kLumensPerWatt = 683.0;
constexpr std::uint64_t kMaxFileBytes = std::uint64_t{2} << 30;
// Extensions whose content caustix uses.
const std::set<std::string> kSupported{"KHR_draco_mesh_compression", "KHR_mesh_quantization", "KHR_materials_transmission",
                                       "KHR_materials_ior", "KHR_materials_volume", "KHR_materials_dispersion",
                                       "KHR_lights_punctual", "KHR_texture_transform", "KHR_materials_emissive_strength"};

// Extensions a file may require that caustix can still import without them.
// The rule: an extension is ignorable when what it changes is something
// caustix does not read at all, so that ignoring it cannot change where
// light goes or how much of it: how textures are stored (a texture caustix
// cannot read falls back to its base colour factor, which changes only a
// receiver's colour, never the light that reaches it), and material layers that
// only add to a surface's own look (sheen, clearcoat, specular colour,
// iridescence, anisotropy, emission strength) -- each named in a warning.
// Not ignorable: anything that changes geometry (EXT_meshopt_compression,
// KHR_mesh_gpu_instancing would add objects) or what the base colour
// means (KHR_materials_pbrSpecularGlossiness).
const std::set<std::string> kIgnorable{"KHR_texture_basisu",         "EXT_texture_webp",
                                       "EXT_texture_avif",             "KHR_materials_emissive_strength", "KHR_materials_clearcoat",
                                       "KHR_materials_sheen",          "KHR_materials_specular",     "KHR_materials_iridescence",
                                       "KHR_materials_anisotropy",     "KHR_materials_variants",     "KHR_xmp_json_ld"};

// A vertex colour clamped into [0, 1] (NaN to 1: no tint).
std::array<float, 4> clamped_color(std::array<float, 4> c) {
  for (float& x : c) x = std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 1.0f;
  return c;
}

// A URI's %XX escapes decoded (glTF 2.0 §3.2: URIs are RFC 3986; file
// names with spaces arrive as %20).
std::string percent_decoded(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(uri[i]);
    }
  }
  return out;
}

Mat4d mul(const Mat4d& a, const Mat4d& b) {
  Mat4d r{};
  for (std::size_t c = 0; c < 4; ++c) {
    for (std::size_t rr = 0; rr < 4; ++rr) {
      double s = 0;
      for (std::size_t k = 0; k < 4; ++k) s += a[k * 4 + rr] * b[c * 4 + k];
      r[c * 4 + rr] = s;
    }
  }
  return r;
}
V3 apply_dir(const Mat4d& m, const V3& d) {
  return {m[0] * d[0] + m[4] * d[1] + m[8] * d[2], m[1] * d[0] + m[5] * d[1] + m[9] * d[2],
          m[2] * d[0] + m[6] * d[1] + m[10] * d[2]};
}
V3 normalized(const V3& v) {
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / len, v[1] / len, v[2] / len};
}
Vec3f to_f(const V3& v) { return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])}; }

// A value of an extension object, or nullptr.
const tinygltf::Value* field(const tinygltf::Value& obj, const char* key) {
  return obj.IsObject() && obj.Has(key) ? &obj.Get(key) : nullptr;
}
const tinygltf::Value* extension(const tinygltf::ExtensionMap& ext, const char* name) {
  const auto it = ext.find(name);
  return it == ext.end() ? nullptr : &it->second;
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    default: return "a matrix type";
  }
}

// KHR_draco_mesh_compression's primitives keep an "indices" accessor with
// no buffer view (the indices are in the Draco stream), which tinygltf 2.7
// refuses unless its own Draco path -- which indexes buffer views unchecked
// -- has filled it. Such "indices" are dropped from the JSON (of a .gltf, or
// of a GLB's first chunk) before tinygltf parses it; the primitive is
// decoded from its stream (decode_draco_primitive). Bytes that do not parse
// are left for tinygltf to refuse.
void without_draco_indices(std::vector<std::uint8_t>& bytes) {
  const bool glb = bytes.size() >= 20 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  std::size_t begin = 0, end = bytes.size();
  if (glb) {
    std::uint32_t chunk = 0, type = 0;
    std::memcpy(&chunk, bytes.data() + 12, 4);
    std::memcpy(&type, bytes.data() + 16, 4);
    if (type != 0x4E4F534A || chunk > bytes.size() - 20) return;  // "JSON"
    begin = 20;
    end = 20 + std::size_t{chunk};
  }
  nlohmann::json doc = nlohmann::json::parse(bytes.begin() + static_cast<std::ptrdiff_t>(begin), bytes.begin() + static_cast<std::ptrdiff_t>(end),
                                             nullptr, /*allow_exceptions=*/false);
  if (!doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array()) return;
  bool changed = false;
  for (auto& mesh : doc["meshes"]) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (auto& prim : mesh["primitives"]) {
      if (prim.is_object() && prim.contains("indices") && prim.contains("extensions") && prim["extensions"].is_object() &&
          prim["extensions"].contains("KHR_draco_mesh_compression")) {
        prim.erase("indices");
        changed = true;
      }
    }
  }
  if (!changed) return;
  std::string json = doc.dump();
  if (!glb) {
    bytes.assign(json.begin(), json.end());
    return;
  }
  while (json.size() % 4) json.push_back(' ');  // GLB 2.0 §4.4.3.1: padded with spaces
  std::vector<std::uint8_t> out(bytes.begin(), bytes.begin() + 12);
  const auto u32 = [&](std::size_t at, std::uint64_t v) {
    for (std::size_t k = 0; k < 4; ++k) out[at + k] = static_cast<std::uint8_t>(v >> (8 * k));
  };
  out.resize(20);
  u32(12, json.size());
  u32(16, 0x4E4F534A);
  out.insert(out.end(), json.begin(), json.end());
  out.insert(out.end(), bytes.begin() + static_cast<std::ptrdiff_t>(end), bytes.end());
  u32(8, out.size());
  bytes = std::move(out);
}

}  // namespace

struct GltfFile::Impl {
  std::string path;
  tinygltf::Model model;
  std::vector<std::string> inputs;
  std::vector<std::string> warnings;

  Error fail(const std::string& pointer, const std::string& msg) const {
    return make_error(ErrorCode::kInput, path + ": " + pointer + ": " + msg);
  }
  void warn(const std::string& msg, std::vector<std::string>& out) const { out.push_back(path + ": " + msg); }

  // An index into one of the model's arrays, as found at `pointer`.
  template <typename T>
  std::optional<Error> check_index(int index, const std::vector<T>& array, const char* what, const std::string& pointer) const {
    if (index >= 0 && static_cast<std::size_t>(index) < array.size()) return std::nullopt;
    return fail(pointer, std::string(what) + " " + std::to_string(index) + " does not exist (the file has " +
                             std::to_string(array.size()) + ")");
  }

  // The bytes [offset, offset + length) of buffer view `view`, checked.
  Result<const unsigned char*> view_bytes(int view, std::uint64_t offset, std::uint64_t length, const std::string& pointer) const {
    if (auto e = check_index(view, model.bufferViews, "buffer view", pointer)) return *e;
    const tinygltf::BufferView& bv = model.bufferViews[static_cast<std::size_t>(view)];
    const std::string bp = "/bufferViews/" + std::to_string(view);
    if (auto e = check_index(bv.buffer, model.buffers, "buffer", bp + "/buffer")) return *e;
    const auto& data = model.buffers[static_cast<std::size_t>(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset) {
      return fail(bp, "bytes " + std::to_string(bv.byteOffset) + " + " + std::to_string(bv.byteLength) + " run past the " +
                          std::to_string(data.size()) + " bytes of buffer " + std::to_string(bv.buffer));
    }
    if (offset > bv.byteLength || length > bv.byteLength - offset) {
      return fail(pointer, "bytes " + std::to_string(offset) + " + " + std::to_string(length) + " run past the " +
                               std::to_string(bv.byteLength) + " bytes of buffer view " + std::to_string(view));
    }
    return data.data() + bv.byteOffset + offset;
  }

  // Accessor `index` (referenced at `pointer`) as doubles, `components` per
  // element: normalised integers mapped to [0, 1] or [-1, 1] (glTF 2.0
  // §3.11), sparse substitutions applied. `allowed` lists the component
  // types the attribute may have.
  Result<std::vector<double>> read_accessor(int index, const std::string& pointer, int type, std::initializer_list<int> allowed,
                                            bool indices = false) const {
    if (auto e = check_index(index, model.accessors, "accessor", pointer)) return *e;
    const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(index)];
    const std::string ap = "/accessors/" + std::to_string(index);
    if (a.type != type) return fail(ap + "/type", std::string("expected ") + type_name(type) + " at " + pointer + ", got " + type_name(a.type));
    if (std::find(allowed.begin(), allowed.end(), a.componentType) == allowed.end()) {
      return fail(ap + "/componentType", "component type " + std::to_string(a.componentType) + " is not allowed for " + pointer);
    }
    if (a.count == 0 || a.count > 3 * std::uint64_t{kMaxMeshVertices}) {
      return fail(ap + "/count", "count " + std::to_string(a.count) + " is outside 1.." + std::to_string(3 * std::uint64_t{kMaxMeshVertices}));
    }
    const auto comp = static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(type)));
    const auto csize = static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType)));
    std::vector<double> out(a.count * comp, 0.0);
    const auto decode = [&](const unsigned char* p, int ctype, bool normalized) {
      double v = 0;
      switch (ctype) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: { std::int8_t x; std::memcpy(&x, p, 1); v = normalized ? std::max(x / 127.0, -1.0) : x; break; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: { std::uint8_t x; std::memcpy(&x, p, 1); v = normalized ? x / 255.0 : x; break; }
        case TINYGLTF_COMPONENT_TYPE_SHORT: { std::int16_t x; std::memcpy(&x, p, 2); v = normalized ? std::max(x / 32767.0, -1.0) : x; break; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t x; std::memcpy(&x, p, 2); v = normalized ? x / 65535.0 : x; break; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { std::uint32_t x; std::memcpy(&x, p, 4); v = x; break; }
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float x; std::memcpy(&x, p, 4); v = x; break; }
        default: break;
      }
      return v;
    };
    const bool normalized = a.normalized && !indices;
    if (a.bufferView >= 0) {
      const std::size_t elem = comp * csize;
      std::size_t stride = elem;
      if (static_cast<std::size_t>(a.bufferView) < model.bufferViews.size()) {
        const std::size_t s = model.bufferViews[static_cast<std::size_t>(a.bufferView)].byteStride;
        if (s != 0 && s < elem) {
          return fail("/bufferViews/" + std::to_string(a.bufferView) + "/byteStride",
                      "stride " + std::to_string(s) + " is shorter than the " + std::to_string(elem) + "-byte elements of accessor " + std::to_string(index));
        }
        if (s != 0) stride = s;
      }
      auto bytes = view_bytes(a.bufferView, a.byteOffset, stride * (a.count - 1) + elem, ap);
      if (!bytes) return bytes.error();
      for (std::size_t i = 0; i < a.count; ++i) {
        for (std::size_t k = 0; k < comp; ++k) out[i * comp + k] = decode(*bytes + i * stride + k * csize, a.componentType, normalized);
      }
    }  // else all zeros (glTF 2.0 §3.6.2.1), or a sparse accessor's base
    if (a.sparse.isSparse) {
      const std::string sp = ap + "/sparse";
      const auto n = static_cast<std::size_t>(std::max(a.sparse.count, 0));
      if (a.sparse.count <= 0 || n > a.count) return fail(sp + "/count", "must be in 1.." + std::to_string(a.count));
      const int itype = a.sparse.indices.componentType;
      if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
          itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        return fail(sp + "/indices/componentType", "must be an unsigned integer type");
      }
      const auto isize = static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(itype)));
      auto ib = view_bytes(a.sparse.indices.bufferView, static_cast<std::uint64_t>(std::max(a.sparse.indices.byteOffset, 0)), n * isize, sp + "/indices");
      if (!ib) return ib.error();
      auto vb = view_bytes(a.sparse.values.bufferView, static_cast<std::uint64_t>(std::max(a.sparse.values.byteOffset, 0)), n * comp * csize, sp + "/values");
      if (!vb) return vb.error();
      for (std::size_t i = 0; i < n; ++i) {
        const auto target = static_cast<std::uint64_t>(decode(*ib + i * isize, itype, false));
        if (target >= a.count) return fail(sp + "/indices", "index " + std::to_string(target) + " is beyond the accessor's " + std::to_string(a.count) + " elements");
        for (std::size_t k = 0; k < comp; ++k) out[target * comp + k] = decode(*vb + (i * comp + k) * csize, a.componentType, normalized);
      }
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (!std::isfinite(out[i]) || std::fabs(out[i]) > 3.0e38) {
        return fail(ap, "element " + std::to_string(i / comp) + " has a non-finite or out-of-range value");
      }
    }
    return out;
  }

  // One triangle primitive's corners, appended to a soup-in-the-making.
  struct Corners {
    std::vector<V3> positions;
    std::vector<V3> normals;  // empty, or one per position
    std::vector<std::array<float, 2>> uvs;  // empty, or one per position (the base-colour texture's set)
    std::vector<std::array<float, 4>> colors;  // empty, or one per position (COLOR_0, RGBA)
    std::vector<std::array<std::uint32_t, 3>> triangles;
  };

  Result<Corners> decode_draco_primitive(const tinygltf::Value& ext, const std::string& pp, int texcoord, bool colors) const {
    const std::string ep = pp + "/extensions/KHR_draco_mesh_compression";
    const tinygltf::Value* view = field(ext, "bufferView");
    const tinygltf::Value* attrs = field(ext, "attributes");
    if (!view || !view->IsInt()) return fail(ep + "/bufferView", "expected a buffer view index");
    if (!attrs || !attrs->IsObject()) return fail(ep + "/attributes", "expected an object");
    const int v = view->GetNumberAsInt();
    if (auto e = check_index(v, model.bufferViews, "buffer view", ep + "/bufferView")) return *e;
    auto bytes = view_bytes(v, 0, model.bufferViews[static_cast<std::size_t>(v)].byteLength, ep + "/bufferView");
    if (!bytes) return bytes.error();
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(*bytes), model.bufferViews[static_cast<std::size_t>(v)].byteLength);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) return fail(ep, std::string("Draco decoding failed: ") + decoded.status().error_msg());
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    const auto attribute = [&](const char* name) -> Result<const draco::PointAttribute*> {
      const tinygltf::Value* id = field(*attrs, name);
      if (!id) return static_cast<const draco::PointAttribute*>(nullptr);
      const draco::PointAttribute* a = id->IsInt() ? mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(id->GetNumberAsInt())) : nullptr;
      const bool color = std::string_view(name) == "COLOR_0";
      const int want = std::string_view(name).rfind("TEXCOORD_", 0) == 0 ? 2 : 3;
      if (!a || (color ? a->num_components() != 3 && a->num_components() != 4 : a->num_components() != want)) {
        return fail(ep + "/attributes/" + name, "no " + (color ? std::string("3- or 4") : std::to_string(want)) + "-component Draco attribute with this id");
      }
      return a;
    };
    auto pos = attribute("POSITION");
    if (!pos) return pos.error();
    if (!*pos) return fail(ep + "/attributes", "no POSITION");
    auto nrm = attribute("NORMAL");
    if (!nrm) return nrm.error();
    const std::string uv_name = "TEXCOORD_" + std::to_string(std::max(texcoord, 0));
    auto tex = texcoord >= 0 ? attribute(uv_name.c_str()) : Result<const draco::PointAttribute*>(static_cast<const draco::PointAttribute*>(nullptr));
    if (!tex) return tex.error();
    auto col = colors ? attribute("COLOR_0") : Result<const draco::PointAttribute*>(static_cast<const draco::PointAttribute*>(nullptr));
    if (!col) return col.error();
    if (mesh->num_points() > kMaxMeshVertices) return fail(ep, "more than " + std::to_string(kMaxMeshVertices) + " vertices");
    Corners c;
    c.positions.resize(mesh->num_points());
    if (*nrm) c.normals.resize(mesh->num_points());
    for (draco::PointIndex i(0); i < mesh->num_points(); ++i) {
      std::array<float, 3> p{}, n{};
      if (!(*pos)->ConvertValue<float, 3>((*pos)->mapped_index(i), p.data()) ||
          (*nrm && !(*nrm)->ConvertValue<float, 3>((*nrm)->mapped_index(i), n.data()))) {
        return fail(ep, "cannot read the attributes of Draco point " + std::to_string(i.value()));
      }
      c.positions[i.value()] = {p[0], p[1], p[2]};
      if (*nrm) c.normals[i.value()] = {n[0], n[1], n[2]};
      if (*tex) {
        std::array<float, 2> uv{};
        if (!(*tex)->ConvertValue<float, 2>((*tex)->mapped_index(i), uv.data()) || !std::isfinite(uv[0]) || !std::isfinite(uv[1])) {
          return fail(ep, "cannot read the texture coordinates of Draco point " + std::to_string(i.value()));
        }
        c.uvs.push_back(uv);
      }
      if (*col) {
        std::array<float, 4> rgba{1, 1, 1, 1};
        const bool read = (*col)->num_components() == 4 ? (*col)->ConvertValue<float, 4>((*col)->mapped_index(i), rgba.data())
                                                        : (*col)->ConvertValue<float, 3>((*col)->mapped_index(i), rgba.data());
        if (!read) return fail(ep, "cannot read the colour of Draco point " + std::to_string(i.value()));
        c.colors.push_back(clamped_color(rgba));
      }
    }
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
      const auto& face = mesh->face(f);
      c.triangles.push_back({face[0].value(), face[1].value(), face[2].value()});
    }
    return c;
  }

  // The triangles of primitive k of mesh m (an empty result for points and
  // lines, with a warning).
  // With `texcoord` >= 0, TEXCOORD_<texcoord> too (a textured receiver's);
  // with `colors`, COLOR_0 (a receiver's vertex colours).
  Result<Corners> primitive_corners(std::size_t m, std::size_t k, std::vector<std::string>& warns, int texcoord = -1, bool colors = false) const {
    const tinygltf::Primitive& prim = model.meshes[m].primitives[k];
    const std::string pp = "/meshes/" + std::to_string(m) + "/primitives/" + std::to_string(k);
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      if (mode < 0 || mode > 6) return fail(pp + "/mode", "unknown mode " + std::to_string(mode));
      warn(pp + ": points or lines (mode " + std::to_string(mode) + ") are not a surface; skipped", warns);
      return Corners{};
    }
    if (!prim.targets.empty()) warn(pp + ": " + std::to_string(prim.targets.size()) + " morph target(s) ignored (the bake takes the base shape)", warns);
    if (const tinygltf::Value* draco = extension(prim.extensions, "KHR_draco_mesh_compression")) {
      return decode_draco_primitive(*draco, pp, texcoord, colors);
    }
    const auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) return fail(pp + "/attributes", "no POSITION attribute");
    // KHR_mesh_quantization allows integer positions and normals.
    const std::initializer_list<int> any_type{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                              TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
    auto pos = read_accessor(pos_it->second, pp + "/attributes/POSITION", TINYGLTF_TYPE_VEC3, any_type);
    if (!pos) return pos.error();
    Corners c;
    const std::size_t n = pos->size() / 3;
    for (std::size_t i = 0; i < n; ++i) c.positions.push_back({(*pos)[3 * i], (*pos)[3 * i + 1], (*pos)[3 * i + 2]});
    if (const auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
      auto nrm = read_accessor(it->second, pp + "/attributes/NORMAL", TINYGLTF_TYPE_VEC3,
                               {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT});
      if (!nrm) return nrm.error();
      if (nrm->size() != pos->size()) return fail(pp + "/attributes/NORMAL", "count differs from POSITION's " + std::to_string(n));
      for (std::size_t i = 0; i < n; ++i) c.normals.push_back({(*nrm)[3 * i], (*nrm)[3 * i + 1], (*nrm)[3 * i + 2]});
    }
    if (texcoord >= 0) {
      const std::string name = "TEXCOORD_" + std::to_string(texcoord);
      const auto it = prim.attributes.find(name);
      if (it == prim.attributes.end()) return fail(pp + "/attributes", "no " + name + " for its material's textures");
      auto uv = read_accessor(it->second, pp + "/attributes/" + name, TINYGLTF_TYPE_VEC2, any_type);
      if (!uv) return uv.error();
      if (uv->size() != 2 * n) return fail(pp + "/attributes/" + name, "count differs from POSITION's " + std::to_string(n));
      for (std::size_t i = 0; i < n; ++i) c.uvs.push_back({static_cast<float>((*uv)[2 * i]), static_cast<float>((*uv)[2 * i + 1])});
    }
    if (colors) {
      // glTF 2.0 §3.7.2.1: COLOR_0 is VEC3 or VEC4, float or normalised
      // unsigned byte or short, linear.
      const auto it = prim.attributes.find("COLOR_0");
      if (it == prim.attributes.end()) return fail(pp + "/attributes", "no COLOR_0");
      if (auto e = check_index(it->second, model.accessors, "accessor", pp + "/attributes/COLOR_0")) return *e;
      const int type = model.accessors[static_cast<std::size_t>(it->second)].type == TINYGLTF_TYPE_VEC3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
      auto col = read_accessor(it->second, pp + "/attributes/COLOR_0", type,
                               {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
      if (!col) return col.error();
      const std::size_t comp = type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
      if (col->size() != comp * n) return fail(pp + "/attributes/COLOR_0", "count differs from POSITION's " + std::to_string(n));
      for (std::size_t i = 0; i < n; ++i) {
        std::array<float, 4> rgba{1, 1, 1, 1};
        for (std::size_t k2 = 0; k2 < comp; ++k2) rgba[k2] = static_cast<float>((*col)[comp * i + k2]);
        c.colors.push_back(clamped_color(rgba));
      }
    }
    std::vector<std::uint32_t> idx;
    if (prim.indices >= 0) {
      auto ind = read_accessor(prim.indices, pp + "/indices", TINYGLTF_TYPE_SCALAR,
                               {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT}, true);
      if (!ind) return ind.error();
      for (std::size_t i = 0; i < ind->size(); ++i) {
        const double v = (*ind)[i];
        if (v >= static_cast<double>(n)) {
          return fail("/accessors/" + std::to_string(prim.indices), "index " + std::to_string(static_cast<std::uint64_t>(v)) + " at element " +
                                                                        std::to_string(i) + " is beyond the " + std::to_string(n) + " vertices of POSITION");
        }
        idx.push_back(static_cast<std::uint32_t>(v));
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) idx.push_back(static_cast<std::uint32_t>(i));
    }
    // glTF 2.0 §3.7.2.1: strips alternate their winding, fans share corner 0.
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (idx.size() % 3 != 0) warn(pp + ": " + std::to_string(idx.size()) + " indices is not a multiple of 3; the last ones are ignored", warns);
      for (std::size_t i = 0; i + 2 < idx.size(); i += 3) c.triangles.push_back({idx[i], idx[i + 1], idx[i + 2]});
    } else {
      for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_FAN) c.triangles.push_back({idx[0], idx[i + 1], idx[i + 2]});
        else if (i % 2 == 0) c.triangles.push_back({idx[i], idx[i + 1], idx[i + 2]});
        else c.triangles.push_back({idx[i + 1], idx[i], idx[i + 2]});
      }
    }
    return c;
  }

  // Primitives -> one imported mesh. Corners at the same position (and,
  // without `weld`, the same normal) are merged; merged normals are summed
  // and renormalised by mesh_from_soup.
  Result<ImportedMesh> make_mesh(std::vector<Corners> parts, bool weld, const std::string& pointer) const {
    // Seam copies a few ulps apart become one position first
    // (snap_close_points), so that welding and the topology checks see them.
    std::vector<V3> all;
    for (const Corners& c : parts) all.insert(all.end(), c.positions.begin(), c.positions.end());
    snap_close_points(all);
    for (std::size_t i = 0; Corners& c : parts) {
      for (V3& p : c.positions) p = all[i++];
    }
    PolygonSoup soup;
    std::map<std::array<float, 12>, std::uint32_t> index;
    const bool normals = std::all_of(parts.begin(), parts.end(), [](const Corners& c) { return !c.normals.empty(); });
    // Texture coordinates split vertices as normals do (a UV seam), unless welded.
    const bool uvs = !weld && std::all_of(parts.begin(), parts.end(), [](const Corners& c) { return !c.uvs.empty() && c.uvs.size() == c.positions.size(); });
    // Vertex colours split vertices as texture coordinates do.
    const bool colors = !weld && std::all_of(parts.begin(), parts.end(), [](const Corners& c) { return !c.colors.empty() && c.colors.size() == c.positions.size(); });
    std::vector<V3> normal_sum;
    for (const Corners& c : parts) {
      std::vector<std::uint32_t> remap(c.positions.size());
      for (std::size_t i = 0; i < c.positions.size(); ++i) {
        const V3& p = c.positions[i];
        const V3 n = normals ? c.normals[i] : V3{0, 0, 0};
        std::array<float, 12> key{static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]), 0, 0, 0, 0, 0, 0, 0, 0, 0};
        if (!weld) {
          for (std::size_t k = 0; k < 3; ++k) key[3 + k] = static_cast<float>(n[k]);
        }
        if (uvs) {
          key[6] = c.uvs[i][0];
          key[7] = c.uvs[i][1];
        }
        if (colors) std::copy(c.colors[i].begin(), c.colors[i].end(), key.begin() + 8);
        const auto [it, inserted] = index.emplace(key, static_cast<std::uint32_t>(soup.points.size()));
        if (inserted) {
          soup.points.push_back(p);
          normal_sum.push_back({0, 0, 0});
          if (uvs) soup.uvs.push_back(c.uvs[i]);
          if (colors) soup.colors.push_back(c.colors[i]);
        }
        if (normals) {
          const V3 u = normalized(n);
          for (std::size_t k = 0; k < 3; ++k) normal_sum[it->second][k] += std::isfinite(u[k]) ? u[k] : 0;
        }
        remap[i] = it->second;
      }
      for (const auto& t : c.triangles) {
        for (std::uint32_t v : t) {
          if (v >= remap.size()) return fail(pointer, "a Draco face refers to point " + std::to_string(v) + " of " + std::to_string(remap.size()));
          soup.corners.push_back(remap[v]);
        }
        soup.add_polygon_end();
      }
    }
    if (normals) soup.normals = std::move(normal_sum);
    if (soup.points.size() > kMaxMeshVertices) return fail(pointer, "more than " + std::to_string(kMaxMeshVertices) + " vertices");
    auto mesh = mesh_from_soup(std::move(soup));
    if (!mesh) return fail(pointer, mesh.error().message);
    return mesh;
  }

  // The node's local matrix (glTF 2.0 §3.5.3: matrix, or T * R * S).
  Result<Mat4d> local_matrix(std::size_t i) const {
    const tinygltf::Node& n = model.nodes[i];
    const std::string np = "/nodes/" + std::to_string(i);
    Mat4d m = kIdentity;
    if (!n.matrix.empty()) {
      if (n.matrix.size() != 16) return fail(np + "/matrix", "expected 16 numbers");
      std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
      if (m[3] != 0 || m[7] != 0 || m[11] != 0 || m[15] != 1) return fail(np + "/matrix", "not an affine transform (last row must be 0 0 0 1)");
    } else {
      V3 t{0, 0, 0}, s{1, 1, 1};
      std::array<double, 4> q{0, 0, 0, 1};
      if (!n.translation.empty() && n.translation.size() != 3) return fail(np + "/translation", "expected 3 numbers");
      if (!n.scale.empty() && n.scale.size() != 3) return fail(np + "/scale", "expected 3 numbers");
      if (!n.rotation.empty() && n.rotation.size() != 4) return fail(np + "/rotation", "expected 4 numbers (a quaternion x, y, z, w)");
      std::copy(n.translation.begin(), n.translation.end(), t.begin());
      std::copy(n.scale.begin(), n.scale.end(), s.begin());
      std::copy(n.rotation.begin(), n.rotation.end(), q.begin());
      const double ql = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      if (!(ql > 1e-6)) return fail(np + "/rotation", "not a unit quaternion");
      for (double& c : q) c /= ql;
      const double x = q[0], y = q[1], z = q[2], w = q[3];
      const std::array<double, 9> r{1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w),
                                    2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                                    2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)};
      for (std::size_t c = 0; c < 3; ++c) {
        for (std::size_t rr = 0; rr < 3; ++rr) m[c * 4 + rr] = r[c * 3 + rr] * s[c];
      }
      m[12] = t[0];
      m[13] = t[1];
      m[14] = t[2];
    }
    for (double v : m) {
      if (!std::isfinite(v) || std::fabs(v) > 1e30) return fail(np, "non-finite or out-of-range transform");
    }
    return m;
  }

  std::string node_name(std::size_t i) const {
    return model.nodes[i].name.empty() ? "node" + std::to_string(i) : model.nodes[i].name;
  }

  // A texture of a receiver's material (glTF 2.0 §3.9.6: the texture's
  // image, TEXCOORD_n, the sampler's wraps; KHR_texture_transform) at
  // `tp`, with the texture-coordinate set it reads; nullopt when caustix
  // cannot read its image (said in a warning). `data`: a normal,
  // metallic-roughness or occlusion texture (linear values); `keep_alpha`:
  // the base colour of a material that masks or blends. Images are listed
  // once each per use as colour or data in `images` (image_of: (glTF
  // image, data) -> index there).
  Result<std::optional<std::pair<MapTexture, int>>> texture(int tex, int tex_coord, const tinygltf::ExtensionMap& extensions, const std::string& tp,
                                                           bool data, bool keep_alpha, std::vector<ImageSource>& images,
                                                           std::map<std::pair<int, bool>, std::uint32_t>& image_of,
                                                           std::vector<std::string>& warns) const {
    if (auto e = check_index(tex, model.textures, "texture", tp + "/index")) return *e;
    const tinygltf::Texture& t = model.textures[static_cast<std::size_t>(tex)];
    const std::string xp = "/textures/" + std::to_string(tex);
    if (t.source < 0) {
      warn(xp + ": no PNG or JPEG source (a KHR_texture_basisu, EXT_texture_webp or EXT_texture_avif image only); " + tp + " is not used", warns);
      return std::optional<std::pair<MapTexture, int>>{};
    }
    if (auto e = check_index(t.source, model.images, "image", xp + "/source")) return *e;
    MapTexture a;
    int texcoord = tex_coord;
    if (t.sampler >= 0) {
      if (auto e = check_index(t.sampler, model.samplers, "sampler", xp + "/sampler")) return *e;
      const tinygltf::Sampler& smp = model.samplers[static_cast<std::size_t>(t.sampler)];
      const auto wrap = [](int w) {
        return w == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE ? TextureWrap::kClamp
                                                        : (w == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? TextureWrap::kMirror : TextureWrap::kRepeat);
      };
      a.wrap_s = wrap(smp.wrapS);
      a.wrap_t = wrap(smp.wrapT);
    }
    if (const tinygltf::Value* tt = extension(extensions, "KHR_texture_transform")) {
      const std::string ep = tp + "/extensions/KHR_texture_transform";
      std::array<float, 2> offset{0, 0}, scale{1, 1};
      float rotation = 0;
      for (const auto& [name, out] : {std::pair{"offset", &offset}, std::pair{"scale", &scale}}) {
        const tinygltf::Value* v = field(*tt, name);
        if (!v) continue;
        if (!v->IsArray() || v->ArrayLen() != 2) return fail(ep + "/" + name, "expected 2 numbers");
        for (int k = 0; k < 2; ++k) {
          const tinygltf::Value& x = v->Get(k);
          if (!x.IsNumber() || !(std::fabs(x.GetNumberAsDouble()) < 1e6)) return fail(ep + "/" + name + "/" + std::to_string(k), "must be a number below 1e6 in magnitude");
          (*out)[static_cast<std::size_t>(k)] = static_cast<float>(x.GetNumberAsDouble());
        }
      }
      if (const tinygltf::Value* v = field(*tt, "rotation")) {
        if (!v->IsNumber() || !std::isfinite(v->GetNumberAsDouble())) return fail(ep + "/rotation", "must be a number");
        rotation = static_cast<float>(v->GetNumberAsDouble());
      }
      if (const tinygltf::Value* v = field(*tt, "texCoord")) {
        if (!v->IsInt() || v->GetNumberAsInt() < 0) return fail(ep + "/texCoord", "must be a whole number >= 0");
        texcoord = v->GetNumberAsInt();
      }
      a.transform = texture_transform(offset, rotation, scale);
    }
    const auto [at, added] = image_of.emplace(std::pair{t.source, data}, static_cast<std::uint32_t>(images.size()));
    if (added) {
      const tinygltf::Image& gi = model.images[static_cast<std::size_t>(t.source)];
      const std::string ip = "/images/" + std::to_string(t.source);
      ImageSource src;
      src.where = path + ": " + ip;
      src.fall_back = true;
      src.data = data;
      if (!gi.uri.empty()) {
        src.path = (std::filesystem::path(path).parent_path() / percent_decoded(gi.uri)).lexically_normal().string();
        src.name = percent_decoded(gi.uri);  // as the file names it (TEXR records it)
      } else {
        src.name = ip + (gi.name.empty() ? "" : " ('" + gi.name + "')");
        src.mime_type = gi.mimeType;
        if (gi.bufferView >= 0) {
          if (auto e = check_index(gi.bufferView, model.bufferViews, "buffer view", ip + "/bufferView")) return *e;
          const auto length = model.bufferViews[static_cast<std::size_t>(gi.bufferView)].byteLength;
          auto bytes = view_bytes(gi.bufferView, 0, length, ip + "/bufferView");
          if (!bytes) return bytes.error();
          src.bytes.assign(*bytes, *bytes + length);
        } else {
          src.bytes = gi.image;  // a data URI's bytes (the image loader kept them)
        }
      }
      images.push_back(std::move(src));
    }
    if (keep_alpha) images[at->second].keep_alpha = true;
    a.image = at->second;
    return std::optional{std::pair{a, texcoord}};
  }

  // The textures of receiver material `index` into `mat` (its albedo
  // texture and SurfaceMaps), and the texture-coordinate set they read
  // (-1: none). caustix's meshes carry one set: a map on another set than
  // the first one read is named in a warning and left out.
  Result<int> material_textures(int index, Material& mat, std::vector<ImageSource>& images, std::map<std::pair<int, bool>, std::uint32_t>& image_of,
                                std::vector<std::string>& warns) const {
    const tinygltf::Material& gm = model.materials[static_cast<std::size_t>(index)];
    const std::string mp = "/materials/" + std::to_string(index);
    int texcoord = -1;
    const auto take = [&](int tex, int tex_coord, const tinygltf::ExtensionMap& ext, const std::string& tp, bool data, bool keep_alpha,
                          std::optional<MapTexture>& out) -> Status {
      if (tex < 0) return Status::success();
      auto t = texture(tex, tex_coord, ext, tp, data, keep_alpha, images, image_of, warns);
      if (!t) return t.error();
      if (!*t) return Status::success();
      if (texcoord >= 0 && (*t)->second != texcoord) {
        warn(tp + " reads TEXCOORD_" + std::to_string((*t)->second) + ", the material's other textures TEXCOORD_" + std::to_string(texcoord) +
                 "; caustix keeps one set, so this texture is not used",
             warns);
        return Status::success();
      }
      texcoord = (*t)->second;
      out = (*t)->first;
      return Status::success();
    };
    const auto& pbr = gm.pbrMetallicRoughness;
    const bool blends = mat.maps && mat.maps->alpha_mode != AlphaMode::kOpaque;
    CAUSTIX_RETURN_IF_ERROR(take(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions,
                                 mp + "/pbrMetallicRoughness/baseColorTexture", false, blends, mat.albedo_texture));
    SurfaceMaps maps = mat.maps.value_or(SurfaceMaps{});
    CAUSTIX_RETURN_IF_ERROR(take(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, pbr.metallicRoughnessTexture.extensions,
                                 mp + "/pbrMetallicRoughness/metallicRoughnessTexture", true, false, maps.metallic_roughness));
    CAUSTIX_RETURN_IF_ERROR(take(gm.normalTexture.index, gm.normalTexture.texCoord, gm.normalTexture.extensions, mp + "/normalTexture", true, false, maps.normal));
    CAUSTIX_RETURN_IF_ERROR(take(gm.occlusionTexture.index, gm.occlusionTexture.texCoord, gm.occlusionTexture.extensions, mp + "/occlusionTexture", true,
                                 false, maps.occlusion));
    CAUSTIX_RETURN_IF_ERROR(take(gm.emissiveTexture.index, gm.emissiveTexture.texCoord, gm.emissiveTexture.extensions, mp + "/emissiveTexture", false,
                                 false, maps.emissive));
    if (maps.any_map() || mat.maps) mat.maps = maps;
    return texcoord;
  }

  // Which of the model's materials maps to what (docs/scene-format.md).
  Result<std::pair<Role, Material>> material(int index, const std::string& pointer, std::vector<std::string>& warns) const {
    Material mat;
    if (index < 0) return std::pair{Role::kReceiver, mat};
    if (auto e = check_index(index, model.materials, "material", pointer)) return *e;
    const tinygltf::Material& gm = model.materials[static_cast<std::size_t>(index)];
    const std::string mp = "/materials/" + std::to_string(index);
    const std::string label = "material " + std::to_string(index) + (gm.name.empty() ? "" : " '" + gm.name + "'");
    const auto& pbr = gm.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4) return fail(mp + "/pbrMetallicRoughness/baseColorFactor", "expected 4 numbers");
    Vec3f base{};
    for (std::size_t k = 0; k < 3; ++k) {
      const double c = pbr.baseColorFactor[k];
      if (!(c >= 0 && c <= 1)) return fail(mp + "/pbrMetallicRoughness/baseColorFactor/" + std::to_string(k), "must be in [0, 1]");
      base[k] = static_cast<float>(c);
    }
    std::vector<std::string> ignored;
    for (const auto& [name, value] : gm.extensions) {
      if (!kSupported.count(name)) ignored.push_back(name);
    }
    const tinygltf::Value* transmission = extension(gm.extensions, "KHR_materials_transmission");
    double tf = 0;
    if (transmission) {
      if (const tinygltf::Value* v = field(*transmission, "transmissionFactor")) {
        if (!v->IsNumber() || !(v->GetNumberAsDouble() >= 0 && v->GetNumberAsDouble() <= 1)) {
          return fail(mp + "/extensions/KHR_materials_transmission/transmissionFactor", "must be a number in [0, 1]");
        }
        tf = v->GetNumberAsDouble();
      }
      if (field(*transmission, "transmissionTexture")) ignored.push_back("transmissionTexture");
    }
    // glTF 2.0 Appendix B and KHR_materials_transmission: transmission is a
    // part of the dielectric lobe, which metallic blends away (the metal
    // base = mix(dielectric, metal, metallic)). caustix's objects are one
    // or the other: the larger part wins, and the other is named.
    const double metallic = std::clamp(pbr.metallicFactor, 0.0, 1.0);
    if (tf > 0 && metallic >= 0.5) {
      warn(mp + ": " + label + " is metallic (" + std::to_string(metallic) + ") and transmissive: glTF blends the transmission away with metallic, so it is imported as a metal, without transmission", warns);
      tf = 0;
    } else if (tf > 0 && metallic > 0) {
      warn(mp + ": " + label + ": its metallic part (" + std::to_string(metallic) + ") is ignored; imported as glass", warns);
    }
    if (tf == 0) {
      // What only transmission reads, on a material that transmits nothing.
      for (const char* e : {"KHR_materials_ior", "KHR_materials_volume", "KHR_materials_dispersion"}) {
        if (extension(gm.extensions, e)) ignored.push_back(std::string(e) + " (the material transmits no light)");
      }
    }
    Role role = Role::kReceiver;
    if (tf > 0) {
      role = Role::kTransparent;
      if (pbr.roughnessFactor > 0.05) {
        warn(mp + ": " + label + ": roughnessFactor " + std::to_string(pbr.roughnessFactor) +
                 " on a transmissive material is ignored: caustix's glass refracts as a smooth surface, so its caustics are sharper than the author's",
             warns);
      }
      mat.transparent = true;
      if (tf < 1) warn(mp + ": " + label + " transmits " + std::to_string(tf) + " of the light; caustix's glass transmits all that Fresnel lets through", warns);
      // KHR_materials_transmission: the base colour tints the transmitted
      // light, at each crossing of the surface (the BTDF is base colour x
      // the specular transmission lobe).
      mat.tint = base;
      mat.ior = 1.5f;  // KHR_materials_ior's default
      if (const tinygltf::Value* ior = extension(gm.extensions, "KHR_materials_ior")) {
        if (const tinygltf::Value* v = field(*ior, "ior")) {
          const double x = v->IsNumber() ? v->GetNumberAsDouble() : -1;
          if (!(x >= 1 && x <= kMaxIor)) return fail(mp + "/extensions/KHR_materials_ior/ior", "must be a number in [1, " + std::to_string(kMaxIor) + "]");
          mat.ior = static_cast<float>(x);
        }
      }
      const tinygltf::Value* volume = extension(gm.extensions, "KHR_materials_volume");
      const tinygltf::Value* disp = extension(gm.extensions, "KHR_materials_dispersion");
      if (disp && volume) {
        // Same meaning as caustix's "dispersion": 20 / Abbe number, 0 none.
        if (const tinygltf::Value* v = field(*disp, "dispersion")) {
          const double x = v->IsNumber() ? v->GetNumberAsDouble() : -1;
          if (!(x >= 0 && x <= kMaxDispersion)) {
            return fail(mp + "/extensions/KHR_materials_dispersion/dispersion", "must be a number in [0, " + std::to_string(kMaxDispersion) + "]");
          }
          mat.dispersion = static_cast<float>(x);
        }
      }
      if (!volume) {
        // KHR_materials_transmission: without KHR_materials_volume the
        // surface is thin-walled (a pane, a shade): light crosses it where
        // it meets it, without bending (Role::kThin).
        role = Role::kThin;
        if (disp) ignored.push_back("KHR_materials_dispersion (a thin-walled material does not disperse; KHR_materials_volume makes it a solid)");
      } else {
        // Beer-Lambert (KHR_materials_volume): light keeps attenuationColor
        // after attenuationDistance, so sigma = -ln(c) / d per channel.
        const std::string vp = mp + "/extensions/KHR_materials_volume";
        double dist = std::numeric_limits<double>::infinity();
        V3 color{1, 1, 1};
        if (const tinygltf::Value* d = field(*volume, "attenuationDistance")) {
          if (!d->IsNumber() || !(d->GetNumberAsDouble() > 0)) return fail(vp + "/attenuationDistance", "must be a number > 0");
          dist = d->GetNumberAsDouble();
        }
        if (const tinygltf::Value* c = field(*volume, "attenuationColor")) {
          if (!c->IsArray() || c->ArrayLen() != 3) return fail(vp + "/attenuationColor", "expected 3 numbers");
          for (int k = 0; k < 3; ++k) {
            const tinygltf::Value& x = c->Get(k);
            if (!x.IsNumber() || !(x.GetNumberAsDouble() >= 0 && x.GetNumberAsDouble() <= 1)) {
              return fail(vp + "/attenuationColor/" + std::to_string(k), "must be a number in [0, 1]");
            }
            color[static_cast<std::size_t>(k)] = x.GetNumberAsDouble();
          }
        }
        for (std::size_t k = 0; k < 3; ++k) {
          const double sigma = std::isinf(dist) ? 0.0 : -std::log(std::max(color[k], 1e-30)) / dist;
          mat.absorption[k] = static_cast<float>(std::min(sigma, double{kMaxCoefficient}));
        }
        if (field(*volume, "thicknessTexture")) ignored.push_back("thicknessTexture");
      }
    } else if (pbr.metallicFactor >= 0.9 && pbr.roughnessFactor <= 0.2) {
      role = Role::kMirror;
      mat.reflectance = base;
    } else {
      mat.albedo = base;  // a baseColorTexture multiplies it (albedo_texture())
      // The metallic-roughness model's factors and the emission
      // (KHR_materials_emissive_strength scales it), for the renderers'
      // shading (formats/scene.h Surface).
      Surface& sf = mat.surface.emplace();
      sf.metallic = static_cast<float>(metallic);
      if (!(pbr.roughnessFactor >= 0 && pbr.roughnessFactor <= 1)) {
        return fail(mp + "/pbrMetallicRoughness/roughnessFactor", "must be in [0, 1]");
      }
      sf.roughness = static_cast<float>(pbr.roughnessFactor);
      double strength = 1;
      if (const tinygltf::Value* es = extension(gm.extensions, "KHR_materials_emissive_strength")) {
        if (const tinygltf::Value* v = field(*es, "emissiveStrength")) {
          if (!v->IsNumber() || !(v->GetNumberAsDouble() >= 0 && v->GetNumberAsDouble() <= 1e6)) {
            return fail(mp + "/extensions/KHR_materials_emissive_strength/emissiveStrength", "must be a number in [0, 1e6]");
          }
          strength = v->GetNumberAsDouble();
        }
      }
      if (gm.emissiveFactor.size() == 3) {
        for (std::size_t k = 0; k < 3; ++k) {
          const double e = gm.emissiveFactor[k];
          if (!(e >= 0 && e <= 1)) return fail(mp + "/emissiveFactor/" + std::to_string(k), "must be in [0, 1]");
          sf.emissive[k] = static_cast<float>(std::min(e * strength, 1e6));
        }
      }
      // glTF 2.0 §3.9.4 alpha; the factors of the normal and occlusion
      // textures (material_textures() reads the textures themselves).
      SurfaceMaps maps;
      if (gm.alphaMode == "MASK") maps.alpha_mode = AlphaMode::kMask;
      else if (gm.alphaMode == "BLEND") maps.alpha_mode = AlphaMode::kBlend;
      else if (!gm.alphaMode.empty() && gm.alphaMode != "OPAQUE") return fail(mp + "/alphaMode", "must be OPAQUE, MASK or BLEND");
      const double a = pbr.baseColorFactor[3], cutoff = gm.alphaCutoff;
      if (!(a >= 0 && a <= 1)) return fail(mp + "/pbrMetallicRoughness/baseColorFactor/3", "must be in [0, 1]");
      if (!(cutoff >= 0 && cutoff <= 1)) return fail(mp + "/alphaCutoff", "must be in [0, 1]");
      const double scale = gm.normalTexture.scale, occlusion = gm.occlusionTexture.strength;
      if (!(std::fabs(scale) <= 1000)) return fail(mp + "/normalTexture/scale", "must be a number in [-1000, 1000]");
      if (!(occlusion >= 0 && occlusion <= 1)) return fail(mp + "/occlusionTexture/strength", "must be in [0, 1]");
      maps.alpha = static_cast<float>(a);
      maps.alpha_cutoff = static_cast<float>(cutoff);
      maps.normal_scale = static_cast<float>(scale);
      maps.occlusion_strength = static_cast<float>(occlusion);
      if (maps.alpha_mode != AlphaMode::kOpaque) mat.maps = maps;
      else if (gm.normalTexture.index >= 0 || gm.occlusionTexture.index >= 0) mat.maps = maps;  // the textures follow
    }
    if (role != Role::kReceiver) {
      const char* why = role == Role::kMirror ? "a mirror's reflectance is its base colour factor" : "glass is not textured";
      for (const auto& [used, name] : {std::pair{pbr.baseColorTexture.index >= 0, "baseColorTexture"},
                                       std::pair{pbr.metallicRoughnessTexture.index >= 0, "metallicRoughnessTexture"},
                                       std::pair{gm.normalTexture.index >= 0, "normalTexture"},
                                       std::pair{gm.occlusionTexture.index >= 0, "occlusionTexture"},
                                       std::pair{gm.emissiveTexture.index >= 0, "emissiveTexture"}}) {
        if (used) ignored.push_back(std::string(name) + " (" + why + ")");
      }
      if (!gm.alphaMode.empty() && gm.alphaMode != "OPAQUE") ignored.push_back("alphaMode " + gm.alphaMode + " (" + why + ")");
    }
    if (!ignored.empty()) {
      std::string list;
      for (const auto& s : ignored) list += (list.empty() ? "" : ", ") + s;
      warn(mp + ": " + label + ": ignored " + list, warns);
    }
    return std::pair{role, mat};
  }
};

bool is_gltf_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".gltf" || ext == ".glb";
}

GltfFile::GltfFile(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GltfFile::GltfFile(GltfFile&&) noexcept = default;
GltfFile& GltfFile::operator=(GltfFile&&) noexcept = default;
GltfFile::~GltfFile() = default;
const std::string& GltfFile::path() const { return impl_->path; }
const std::vector<std::string>& GltfFile::inputs() const { return impl_->inputs; }
const std::vector<std::string>& GltfFile::warnings() const { return impl_->warnings; }

Result<GltfFile> GltfFile::load(const std::string& path) {
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return make_error(ErrorCode::kInput, path + ": " + (std::filesystem::exists(path, ec) ? "not a regular file" : "glTF file not found"));
  }

  auto bytes = read_file(path, kMaxFileBytes);
  if (!bytes) return bytes.error();
  without_draco_indices(*bytes);

  tinygltf::TinyGLTF loader;
  // Images stay encoded (TINYGLTF_NO_STB_IMAGE): a data URI's bytes are
  // kept in Image::image for the baker's OpenImageIO reader
  // (bake/texture_import.h); external files keep their uri, buffer views
  // their view, read later through the checked view_bytes. (tinygltf hands
  // a buffer view's image over by its byteLength without checking it
  // against the buffer: copying those bytes here read past a buffer whose
  // view claimed more than it held.)
  loader.SetImageLoader(
      [](tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes, int size, void*) {
        if (image->bufferView < 0) image->image.assign(bytes, bytes + size);
        return true;
      },
      nullptr);
  std::string err, warn;
  const std::string base = std::filesystem::path(path).parent_path().string();
  const auto length = static_cast<unsigned int>(bytes->size());
  // A GLB by its magic (whatever the extension), else JSON.
  const bool ok = bytes->size() >= 4 && std::memcmp(bytes->data(), "glTF", 4) == 0
                      ? loader.LoadBinaryFromMemory(&impl->model, &err, &warn, bytes->data(), length, base)
                      : loader.LoadASCIIFromString(&impl->model, &err, &warn, reinterpret_cast<const char*>(bytes->data()), length, base);
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    for (char& c : err) c = c == '\n' ? ';' : c;
    return make_error(ErrorCode::kInput, path + ": not a valid glTF 2.0 file (tinygltf: " + (err.empty() ? "no reason given" : err) + ")");
  }
  std::size_t start = 0;
  while (start < warn.size()) {
    const std::size_t end = std::min(warn.find('\n', start), warn.size());
    if (end > start) impl->warn("tinygltf: " + warn.substr(start, end - start), impl->warnings);
    start = end + 1;
  }
  impl->inputs.push_back(path);
  for (const tinygltf::Buffer& b : impl->model.buffers) {
    if (!b.uri.empty() && b.uri.rfind("data:", 0) != 0) impl->inputs.push_back((std::filesystem::path(base) / b.uri).lexically_normal().string());
  }
  const tinygltf::Model& m = impl->model;
  for (std::size_t i = 0; i < m.extensionsRequired.size(); ++i) {
    if (!kSupported.count(m.extensionsRequired[i]) && !kIgnorable.count(m.extensionsRequired[i])) {
      return impl->fail("/extensionsRequired/" + std::to_string(i),
                        "the file requires extension " + m.extensionsRequired[i] + ", which caustix does not support");
    }
  }
  for (const std::string& e : m.extensionsUsed) {
    const bool required = std::find(m.extensionsRequired.begin(), m.extensionsRequired.end(), e) != m.extensionsRequired.end();
    if (!kSupported.count(e)) {
      impl->warn("extension " + e + (required ? " (required by the file)" : "") +
                     " is not supported; what it adds is ignored" +
                     (required ? ", which cannot change the light: caustix reads nothing it changes" : ""),
                 impl->warnings);
    }
  }
  if (!m.animations.empty()) impl->warn(std::to_string(m.animations.size()) + " animation(s) ignored: the bake takes the rest pose", impl->warnings);
  if (!m.skins.empty()) impl->warn(std::to_string(m.skins.size()) + " skin(s) ignored: skinned meshes are baked in their bind pose", impl->warnings);
  return GltfFile(std::move(impl));
}

Result<ImportedMesh> GltfFile::node_mesh(const std::string& node, bool weld) const {
  const Impl& im = *impl_;
  const auto& nodes = im.model.nodes;
  const auto it = std::find_if(nodes.begin(), nodes.end(), [&](const tinygltf::Node& n) { return n.name == node; });
  if (it == nodes.end()) {
    std::string names;
    for (std::size_t i = 0; i < nodes.size() && i < 20; ++i) names += (i ? ", " : "") + im.node_name(i);
    return make_error(ErrorCode::kInput, im.path + ": no node named '" + node + "' (nodes: " + (names.empty() ? "none" : names) +
                                             (nodes.size() > 20 ? ", ..." : "") + ")");
  }
  const auto i = static_cast<std::size_t>(it - nodes.begin());
  const std::string np = "/nodes/" + std::to_string(i);
  if (it->mesh < 0) return im.fail(np, "node '" + node + "' has no mesh");
  if (auto e = im.check_index(it->mesh, im.model.meshes, "mesh", np + "/mesh")) return *e;
  const auto m = static_cast<std::size_t>(it->mesh);
  std::vector<Impl::Corners> parts;
  std::vector<std::string> warns;
  for (std::size_t k = 0; k < im.model.meshes[m].primitives.size(); ++k) {
    auto c = im.primitive_corners(m, k, warns);
    if (!c) return c.error();
    parts.push_back(std::move(*c));
  }
  auto mesh = im.make_mesh(std::move(parts), weld, "/meshes/" + std::to_string(m));
  if (!mesh) return mesh.error();
  for (auto& w : warns) mesh->warnings.push_back(std::move(w));
  return mesh;
}

Result<GltfScene> GltfFile::scene() const {
  const Impl& im = *impl_;
  const tinygltf::Model& model = im.model;
  GltfScene out;
  const std::string file = std::filesystem::path(im.path).filename().string();

  // Root nodes: the default scene's, else the first scene's, else every node
  // that is no other node's child.
  std::vector<int> roots;
  std::string roots_ptr;
  if (!model.scenes.empty()) {
    std::size_t s = 0;
    if (model.defaultScene >= 0) {
      if (auto e = im.check_index(model.defaultScene, model.scenes, "scene", "/scene")) return *e;
      s = static_cast<std::size_t>(model.defaultScene);
    }
    if (model.scenes.size() > 1) {
      im.warn("the file has " + std::to_string(model.scenes.size()) + " scenes; imported /scenes/" + std::to_string(s) +
                  (model.scenes[s].name.empty() ? "" : " ('" + model.scenes[s].name + "')") +
                  (model.defaultScene >= 0 ? " (the default scene)" : " (the first: the file names no default)") + ", the others are ignored",
              out.warnings);
    }
    roots = model.scenes[s].nodes;
    roots_ptr = "/scenes/" + std::to_string(s) + "/nodes";
    out.scene.name = model.scenes[s].name;
  } else {
    std::vector<bool> child(model.nodes.size(), false);
    for (const auto& n : model.nodes) {
      for (int c : n.children) {
        if (c >= 0 && static_cast<std::size_t>(c) < child.size()) child[static_cast<std::size_t>(c)] = true;
      }
    }
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
      if (!child[i]) roots.push_back(static_cast<int>(i));
    }
    roots_ptr = "/nodes";
  }

  // Depth-first, in document order, each node reached once (glTF 2.0 §3.5.4:
  // the nodes form disjoint trees).
  std::vector<bool> seen(model.nodes.size(), false);
  struct Visit { std::size_t node; Mat4d world; };
  std::vector<Visit> order;
  std::vector<std::tuple<int, std::string, Mat4d>> stack;
  for (std::size_t r = roots.size(); r-- > 0;) stack.emplace_back(roots[r], roots_ptr + "/" + std::to_string(r), kIdentity);
  while (!stack.empty()) {
    auto [n, ptr, parent] = stack.back();
    stack.pop_back();
    if (auto e = im.check_index(n, model.nodes, "node", ptr)) return *e;
    const auto i = static_cast<std::size_t>(n);
    if (seen[i]) return im.fail(ptr, "node " + std::to_string(i) + " is reached twice: a node may have one parent and no cycle");
    seen[i] = true;
    auto local = im.local_matrix(i);
    if (!local) return local.error();
    const Mat4d world = mul(parent, *local);
    order.push_back({i, world});
    const auto& ch = model.nodes[i].children;
    for (std::size_t c = ch.size(); c-- > 0;) stack.emplace_back(ch[c], "/nodes/" + std::to_string(i) + "/children/" + std::to_string(c), world);
  }

  // Where each imported object and light came from, for messages.
  struct Origins {
    std::vector<std::string> objects, lights;
    // "/objects/3/transform" -> "/nodes/7 ('Lens')/transform"
    std::string locate(const std::string& pointer) const {
      for (const auto& [prefix, list] : {std::pair{std::string("/objects/"), &objects}, std::pair{std::string("/lights/"), &lights}}) {
        if (pointer.rfind(prefix, 0) != 0) continue;
        const std::size_t end = pointer.find('/', prefix.size());
        const std::string digits = pointer.substr(prefix.size(), end - prefix.size());
        const std::size_t k = digits.empty() ? list->size() : std::stoul(digits);
        if (k < list->size()) return (*list)[k] + (end == std::string::npos ? "" : pointer.substr(end));
      }
      return "the imported scene's " + pointer;
    }
  } where;
  std::map<std::tuple<std::size_t, std::size_t, bool, int, bool>, std::uint32_t> mesh_of;  // (mesh, primitive, weld, texcoord, colours) -> index
  std::map<int, std::pair<Role, Material>> materials;
  std::map<int, int> texcoord_of;  // textured material -> its TEXCOORD set
  std::map<std::pair<int, bool>, std::uint32_t> image_of;
  std::set<std::string> names;
  bool camera_taken = false;
  for (const Visit& v : order) {
    const tinygltf::Node& n = model.nodes[v.node];
    const std::string np = "/nodes/" + std::to_string(v.node);
    if (n.skin >= 0) im.warn(np + ": skin ignored", out.warnings);
    if (n.mesh >= 0) {
      if (auto e = im.check_index(n.mesh, model.meshes, "mesh", np + "/mesh")) return *e;
      const auto m = static_cast<std::size_t>(n.mesh);
      const auto& prims = model.meshes[m].primitives;
      for (std::size_t k = 0; k < prims.size(); ++k) {
        const std::string pp = "/meshes/" + std::to_string(m) + "/primitives/" + std::to_string(k);
        // Each material read (and warned about) once, however many nodes use it.
        auto cached = materials.find(prims[k].material);
        if (cached == materials.end()) {
          auto read = im.material(prims[k].material, pp + "/material", out.warnings);
          if (!read) return read.error();
          if (read->first == Role::kReceiver && prims[k].material >= 0) {
            auto set = im.material_textures(prims[k].material, read->second, out.images, image_of, out.warnings);
            if (!set) return set.error();
            if (*set >= 0) texcoord_of[prims[k].material] = *set;
          }
          cached = materials.emplace(prims[k].material, *read).first;
        }
        const auto* mat = &cached->second;
        // The texture's coordinate set, when this primitive has it.
        int texcoord = -1;
        if (const auto tc = texcoord_of.find(prims[k].material); tc != texcoord_of.end()) {
          texcoord = tc->second;
          if (!prims[k].attributes.count("TEXCOORD_" + std::to_string(texcoord))) {
            im.warn(pp + ": no TEXCOORD_" + std::to_string(texcoord) + " for its material's textures; drawn with its factors alone", out.warnings);
            texcoord = -1;
          }
        }
        // A solid's mesh is welded for its topology; a transmissive surface
        // that bounds no solid is baked thin-walled (caustix-bake, naming it).
        const bool weld = is_transparent(mat->first);
        // A receiver's vertex colours (glTF 2.0 §3.9.2: COLOR_0 multiplies
        // the base colour).
        const bool colors = mat->first == Role::kReceiver && prims[k].attributes.count("COLOR_0");
        const auto key = std::tuple{m, k, weld, texcoord, colors};
        auto found = mesh_of.find(key);
        if (found == mesh_of.end()) {
          std::vector<std::string> warns;
          auto c = im.primitive_corners(m, k, warns, texcoord, colors);
          if (!c) return c.error();
          for (auto& w : warns) out.warnings.push_back(std::move(w));
          if (c->triangles.empty()) continue;  // points or lines: warned
          auto mesh = im.make_mesh({std::move(*c)}, weld, pp);
          if (!mesh) return mesh.error();
          for (const auto& w : mesh->warnings) out.warnings.push_back(im.path + ": " + pp + ": " + w);
          mesh->warnings.clear();
          MeshInfo info;
          info.source = file + "#" + pp;
          found = mesh_of.emplace(key, static_cast<std::uint32_t>(out.meshes.size())).first;
          out.scene.meshes.push_back(info);
          out.meshes.push_back(std::move(*mesh));
        }
        Object o;
        o.name = im.node_name(v.node) + (prims.size() > 1 ? "/" + std::to_string(k) : "");
        if (names.count(o.name)) {
          std::string unique;
          for (int s = 2; names.count(unique = o.name + "~" + std::to_string(s)); ++s) {}
          im.warn(np + ": object name '" + o.name + "' is taken; named '" + unique + "'", out.warnings);
          o.name = unique;
        }
        names.insert(o.name);
        o.mesh_index = found->second;
        o.role = mat->first;
        o.material = mat->second;
        if (texcoord < 0) for_each_texture_slot(o.material, [](std::optional<MapTexture>& t) { t.reset(); });
        for (std::size_t c = 0; c < 16; ++c) o.transform[c] = static_cast<float>(v.world[c]);
        out.scene.objects.push_back(o);
        where.objects.push_back(np + " ('" + im.node_name(v.node) + "')");
      }
    }
    if (const tinygltf::Value* lp = extension(n.extensions, "KHR_lights_punctual")) {
      const tinygltf::Value* li = field(*lp, "light");
      const std::string lptr = np + "/extensions/KHR_lights_punctual/light";
      if (!li || !li->IsInt()) return im.fail(lptr, "expected a light index");
      if (auto e = im.check_index(li->GetNumberAsInt(), model.lights, "light", lptr)) return *e;
      const tinygltf::Light& gl = model.lights[static_cast<std::size_t>(li->GetNumberAsInt())];
      const std::string gp = "/extensions/KHR_lights_punctual/lights/" + std::to_string(li->GetNumberAsInt());
      Light l;
      l.name = gl.name.empty() ? im.node_name(v.node) : gl.name;
      if (!gl.color.empty()) {
        if (gl.color.size() != 3) return im.fail(gp + "/color", "expected 3 numbers");
        for (std::size_t k = 0; k < 3; ++k) {
          if (!(gl.color[k] >= 0 && gl.color[k] <= 1e6)) return im.fail(gp + "/color/" + std::to_string(k), "must be a number >= 0");
          l.color[k] = static_cast<float>(gl.color[k]);
        }
      }
      if (!(gl.intensity >= 0 && gl.intensity < 1e30)) return im.fail(gp + "/intensity", "must be a number >= 0");
      if (gl.range > 0) im.warn(gp + ": range ignored (caustix's point lights fall off as 1/r^2 without a cut-off)", out.warnings);
      if (gl.type == "directional") {
        l.type = LightType::kDirectional;
        l.direction = to_f(normalized(apply_dir(v.world, {0, 0, -1})));
        l.irradiance = static_cast<float>(gl.intensity / kLumensPerWatt);
      } else if (gl.type == "point" || gl.type == "spot") {
        l.type = LightType::kPoint;
        l.position = to_f({v.world[12], v.world[13], v.world[14]});
        l.intensity = static_cast<float>(gl.intensity / kLumensPerWatt);
        if (gl.type == "spot") {
          // KHR_lights_punctual: the cone about the node's -z.
          const double inner = gl.spot.innerConeAngle, outer = gl.spot.outerConeAngle;
          if (!(outer > 0 && outer <= kPi / 2)) return im.fail(gp + "/spot/outerConeAngle", "must be in (0, pi/2]");
          if (!(inner >= 0 && inner < outer)) return im.fail(gp + "/spot/innerConeAngle", "must be in [0, outerConeAngle)");
          l.spot = true;
          l.direction = to_f(normalized(apply_dir(v.world, {0, 0, -1})));
          l.inner_cone = static_cast<float>(inner);
          l.outer_cone = static_cast<float>(outer);
        }
      } else {
        return im.fail(gp + "/type", "unknown light type '" + gl.type + "'");
      }
      out.scene.lights.push_back(l);
      where.lights.push_back(gp + " (node '" + im.node_name(v.node) + "')");
    }
    if (n.camera >= 0) {
      if (auto e = im.check_index(n.camera, model.cameras, "camera", np + "/camera")) return *e;
      const tinygltf::Camera& gc = model.cameras[static_cast<std::size_t>(n.camera)];
      const std::string cp = "/cameras/" + std::to_string(n.camera);
      if (camera_taken) {
        im.warn(np + ": camera ignored (the first camera is used)", out.warnings);
      } else if (gc.type != "perspective") {
        im.warn(cp + ": " + gc.type + " camera ignored (caustix's cameras are perspective)", out.warnings);
      } else {
        const auto& p = gc.perspective;
        if (!(p.yfov > 0 && p.yfov < kPi)) return im.fail(cp + "/perspective/yfov", "must be in (0, pi)");
        if (!(p.znear > 0)) return im.fail(cp + "/perspective/znear", "must be > 0");
        if (p.zfar != 0 && !(p.zfar > p.znear)) return im.fail(cp + "/perspective/zfar", "must be greater than znear");
        Camera cam;
        const V3 pos{v.world[12], v.world[13], v.world[14]};
        const V3 fwd = normalized(apply_dir(v.world, {0, 0, -1}));
        cam.position = to_f(pos);
        cam.target = to_f({pos[0] + fwd[0], pos[1] + fwd[1], pos[2] + fwd[2]});
        cam.up = to_f(normalized(apply_dir(v.world, {0, 1, 0})));
        cam.fov_y_deg = static_cast<float>(p.yfov * 180.0 / kPi);
        cam.near_plane = static_cast<float>(p.znear);
        // An infinite projection (no zfar) gets a far plane 10^4 near planes out.
        cam.far_plane = static_cast<float>(p.zfar > 0 ? p.zfar : std::max(100.0, 1e4 * p.znear));
        out.scene.camera = cam;
        camera_taken = true;
      }
    }
  }
  if (out.scene.objects.empty()) return im.fail(roots_ptr, "the scene has no triangle meshes");
  // scene.json's value rules, said of the glTF node they break.
  if (auto issue = validate_scene(out.scene, /*check_meshes=*/false)) return im.fail(where.locate(issue->pointer), issue->message);
  return out;
}

}  // namespace caustix::bake
