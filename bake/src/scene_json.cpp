// scene.json front end. The schema is documented in docs/scene-format.md;
// value ranges live in formats' validate_scene(), shared with the .cxb reader.

#include "caustix/bake/scene_json.h"

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <map>

#include "caustix/bake/gltf_import.h"
#include "caustix/formats/file_io.h"
#include "json_locations.h"

namespace caustix::bake {
namespace {

using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

// Walks the DOM with the current JSON pointer, turning every problem into a
// located error. Getters return false after recording the first error.
class Walker {
 public:
  Walker(const LocatedJson& doc, std::string file) : doc_(doc), file_(std::move(file)) {}

  std::string where(const std::string& pointer) const {
    // The pointer itself, or its nearest ancestor that has a position.
    std::string p = pointer;
    while (true) {
      const auto it = doc_.positions.find(p);
      if (it != doc_.positions.end()) {
        return file_ + ":" + std::to_string(it->second.line) + ":" + std::to_string(it->second.column);
      }
      if (p.empty()) return file_ + ":1:1";
      p = p.substr(0, p.rfind('/'));
    }
  }
  bool fail(const std::string& pointer, const std::string& msg) {
    if (!error_) error_ = make_error(ErrorCode::kInput, where(pointer) + ": " + (pointer.empty() ? "/" : pointer) + ": " + msg);
    return false;
  }
  void warn(const std::string& pointer, const std::string& msg) {
    warnings_.push_back(where(pointer) + ": " + pointer + ": " + msg);
  }
  const std::optional<Error>& error() const { return error_; }
  std::vector<std::string>& warnings() { return warnings_; }

  // Warns about members not in `known`.
  void check_fields(const json& obj, const std::string& ptr, std::initializer_list<const char*> known) {
    for (const auto& [k, v] : obj.items()) {
      bool found = false;
      for (const char* name : known) found = found || k == name;
      if (!found) warn(ptr + "/" + pointer_token(k), "unknown field \"" + k + "\" (ignored)");
    }
  }

  bool object(const json& v, const std::string& ptr) {
    return v.is_object() || fail(ptr, "expected an object, got " + type_of(v));
  }
  // A member that must exist.
  const json* member(const json& obj, const std::string& ptr, const char* key) {
    const auto it = obj.find(key);
    if (it == obj.end()) {
      fail(ptr, std::string("missing required field \"") + key + "\"");
      return nullptr;
    }
    return &*it;
  }
  static const json* optional_member(const json& obj, const char* key) {
    const auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }

  bool number(const json& v, const std::string& ptr, float& out) {
    if (!v.is_number()) return fail(ptr, "expected a number, got " + type_of(v));
    const double d = v.get<double>();
    if (!std::isfinite(d) || std::fabs(d) > 3.0e38) return fail(ptr, "number out of range");
    out = static_cast<float>(d);
    return true;
  }
  bool integer(const json& v, const std::string& ptr, std::uint32_t& out) {
    if (!v.is_number_integer()) return fail(ptr, "expected a whole number, got " + type_of(v));
    if (v.is_number_unsigned() ? v.get<std::uint64_t>() > UINT32_MAX : v.get<std::int64_t>() < 0) {
      return fail(ptr, "expected a whole number in [0, 4294967295]");
    }
    out = static_cast<std::uint32_t>(v.get<std::uint64_t>());
    return true;
  }
  bool string(const json& v, const std::string& ptr, std::string& out) {
    if (!v.is_string()) return fail(ptr, "expected a string, got " + type_of(v));
    out = v.get<std::string>();
    return true;
  }
  bool boolean(const json& v, const std::string& ptr, bool& out) {
    if (!v.is_boolean()) return fail(ptr, "expected true or false, got " + type_of(v));
    out = v.get<bool>();
    return true;
  }
  template <std::size_t N>
  bool numbers(const json& v, const std::string& ptr, std::array<float, N>& out) {
    if (!v.is_array() || v.size() != N) {
      return fail(ptr, "expected an array of " + std::to_string(N) + " numbers, got " + type_of(v));
    }
    for (std::size_t i = 0; i < N; ++i) {
      if (!number(v[i], ptr + "/" + std::to_string(i), out[i])) return false;
    }
    return true;
  }
  // A number applied to every component, or an array of 3.
  bool scalar_or_vec3(const json& v, const std::string& ptr, Vec3f& out) {
    if (v.is_number()) {
      float f = 0;
      if (!number(v, ptr, f)) return false;
      out = {f, f, f};
      return true;
    }
    return numbers(v, ptr, out);
  }

  static std::string type_of(const json& v) {
    if (v.is_array()) return "an array of " + std::to_string(v.size());
    return std::string(v.type_name());
  }

 private:
  const LocatedJson& doc_;
  std::string file_;
  std::optional<Error> error_;
  std::vector<std::string> warnings_;
};

// Column-major 4x4 product.
Mat4f mul(const Mat4f& a, const Mat4f& b) {
  Mat4f r{};
  for (int c = 0; c < 4; ++c) {
    for (int rr = 0; rr < 4; ++rr) {
      float s = 0;
      for (int k = 0; k < 4; ++k) s += a[static_cast<std::size_t>(k * 4 + rr)] * b[static_cast<std::size_t>(c * 4 + k)];
      r[static_cast<std::size_t>(c * 4 + rr)] = s;
    }
  }
  return r;
}

Mat4f rotation(int axis, double deg) {
  const double r = deg * kPi / 180.0;
  const auto c = static_cast<float>(std::cos(r)), s = static_cast<float>(std::sin(r));
  Mat4f m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // rotate a toward b
  m[static_cast<std::size_t>(a * 4 + a)] = c;
  m[static_cast<std::size_t>(a * 4 + b)] = s;
  m[static_cast<std::size_t>(b * 4 + a)] = -s;
  m[static_cast<std::size_t>(b * 4 + b)] = c;
  return m;
}

bool parse_transform(Walker& w, const json& v, const std::string& ptr, Mat4f& out) {
  if (!w.object(v, ptr)) return false;
  w.check_fields(v, ptr, {"matrix", "translate", "rotate_deg", "scale"});
  if (const json* m = Walker::optional_member(v, "matrix")) {
    if (v.size() != 1) return w.fail(ptr, "\"matrix\" cannot be combined with translate/rotate_deg/scale");
    std::array<float, 16> rows{};
    if (!w.numbers(*m, ptr + "/matrix", rows)) return false;
    // Written row-major (as read); stored column-major.
    for (std::size_t r = 0; r < 4; ++r) {
      for (std::size_t c = 0; c < 4; ++c) out[c * 4 + r] = rows[r * 4 + c];
    }
    return true;
  }
  Vec3f t{0, 0, 0}, rot{0, 0, 0}, s{1, 1, 1};
  if (const json* j = Walker::optional_member(v, "translate"); j && !w.numbers(*j, ptr + "/translate", t)) return false;
  if (const json* j = Walker::optional_member(v, "rotate_deg"); j && !w.numbers(*j, ptr + "/rotate_deg", rot)) return false;
  if (const json* j = Walker::optional_member(v, "scale"); j && !w.scalar_or_vec3(*j, ptr + "/scale", s)) return false;
  // M = T * Rz * Ry * Rx * S: scale first, then rotate about x, y, z.
  Mat4f m{s[0], 0, 0, 0, 0, s[1], 0, 0, 0, 0, s[2], 0, 0, 0, 0, 1};
  m = mul(rotation(0, rot[0]), m);
  m = mul(rotation(1, rot[1]), m);
  m = mul(rotation(2, rot[2]), m);
  m[12] = t[0];
  m[13] = t[1];
  m[14] = t[2];
  out = m;
  return true;
}

// "scattering", "phase" and "anisotropy" of a material, the water or the
// medium (Pfeuti's phase functions; docs/scene-format.md).
bool parse_scattering(Walker& w, const json& v, const std::string& ptr, Scattering& out) {
  if (const json* j = Walker::optional_member(v, "scattering"); j && !w.scalar_or_vec3(*j, ptr + "/scattering", out.coefficient)) {
    return false;
  }
  if (const json* j = Walker::optional_member(v, "phase")) {
    std::string phase;
    if (!w.string(*j, ptr + "/phase", phase)) return false;
    if (phase == "isotropic") out.phase = Phase::kIsotropic;
    else if (phase == "schlick") out.phase = Phase::kSchlick;
    else return w.fail(ptr + "/phase", "expected \"isotropic\" or \"schlick\", got \"" + phase + "\"");
  }
  if (const json* j = Walker::optional_member(v, "anisotropy"); j && !w.number(*j, ptr + "/anisotropy", out.anisotropy)) {
    return false;
  }
  if (!out.scatters() && (v.contains("phase") || v.contains("anisotropy"))) {
    w.warn(ptr, "\"phase\" and \"anisotropy\" have no effect without \"scattering\"");
  }
  return true;
}

// "albedo_texture": a file name (mapped by the mesh's texture coordinates),
// or {"file", "projection": "uv" | "box", "scale": s or [su, sv], "offset":
// [ou, ov], "rotation_deg", "wrap": "repeat" | "clamp" | "mirror"}; the
// transform is KHR_texture_transform's T * R * S (rotation counter-clockwise
// in UV space, as the Khronos sample viewer applies it).
bool parse_albedo_texture(Walker& w, const json& v, const std::string& ptr, AlbedoTexture& out, std::string& file) {
  if (v.is_string()) return w.string(v, ptr, file);
  if (!w.object(v, ptr)) return false;
  w.check_fields(v, ptr, {"file", "projection", "scale", "offset", "rotation_deg", "wrap"});
  const json* f = w.member(v, ptr, "file");
  if (!f || !w.string(*f, ptr + "/file", file)) return false;
  if (file.empty()) return w.fail(ptr + "/file", "the file name is empty");
  if (const json* j = Walker::optional_member(v, "projection")) {
    std::string p;
    if (!w.string(*j, ptr + "/projection", p)) return false;
    if (p == "uv") out.projection = TextureProjection::kUv;
    else if (p == "box") out.projection = TextureProjection::kBox;
    else return w.fail(ptr + "/projection", "expected \"uv\" or \"box\", got \"" + p + "\"");
  }
  if (const json* j = Walker::optional_member(v, "wrap")) {
    std::string m;
    if (!w.string(*j, ptr + "/wrap", m)) return false;
    if (m == "repeat") out.wrap_s = TextureWrap::kRepeat;
    else if (m == "clamp") out.wrap_s = TextureWrap::kClamp;
    else if (m == "mirror") out.wrap_s = TextureWrap::kMirror;
    else return w.fail(ptr + "/wrap", "expected \"repeat\", \"clamp\" or \"mirror\", got \"" + m + "\"");
    out.wrap_t = out.wrap_s;
  }
  std::array<float, 2> scale{1, 1}, offset{0, 0};
  float rotation = 0;
  if (const json* j = Walker::optional_member(v, "scale")) {
    if (j->is_number()) {
      if (!w.number(*j, ptr + "/scale", scale[0])) return false;
      scale[1] = scale[0];
    } else if (!w.numbers(*j, ptr + "/scale", scale)) {
      return false;
    }
  }
  if (const json* j = Walker::optional_member(v, "offset"); j && !w.numbers(*j, ptr + "/offset", offset)) return false;
  if (const json* j = Walker::optional_member(v, "rotation_deg"); j && !w.number(*j, ptr + "/rotation_deg", rotation)) return false;
  out.transform = texture_transform(offset, static_cast<float>(rotation * kPi / 180.0), scale);
  return true;
}

// A material's texture slots in scene.json (formats/scene.h Material and
// SurfaceMaps): the key, whether its image holds data rather than colour,
// and the slot.
struct TextureKey {
  const char* key;
  bool data;
  std::optional<MapTexture>& (*slot)(Material&);
};
const TextureKey kTextureKeys[] = {
    {"albedo_texture", false, [](Material& m) -> std::optional<MapTexture>& { return m.albedo_texture; }},
    {"metallic_roughness_texture", true, [](Material& m) -> std::optional<MapTexture>& { return m.maps.value().metallic_roughness; }},
    {"normal_texture", true, [](Material& m) -> std::optional<MapTexture>& { return m.maps.value().normal; }},
    {"occlusion_texture", true, [](Material& m) -> std::optional<MapTexture>& { return m.maps.value().occlusion; }},
    {"emissive_texture", false, [](Material& m) -> std::optional<MapTexture>& { return m.maps.value().emissive; }},
};
// A texture file a material names, in kTextureKeys' order.
struct NamedTexture {
  const TextureKey* key;
  std::string file;
};

bool parse_material(Walker& w, const json& v, const std::string& ptr, Material& out, std::vector<NamedTexture>& textures, bool& thin) {
  if (!w.object(v, ptr)) return false;
  w.check_fields(v, ptr, {"albedo", "albedo_texture", "transparent", "thin", "ior", "dispersion", "absorption", "tint", "scattering", "phase", "anisotropy", "reflectance",
                          "metallic", "roughness", "emissive", "metallic_roughness_texture", "normal_texture", "occlusion_texture", "emissive_texture",
                          "normal_scale", "occlusion_strength", "alpha_mode", "alpha", "alpha_cutoff"});
  // Maps and alpha (formats/scene.h SurfaceMaps): any of their keys gives
  // the material maps, the others at their defaults.
  for (const char* key : {"metallic_roughness_texture", "normal_texture", "occlusion_texture", "emissive_texture", "normal_scale",
                          "occlusion_strength", "alpha_mode", "alpha", "alpha_cutoff"}) {
    if (v.contains(key) && !out.maps) out.maps.emplace();
  }
  for (const TextureKey& k : kTextureKeys) {
    const json* j = Walker::optional_member(v, k.key);
    if (!j) continue;
    NamedTexture& t = textures.emplace_back(NamedTexture{&k, {}});
    if (!parse_albedo_texture(w, *j, ptr + "/" + k.key, k.slot(out).emplace(), t.file)) return false;
  }
  if (out.albedo_texture) out.albedo = {1, 1, 1};  // the texture alone, unless "albedo" tints it
  if (out.maps) {
    SurfaceMaps& m = *out.maps;
    if (const json* j = Walker::optional_member(v, "alpha_mode")) {
      std::string mode;
      if (!w.string(*j, ptr + "/alpha_mode", mode)) return false;
      if (mode == "opaque") m.alpha_mode = AlphaMode::kOpaque;
      else if (mode == "mask") m.alpha_mode = AlphaMode::kMask;
      else if (mode == "blend") m.alpha_mode = AlphaMode::kBlend;
      else return w.fail(ptr + "/alpha_mode", "expected \"opaque\", \"mask\" or \"blend\", got \"" + mode + "\"");
    }
    for (const auto& [key, value] : {std::pair{"alpha", &m.alpha}, std::pair{"alpha_cutoff", &m.alpha_cutoff}, std::pair{"normal_scale", &m.normal_scale},
                                     std::pair{"occlusion_strength", &m.occlusion_strength}}) {
      if (const json* j = Walker::optional_member(v, key); j && !w.number(*j, ptr + "/" + key, *value)) return false;
    }
  }
  if (const json* j = Walker::optional_member(v, "albedo"); j && !w.scalar_or_vec3(*j, ptr + "/albedo", out.albedo)) return false;
  if (const json* j = Walker::optional_member(v, "transparent"); j && !w.boolean(*j, ptr + "/transparent", out.transparent)) return false;
  if (const json* j = Walker::optional_member(v, "thin")) {
    if (!w.boolean(*j, ptr + "/thin", thin)) return false;
    if (thin && !out.transparent) {
      w.warn(ptr + "/thin", "\"thin\" has no effect on an opaque material");
      thin = false;
    }
  }
  if (const json* j = Walker::optional_member(v, "ior")) {
    if (!w.number(*j, ptr + "/ior", out.ior)) return false;
    if (!out.transparent) w.warn(ptr + "/ior", "\"ior\" has no effect on an opaque material");
  }
  if (const json* j = Walker::optional_member(v, "dispersion")) {
    if (!w.number(*j, ptr + "/dispersion", out.dispersion)) return false;
    if (!out.transparent) w.warn(ptr + "/dispersion", "\"dispersion\" has no effect on an opaque material");
  }
  if (const json* j = Walker::optional_member(v, "absorption")) {
    if (!w.scalar_or_vec3(*j, ptr + "/absorption", out.absorption)) return false;
    if (!out.transparent) w.warn(ptr + "/absorption", "\"absorption\" has no effect on an opaque material");
  }
  if (const json* j = Walker::optional_member(v, "tint")) {
    if (!w.scalar_or_vec3(*j, ptr + "/tint", out.tint)) return false;
    if (!out.transparent) {
      w.warn(ptr + "/tint", "\"tint\" has no effect on an opaque material");
      out.tint = {1, 1, 1};
    }
  }
  if (const json* j = Walker::optional_member(v, "reflectance"); j && !w.scalar_or_vec3(*j, ptr + "/reflectance", out.reflectance)) {
    return false;
  }
  // A receiver's surface beyond Lambert's (formats/scene.h Surface): any of
  // the three gives it one, the others at their defaults.
  for (const char* key : {"metallic", "roughness", "emissive"}) {
    const json* j = Walker::optional_member(v, key);
    if (!j) continue;
    Surface& sf = out.surface ? *out.surface : out.surface.emplace();
    const std::string kp = ptr + "/" + key;
    const bool ok = key[0] == 'e' ? w.scalar_or_vec3(*j, kp, sf.emissive) : w.number(*j, kp, key[0] == 'm' ? sf.metallic : sf.roughness);
    if (!ok) return false;
  }
  return parse_scattering(w, v, ptr, out.scattering);
}

// The glTF files a scene names, each read once (by resolved path).
class GltfFiles {
 public:
  // The file, or nullptr after recording the error at `ptr`.
  const GltfFile* get(Walker& w, const std::string& ptr, const std::string& path, SceneDocument& doc) {
    auto it = files_.find(path);
    if (it == files_.end()) {
      auto file = GltfFile::load(path);
      if (!file) {
        w.fail(ptr, file.error().message);
        return nullptr;
      }
      for (const auto& s : file->inputs()) doc.inputs.push_back(s);
      for (const auto& s : file->warnings()) doc.warnings.push_back(s);
      it = files_.emplace(path, std::move(*file)).first;
    }
    return &it->second;
  }

 private:
  std::map<std::string, GltfFile> files_;
};

// "gltf": every mesh node of the file becomes an object after scene.json's
// own; its lights and camera are taken when scene.json gives none.
bool parse_gltf(Walker& w, const json& root, SceneDocument& doc, const std::filesystem::path& base, GltfFiles& files) {
  const json* j = Walker::optional_member(root, "gltf");
  if (!j) return true;
  std::string src;
  if (!w.string(*j, "/gltf", src)) return false;
  if (!is_gltf_path(src)) return w.fail("/gltf", "expected a .gltf or .glb file, got \"" + src + "\"");
  const std::string resolved = (base / src).lexically_normal().string();
  const GltfFile* file = files.get(w, "/gltf", resolved, doc);
  if (!file) return false;
  auto gs = file->scene();
  if (!gs) return w.fail("/gltf", gs.error().message);
  const auto offset = static_cast<std::uint32_t>(doc.scene.meshes.size());
  const auto image_offset = static_cast<std::uint32_t>(doc.images.size());
  for (Object o : gs->scene.objects) {
    o.mesh_index += offset;
    for_each_texture(o.material, [&](MapTexture& t) { t.image += image_offset; });
    doc.scene.objects.push_back(std::move(o));
  }
  for (auto& im : gs->images) doc.images.push_back(std::move(im));
  for (std::size_t i = 0; i < gs->meshes.size(); ++i) {
    const std::string& source = gs->scene.meshes[i].source;
    doc.mesh_paths.push_back(resolved + source.substr(source.find('#')));
    doc.scene.meshes.push_back(gs->scene.meshes[i]);
    doc.imported.emplace_back(std::move(gs->meshes[i]));
  }
  if (!root.contains("lights")) doc.scene.lights = gs->scene.lights;
  if (!root.contains("camera")) doc.scene.camera = gs->scene.camera;
  for (auto& s : gs->warnings) doc.warnings.push_back(std::move(s));
  return true;
}

bool parse_objects(Walker& w, const json& root, SceneDocument& doc, const std::filesystem::path& base, GltfFiles& files) {
  if (!root.contains("objects") && root.contains("gltf")) return true;
  const json* objs = w.member(root, "", "objects");
  if (!objs) return false;
  if (!objs->is_array()) return w.fail("/objects", "expected an array of objects, got " + Walker::type_of(*objs));
  std::map<std::pair<std::string, bool>, std::uint32_t> mesh_by_path;  // (resolved source, welded)
  std::map<std::pair<std::string, bool>, std::uint32_t> image_by_path;  // (file, data) -> image
  for (std::size_t i = 0; i < objs->size(); ++i) {
    const json& o = (*objs)[i];
    const std::string ptr = "/objects/" + std::to_string(i);
    if (!w.object(o, ptr)) return false;
    w.check_fields(o, ptr, {"name", "mesh", "role", "material", "transform"});
    Object obj;
    const json* name = w.member(o, ptr, "name");
    if (!name || !w.string(*name, ptr + "/name", obj.name)) return false;
    const json* mesh = w.member(o, ptr, "mesh");
    std::string mesh_src;
    if (!mesh || !w.string(*mesh, ptr + "/mesh", mesh_src)) return false;
    if (mesh_src.empty()) return w.fail(ptr + "/mesh", "mesh path is empty");
    if (const json* j = Walker::optional_member(o, "role")) {
      std::string role;
      if (!w.string(*j, ptr + "/role", role)) return false;
      if (role == "receiver") obj.role = Role::kReceiver;
      else if (role == "transparent") obj.role = Role::kTransparent;
      else if (role == "both") obj.role = Role::kBoth;
      else if (role == "mirror") obj.role = Role::kMirror;
      else return w.fail(ptr + "/role", "expected \"receiver\", \"transparent\", \"both\" or \"mirror\", got \"" + role + "\"");
    }
    std::vector<NamedTexture> textures;
    bool thin = false;
    if (const json* j = Walker::optional_member(o, "material"); j && !parse_material(w, *j, ptr + "/material", obj.material, textures, thin)) {
      return false;
    }
    // A thin-walled surface: its own kind of object, not a solid.
    if (thin && obj.role == Role::kTransparent) obj.role = Role::kThin;
    else if (thin) return w.fail(ptr + "/material/thin", "a thin-walled material needs \"role\": \"transparent\" (a thin wall is not a receiver)");
    for (const NamedTexture& t : textures) {
      // One image per distinct resolved file, as colour or as data.
      const std::string file = (base / t.file).lexically_normal().string();
      const std::string kp = ptr + "/material/" + t.key->key;
      const auto [at, added] = image_by_path.emplace(std::pair{file, t.key->data}, static_cast<std::uint32_t>(doc.images.size()));
      if (added) {
        ImageSource src;
        src.name = t.file;  // as the scene names it: the .cxb records it (TEXR), whatever the directory the bake runs in
        src.path = file;
        src.where = w.where(kp) + ": " + kp;
        src.data = t.key->data;
        doc.images.push_back(std::move(src));
      }
      // A base colour that masks or blends keeps its image's alpha.
      const auto& m = obj.material.maps;
      if (t.key == &kTextureKeys[0] && m && m->alpha_mode != AlphaMode::kOpaque) doc.images[at->second].keep_alpha = true;
      t.key->slot(obj.material)->image = at->second;
    }
    if (const json* j = Walker::optional_member(o, "transform"); j && !parse_transform(w, *j, ptr + "/transform", obj.transform)) return false;
    if (!is_mirror(obj.role) && o.contains("material") && o["material"].contains("reflectance")) {
      w.warn(ptr + "/material/reflectance", "\"reflectance\" has no effect on an object that is not a mirror");
    }

    // One mesh per distinct resolved file, numbered in order of first use;
    // "file.glb#Node" names a glTF node's mesh, welded for a solid
    // (GltfFile::node_mesh).
    const std::filesystem::path resolved = (base / mesh_src).lexically_normal();
    const auto hash = mesh_src.find('#');
    const bool from_gltf = hash != std::string::npos && is_gltf_path(mesh_src.substr(0, hash));
    const bool weld = from_gltf && is_transparent(obj.role);
    const auto [it, inserted] =
        mesh_by_path.emplace(std::pair{resolved.string(), weld}, static_cast<std::uint32_t>(doc.mesh_paths.size()));
    if (inserted) {
      if (from_gltf) {
        const std::string file_path = (base / mesh_src.substr(0, hash)).lexically_normal().string();
        const GltfFile* file = files.get(w, ptr + "/mesh", file_path, doc);
        if (!file) return false;
        auto node_mesh = file->node_mesh(mesh_src.substr(hash + 1), weld);
        if (!node_mesh) return w.fail(ptr + "/mesh", node_mesh.error().message);
        for (const auto& s : node_mesh->warnings) doc.warnings.push_back(resolved.string() + ": " + s);
        node_mesh->warnings.clear();
        doc.imported.emplace_back(std::move(*node_mesh));
      } else {
        doc.imported.emplace_back();
      }
      doc.mesh_paths.push_back(resolved.string());
      MeshInfo info;
      info.source = mesh_src;
      doc.scene.meshes.push_back(info);
    }
    obj.mesh_index = it->second;
    doc.scene.objects.push_back(obj);
  }
  return true;
}

bool parse_lights(Walker& w, const json& root, SceneDesc& scene) {
  const json* lights = Walker::optional_member(root, "lights");
  if (!lights) return true;
  if (!lights->is_array()) return w.fail("/lights", "expected an array of lights, got " + Walker::type_of(*lights));
  for (std::size_t i = 0; i < lights->size(); ++i) {
    const json& l = (*lights)[i];
    const std::string ptr = "/lights/" + std::to_string(i);
    if (!w.object(l, ptr)) return false;
    Light light;
    std::string type;
    const json* t = w.member(l, ptr, "type");
    if (!t || !w.string(*t, ptr + "/type", type)) return false;
    if (const json* j = Walker::optional_member(l, "name"); j && !w.string(*j, ptr + "/name", light.name)) return false;
    if (const json* j = Walker::optional_member(l, "color"); j && !w.scalar_or_vec3(*j, ptr + "/color", light.color)) return false;
    if (type == "directional") {
      w.check_fields(l, ptr, {"type", "name", "color", "direction", "irradiance"});
      light.type = LightType::kDirectional;
      const json* d = w.member(l, ptr, "direction");
      if (!d || !w.numbers(*d, ptr + "/direction", light.direction)) return false;
      if (const json* j = Walker::optional_member(l, "irradiance"); j && !w.number(*j, ptr + "/irradiance", light.irradiance)) return false;
    } else if (type == "point" || type == "spot") {
      light.spot = type == "spot";
      if (light.spot) {
        w.check_fields(l, ptr, {"type", "name", "color", "position", "intensity", "direction", "inner_cone_deg", "outer_cone_deg"});
      } else {
        w.check_fields(l, ptr, {"type", "name", "color", "position", "intensity"});
      }
      light.type = LightType::kPoint;
      const json* p = w.member(l, ptr, "position");
      if (!p || !w.numbers(*p, ptr + "/position", light.position)) return false;
      if (const json* j = Walker::optional_member(l, "intensity"); j && !w.number(*j, ptr + "/intensity", light.intensity)) return false;
      if (light.spot) {
        // KHR_lights_punctual's spot: half-angles, inner 0 and outer 45
        // degrees unless given; pointing down unless given.
        float inner = 0, outer = 45;
        if (const json* j = Walker::optional_member(l, "direction"); j && !w.numbers(*j, ptr + "/direction", light.direction)) return false;
        if (const json* j = Walker::optional_member(l, "inner_cone_deg"); j && !w.number(*j, ptr + "/inner_cone_deg", inner)) return false;
        if (const json* j = Walker::optional_member(l, "outer_cone_deg"); j && !w.number(*j, ptr + "/outer_cone_deg", outer)) return false;
        light.inner_cone = inner * 0.017453292f;
        light.outer_cone = outer * 0.017453292f;
      }
    } else if (type == "linear") {
      // Iwasaki et al. fig. 6d: a linear light approximated by N point lights at
      // the centres of N equal pieces of the segment, each with 1/N of the
      // intensity. Checked here, since the expanded lights have no place
      // in the file for validate_scene() to point at.
      w.check_fields(l, ptr, {"type", "name", "color", "from", "to", "samples", "intensity"});
      Vec3f from{}, to{};
      float samples = 8;
      const json* a = w.member(l, ptr, "from");
      if (!a || !w.numbers(*a, ptr + "/from", from)) return false;
      const json* b = w.member(l, ptr, "to");
      if (!b || !w.numbers(*b, ptr + "/to", to)) return false;
      if (const json* j = Walker::optional_member(l, "samples"); j && !w.number(*j, ptr + "/samples", samples)) return false;
      if (const json* j = Walker::optional_member(l, "intensity"); j && !w.number(*j, ptr + "/intensity", light.intensity)) return false;
      if (!(samples >= 1 && samples <= 256) || samples != std::floor(samples)) {
        return w.fail(ptr + "/samples", "must be a whole number in [1, 256]");
      }
      for (std::size_t k = 0; k < 3; ++k) {
        if (!std::isfinite(from[k]) || !std::isfinite(to[k])) return w.fail(ptr, "\"from\" and \"to\" must be finite");
      }
      if (!(light.intensity >= 0 && light.intensity <= 1e9f)) return w.fail(ptr + "/intensity", "must be in [0, 10^9]");
      if (scene.lights.size() + static_cast<std::size_t>(samples) > kMaxLights) {
        return w.fail(ptr + "/samples", "the scene would have more than 4096 lights");
      }
      const auto n = static_cast<int>(samples);
      light.type = LightType::kPoint;
      light.intensity /= static_cast<float>(n);
      const std::string base_name = light.name;
      for (int k = 0; k < n; ++k) {
        const float frac = (static_cast<float>(k) + 0.5f) / static_cast<float>(n);
        for (std::size_t c = 0; c < 3; ++c) light.position[c] = from[c] + frac * (to[c] - from[c]);
        light.name = base_name + "#" + std::to_string(k);
        scene.lights.push_back(light);
      }
      continue;
    } else {
      return w.fail(ptr + "/type", "expected \"directional\", \"point\", \"spot\" or \"linear\", got \"" + type + "\"");
    }
    scene.lights.push_back(light);
  }
  return true;
}

bool parse_water(Walker& w, const json& root, SceneDesc& scene) {
  const json* wj = Walker::optional_member(root, "water");
  if (!wj) return true;
  const std::string ptr = "/water";
  if (!w.object(*wj, ptr)) return false;
  w.check_fields(*wj, ptr, {"level", "ior", "dispersion", "absorption", "scattering", "phase", "anisotropy", "grid", "waves"});
  Water water;
  const json* level = w.member(*wj, ptr, "level");
  if (!level || !w.number(*level, ptr + "/level", water.level)) return false;
  if (const json* j = Walker::optional_member(*wj, "ior"); j && !w.number(*j, ptr + "/ior", water.ior)) return false;
  if (const json* j = Walker::optional_member(*wj, "dispersion"); j && !w.number(*j, ptr + "/dispersion", water.dispersion)) return false;
  if (const json* j = Walker::optional_member(*wj, "absorption"); j && !w.scalar_or_vec3(*j, ptr + "/absorption", water.absorption)) return false;
  if (!parse_scattering(w, *wj, ptr, water.scattering)) return false;
  if (const json* g = Walker::optional_member(*wj, "grid")) {
    if (!w.object(*g, ptr + "/grid")) return false;
    w.check_fields(*g, ptr + "/grid", {"cells", "extent"});
    if (const json* c = Walker::optional_member(*g, "cells")) {
      const std::string cp = ptr + "/grid/cells";
      if (!c->is_array() || c->size() != 2) return w.fail(cp, "expected [cells_x, cells_z], got " + Walker::type_of(*c));
      if (!w.integer((*c)[0], cp + "/0", water.cells[0]) || !w.integer((*c)[1], cp + "/1", water.cells[1])) return false;
    }
    if (const json* e = Walker::optional_member(*g, "extent"); e && !w.numbers(*e, ptr + "/grid/extent", water.extent)) return false;
  }
  if (const json* waves = Walker::optional_member(*wj, "waves")) {
    if (!waves->is_array()) return w.fail(ptr + "/waves", "expected an array of waves, got " + Walker::type_of(*waves));
    if (waves->size() > kMaxWaves) return w.fail(ptr + "/waves", "more than " + std::to_string(kMaxWaves) + " waves");
    for (std::size_t i = 0; i < waves->size(); ++i) {
      const json& wv = (*waves)[i];
      const std::string wp = ptr + "/waves/" + std::to_string(i);
      if (!w.object(wv, wp)) return false;
      w.check_fields(wv, wp, {"amplitude", "wavelength", "direction", "speed", "phase"});
      Wave wave;
      const json* a = w.member(wv, wp, "amplitude");
      if (!a || !w.number(*a, wp + "/amplitude", wave.amplitude)) return false;
      const json* l = w.member(wv, wp, "wavelength");
      if (!l || !w.number(*l, wp + "/wavelength", wave.wavelength)) return false;
      if (const json* j = Walker::optional_member(wv, "direction"); j && !w.numbers(*j, wp + "/direction", wave.direction)) return false;
      if (const json* j = Walker::optional_member(wv, "speed"); j && !w.number(*j, wp + "/speed", wave.speed)) return false;
      if (const json* j = Walker::optional_member(wv, "phase"); j && !w.number(*j, wp + "/phase", wave.phase)) return false;
      water.waves.push_back(wave);
    }
  }
  scene.water = water;
  return true;
}

bool parse_medium(Walker& w, const json& root, SceneDesc& scene) {
  const json* mj = Walker::optional_member(root, "medium");
  if (!mj) return true;
  const std::string ptr = "/medium";
  if (!w.object(*mj, ptr)) return false;
  w.check_fields(*mj, ptr, {"extent", "scattering", "absorption", "phase", "anisotropy"});
  Medium medium;
  const json* e = w.member(*mj, ptr, "extent");
  if (!e || !w.numbers(*e, ptr + "/extent", medium.extent)) return false;
  if (const json* j = Walker::optional_member(*mj, "absorption"); j && !w.scalar_or_vec3(*j, ptr + "/absorption", medium.absorption)) return false;
  if (!parse_scattering(w, *mj, ptr, medium.scattering)) return false;
  scene.medium = medium;
  return true;
}

bool parse_camera(Walker& w, const json& root, SceneDesc& scene) {
  const json* cj = Walker::optional_member(root, "camera");
  if (!cj) return true;
  const std::string ptr = "/camera";
  if (!w.object(*cj, ptr)) return false;
  w.check_fields(*cj, ptr, {"position", "target", "up", "fov_y_deg", "near", "far"});
  Camera cam;
  const json* p = w.member(*cj, ptr, "position");
  if (!p || !w.numbers(*p, ptr + "/position", cam.position)) return false;
  const json* t = w.member(*cj, ptr, "target");
  if (!t || !w.numbers(*t, ptr + "/target", cam.target)) return false;
  if (const json* j = Walker::optional_member(*cj, "up"); j && !w.numbers(*j, ptr + "/up", cam.up)) return false;
  if (const json* j = Walker::optional_member(*cj, "fov_y_deg"); j && !w.number(*j, ptr + "/fov_y_deg", cam.fov_y_deg)) return false;
  if (const json* j = Walker::optional_member(*cj, "near"); j && !w.number(*j, ptr + "/near", cam.near_plane)) return false;
  if (const json* j = Walker::optional_member(*cj, "far"); j && !w.number(*j, ptr + "/far", cam.far_plane)) return false;
  scene.camera = cam;
  return true;
}

}  // namespace

Result<SceneDocument> parse_scene_json(const std::string& text, const std::string& path) {
  const LocatedJson doc = parse_located_json(text);
  if (!doc.error.empty()) {
    // nlohmann reports "line L, column C: ..."; make it FILE:L:C.
    std::string msg = doc.error;
    std::size_t line = 0, col = 0;
    if (std::sscanf(msg.c_str(), "line %zu, column %zu", &line, &col) == 2) {
      const auto colon = msg.find(": ");
      msg = path + ":" + std::to_string(line) + ":" + std::to_string(col) + ": " +
            (colon == std::string::npos ? msg : msg.substr(colon + 2));
    } else {
      msg = path + ": " + msg;
    }
    return make_error(ErrorCode::kInput, msg);
  }
  Walker w(doc, path);
  SceneDocument out;
  const json& root = doc.root;
  if (!w.object(root, "")) return *w.error();
  w.check_fields(root, "", {"name", "objects", "gltf", "lights", "water", "medium", "camera", "$schema", "comment"});
  if (const json* j = Walker::optional_member(root, "name"); j && !w.string(*j, "/name", out.scene.name)) return *w.error();
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  out.inputs.push_back(path);
  GltfFiles files;
  if (!parse_objects(w, root, out, base, files) || !parse_gltf(w, root, out, base, files) || !parse_lights(w, root, out.scene) ||
      !parse_water(w, root, out.scene) || !parse_medium(w, root, out.scene) || !parse_camera(w, root, out.scene)) {
    return *w.error();
  }
  if (out.scene.lights.empty()) {
    w.warn("/lights", "the scene has no lights; everything will be dark: add \"lights\": [{\"type\": \"directional\", "
                      "\"direction\": [0.3, -1, 0.2], \"irradiance\": 1}] (docs/scene-format.md)");
  }
  if (auto issue = validate_scene(out.scene, /*check_meshes=*/false)) {
    w.fail(issue->pointer, issue->message);
    return *w.error();
  }
  normalize_scene(out.scene);
  for (auto& s : w.warnings()) out.warnings.push_back(std::move(s));
  return out;
}

Light default_sun(const std::optional<Camera>& camera) {
  // The automatic camera's direction back towards the eye (Renderer::default_camera).
  double bx = 0.6, bz = 1.0;
  if (camera) {
    bx = static_cast<double>(camera->position[0]) - camera->target[0];
    bz = static_cast<double>(camera->position[2]) - camera->target[2];
  }
  double h = std::hypot(bx, bz);
  if (!(h > 1e-9)) bx = 0, bz = 1, h = 1;  // looking straight down
  const double turn = 40.0 * 3.14159265358979323846 / 180.0, elevation = 55.0 * 3.14159265358979323846 / 180.0;
  const double cx = bx / h, cz = bz / h;
  // Turned to the view's right (a clockwise turn seen from above).
  const double tx = cx * std::cos(turn) + cz * std::sin(turn), tz = -cx * std::sin(turn) + cz * std::cos(turn);
  Light sun;
  sun.type = LightType::kDirectional;
  sun.name = "default sun";
  sun.direction = {static_cast<float>(-tx * std::cos(elevation)), static_cast<float>(-std::sin(elevation)),
                   static_cast<float>(-tz * std::cos(elevation))};
  sun.irradiance = 1.0f;
  return sun;
}

Result<SceneDocument> load_scene(const std::string& path, bool default_light) {
  if (!is_gltf_path(path)) return load_scene_json(path);
  auto file = GltfFile::load(path);
  if (!file) return file.error();
  auto gs = file->scene();
  if (!gs) return gs.error();
  SceneDocument out;
  out.scene = std::move(gs->scene);
  out.images = std::move(gs->images);
  for (std::size_t i = 0; i < gs->meshes.size(); ++i) {
    const std::string& source = out.scene.meshes[i].source;
    out.mesh_paths.push_back(path + source.substr(source.find('#')));
    out.imported.emplace_back(std::move(gs->meshes[i]));
  }
  out.inputs = file->inputs();
  out.warnings = file->warnings();
  for (auto& s : gs->warnings) out.warnings.push_back(std::move(s));
  if (out.scene.lights.empty() && default_light) {
    out.scene.lights.push_back(default_sun(out.scene.camera));
    out.warnings.push_back(path + ": the file has no lights; lit by the default rig, a sun 55 degrees high over the camera's "
                                  "right shoulder (E0 = 1 W/m^2) and the daylight sky (--no-default-light: none; or export "
                                  "its lights as KHR_lights_punctual)");
  } else if (out.scene.lights.empty()) {
    out.warnings.push_back(path + ": the scene has no lights; everything will be dark. Export its lights as KHR_lights_punctual "
                                  "(Blender: glTF export, Include > Punctual Lights), or bake a scene.json that names this file "
                                  "(\"gltf\") and adds \"lights\" (docs/scene-format.md)");
  }
  if (auto issue = validate_scene(out.scene, /*check_meshes=*/false)) {
    return make_error(ErrorCode::kInput, path + ": the imported scene's " + issue->pointer + ": " + issue->message);
  }
  normalize_scene(out.scene);
  return out;
}

Result<SceneDocument> load_scene_json(const std::string& path) {
  auto bytes = read_file(path, std::uint64_t{64} << 20);
  if (!bytes) return bytes.error();
  return parse_scene_json(std::string(bytes->begin(), bytes->end()), path);
}

}  // namespace caustix::bake
