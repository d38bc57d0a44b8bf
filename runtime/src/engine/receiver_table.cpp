#include "receiver_table.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <unordered_set>

namespace caustix::runtime {
namespace {

// Bindings order (caustix.glsl's caustix_table_layer()).
enum : int {
  kShadow2d = 0, kShadowCube, kCaustics, kPosition, kGlassIllumination, kGlassTarget,
  kGlassShadow2d, kGlassShadowCube, kCausticMap, kShadowVsm, kGlassShadowVsm, kCausticsColor
};

bool is_cube(int k) { return k == kShadowCube || k == kGlassShadowCube; }
bool is_depth(int k) { return k == kShadow2d || k == kGlassShadow2d || is_cube(k); }

GLuint texture_of(int k, const ReceiverLighting& r) {
  switch (k) {
    case kShadow2d: return r.shadow_2d;
    case kShadowCube: return r.shadow_cube;
    case kCaustics: return r.caustics;
    case kPosition: return r.position;
    case kGlassIllumination: return r.glass_illumination;
    case kGlassTarget: return r.glass_target;
    case kGlassShadow2d: return r.glass_shadow_2d;
    case kGlassShadowCube: return r.glass_shadow_cube;
    case kCausticMap: return r.caustic_map;
    case kShadowVsm: return r.shadow_vsm;
    case kGlassShadowVsm: return r.glass_shadow_vsm;
    default: return r.caustics_color;
  }
}

// Whether caustix.glsl reads texture k for this block (caustix_irradiance_from_light):
// only those are copied.
bool reads(int k, const LightBlock& b) {
  const bool directional = b.mode.y == 1, point = b.mode.y == 2, vsm = b.light_direction.w != 0.0f;
  const bool caustics = b.mode.x == static_cast<int>(LightMode::kCaustics);
  const bool direct = b.mode.x == static_cast<int>(LightMode::kDirect);
  const bool glass_shadows = direct && b.mode.w != 0;
  switch (k) {
    case kShadow2d: return directional && !vsm;
    case kShadowVsm: return directional && vsm;
    case kShadowCube: return point;
    case kCaustics:
    case kPosition: return caustics;
    case kCausticsColor: return caustics && b.frame_v.w != 0.0f;
    case kGlassIllumination:
    case kGlassTarget: return direct && b.mode.z != 0;
    case kGlassShadow2d: return glass_shadows && directional && !vsm;
    case kGlassShadowVsm: return glass_shadows && directional && vsm;
    case kGlassShadowCube: return glass_shadows && point;
    default: return direct && b.cmap_origin.w != 0.0f;  // kCausticMap
  }
}

// The product texture k belongs to.
ReceiverTable::Product made_by(int k) {
  switch (k) {
    case kCaustics:
    case kCausticsColor: return ReceiverTable::kLevelMaps;
    case kPosition: return ReceiverTable::kPositionMaps;
    case kGlassIllumination:
    case kGlassTarget: return ReceiverTable::kGlass;
    case kCausticMap: return ReceiverTable::kCausticMaps;
    default: return ReceiverTable::kShadowMaps;
  }
}

GLenum default_format(int k) {
  if (is_depth(k)) return GL_DEPTH_COMPONENT16;
  if (k == kPosition) return GL_R16;
  if (k == kShadowVsm || k == kGlassShadowVsm) return GL_RG32F;
  return GL_RGBA32F;
}

std::uint64_t texel_bytes(GLenum format) {
  switch (format) {
    case GL_DEPTH_COMPONENT16:
    case GL_R16: return 2;
    case GL_R32F:
    case GL_DEPTH_COMPONENT24:
    case GL_DEPTH_COMPONENT32F: return 4;
    case GL_RG32F: return 8;
    default: return 16;
  }
}

GLenum source_target(int k) {
  if (is_cube(k)) return GL_TEXTURE_CUBE_MAP;
  return k == kGlassIllumination ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D;
}

const char* kind_name(int k) {
  static const char* names[] = {"shadow_2d", "shadow_cube", "caustics", "position", "glass_illumination", "glass_target",
                                "glass_shadow_2d", "glass_shadow_cube", "caustic_map", "shadow_vsm", "glass_shadow_vsm",
                                "caustics_color"};
  return names[k];
}

}  // namespace

ReceiverTable::Source ReceiverTable::describe(int kind, GLuint texture) const {
  Source s;
  s.texture = texture;
  GLint format = 0;
  glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_WIDTH, &s.width);
  glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_HEIGHT, &s.height);
  glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
  s.format = static_cast<GLenum>(format);
  s.layers = 1;
  if (is_cube(kind)) s.layers = 6;
  if (kind == kGlassIllumination) glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_DEPTH, &s.layers);
  return s;
}

Status ReceiverTable::refresh(std::span<const Pair> pairs, std::span<const Versions> versions, bool everything) {
  copies = 0;
  copied_bytes = 0;
  const auto lights = static_cast<std::uint32_t>(versions.size());
  // Per light, whether each product moved since the last refresh.
  everything = everything || !built_ || copied_.size() != versions.size();
  auto moved = [&](std::uint32_t li, Product p) { return everything || versions[li][p] != copied_[li][p]; };
  // Which sources each kind holds, in layer order, and where each pair's lie.
  std::unordered_set<GLuint> fresh;  // described now: their texels are copied
  std::array<std::vector<GLuint>, kKinds> order;
  std::array<std::vector<GLint>, kKinds> first_layer;  // per entry of `order`
  std::array<GLint, kKinds> next_layer{};
  std::vector<ReceiverTableEntry> entries(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    ReceiverTableEntry& e = entries[i];
    for (auto& v : e.size) v = glm::ivec4(1);
    if (!pairs[i].receiver) continue;  // a zero block: mode.y 0 lights nothing
    const ReceiverLighting& r = *pairs[i].lighting;
    const std::uint32_t li = lights ? static_cast<std::uint32_t>(i % lights) : 0;
    e.block = r.block;
    for (int k = 0; k < kKinds; ++k) {
      if (!reads(k, r.block)) continue;
      const GLuint tex = texture_of(k, r);
      const bool known = sources_.count(tex) != 0;
      if ((!known || moved(li, made_by(k))) && fresh.insert(tex).second) sources_[tex] = describe(k, tex);
      const Source& src = sources_[tex];
      const auto at = std::find(order[k].begin(), order[k].end(), tex);
      GLint layer = 0;
      if (at == order[k].end()) {
        layer = next_layer[k];
        order[k].push_back(tex);
        first_layer[k].push_back(layer);
        next_layer[k] += is_cube(k) ? 1 : src.layers;
      } else {
        layer = first_layer[k][static_cast<std::size_t>(at - order[k].begin())];
      }
      e.layer[k >> 2][k & 3] = layer;
      e.size[k >> 1][(k & 1) * 2] = src.width;
      e.size[k >> 1][(k & 1) * 2 + 1] = src.height;
    }
  }

  for (int k = 0; k < kKinds; ++k) {
    Kind& kd = kinds_[k];
    GLint w = 1, h = 1, layers = is_cube(k) ? 6 : 1;
    GLenum format = default_format(k);
    if (!order[k].empty()) {
      w = h = 0;
      layers = 0;
      format = sources_[order[k][0]].format;
      for (GLuint tex : order[k]) {
        const Source& s = sources_[tex];
        if (s.format != format) {
          return make_error(ErrorCode::kGraphics, std::string("bind_all: the ") + kind_name(k) + " textures differ in format");
        }
        if (is_cube(k) && (s.width != sources_[order[k][0]].width)) {
          return make_error(ErrorCode::kGraphics, std::string("bind_all: the point lights' ") + kind_name(k) + " maps differ in size");
        }
        w = std::max(w, s.width);
        h = std::max(h, s.height);
        layers += s.layers;
      }
    }
    const bool relayout = !built_ || w != kd.width || h != kd.height || layers != kd.layers || format != kd.format;
    if (relayout) {
      const GLenum target = is_cube(k) ? GL_TEXTURE_CUBE_MAP_ARRAY : GL_TEXTURE_2D_ARRAY;
      kd.array = gl::make_texture(target);
      glTextureStorage3D(kd.array.get(), 1, format, w, h, layers);
      // Filtering as the sources' (level 0 only), clamped at the edges.
      GLint mag = GL_LINEAR, compare = GL_NONE, func = GL_LEQUAL;
      if (!order[k].empty()) {
        glGetTextureParameteriv(order[k][0], GL_TEXTURE_MAG_FILTER, &mag);
        glGetTextureParameteriv(order[k][0], GL_TEXTURE_COMPARE_MODE, &compare);
        glGetTextureParameteriv(order[k][0], GL_TEXTURE_COMPARE_FUNC, &func);
      } else if (is_depth(k)) {
        compare = GL_COMPARE_REF_TO_TEXTURE;
      }
      glTextureParameteri(kd.array.get(), GL_TEXTURE_MIN_FILTER, mag);
      glTextureParameteri(kd.array.get(), GL_TEXTURE_MAG_FILTER, mag);
      glTextureParameteri(kd.array.get(), GL_TEXTURE_COMPARE_MODE, compare);
      glTextureParameteri(kd.array.get(), GL_TEXTURE_COMPARE_FUNC, func);
      for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R}) glTextureParameteri(kd.array.get(), wrap, GL_CLAMP_TO_EDGE);
      kd.width = w;
      kd.height = h;
      kd.layers = layers;
      kd.format = format;
    }
    const bool all = relayout || order[k] != kd.order;
    for (std::size_t j = 0; j < order[k].size(); ++j) {
      const Source& s = sources_[order[k][j]];
      if (!all && !fresh.count(s.texture)) continue;
      const GLint z = is_cube(k) ? 6 * first_layer[k][j] : first_layer[k][j];
      glCopyImageSubData(s.texture, source_target(k), 0, 0, 0, 0, kd.array.get(), is_cube(k) ? GL_TEXTURE_CUBE_MAP_ARRAY : GL_TEXTURE_2D_ARRAY,
                         0, 0, 0, z, s.width, s.height, s.layers);
      ++copies;
      copied_bytes += std::uint64_t(s.width) * std::uint64_t(s.height) * std::uint64_t(s.layers) * texel_bytes(s.format);
    }
    kd.order = std::move(order[k]);
  }
  // Forget the textures no longer used (their names may come back).
  for (auto it = sources_.begin(); it != sources_.end();) {
    bool used = false;
    for (const Kind& kd : kinds_) used = used || std::find(kd.order.begin(), kd.order.end(), it->first) != kd.order.end();
    it = used ? std::next(it) : sources_.erase(it);
  }

  // The entries: uploaded where they changed.
  const std::size_t header = sizeof(glm::ivec4);
  if (!built_) {
    buffer_ = gl::make_buffer();
    glNamedBufferStorage(buffer_.get(), static_cast<GLsizeiptr>(header + entries.size() * sizeof(ReceiverTableEntry)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    const glm::ivec4 shape(lights ? static_cast<int>(pairs.size() / lights) : 0, static_cast<int>(lights), 0, 0);
    glNamedBufferSubData(buffer_.get(), 0, header, &shape);
    uploaded_.assign(entries.size(), ReceiverTableEntry{});
  }
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (built_ && std::memcmp(&entries[i], &uploaded_[i], sizeof(ReceiverTableEntry)) == 0) continue;
    glNamedBufferSubData(buffer_.get(), static_cast<GLintptr>(header + i * sizeof(ReceiverTableEntry)), sizeof(ReceiverTableEntry), &entries[i]);
    uploaded_[i] = entries[i];
  }
  built_ = true;
  copied_.assign(versions.begin(), versions.end());
  return Status::success();
}

void ReceiverTable::bind(const Bindings& b) const {
  const GLuint buffer = buffer_.get();
  const GLintptr offset = 0;
  const auto range = static_cast<GLsizeiptr>(sizeof(glm::ivec4) + uploaded_.size() * sizeof(ReceiverTableEntry));
  glBindBuffersRange(GL_SHADER_STORAGE_BUFFER, b.table, 1, &buffer, &offset, &range);
  const unsigned units[kKinds] = {b.shadow_2d,       b.shadow_cube,       b.caustics,    b.position,   b.glass_illumination,
                                  b.glass_target,    b.glass_shadow_2d,   b.glass_shadow_cube, b.caustic_map, b.shadow_vsm,
                                  b.glass_shadow_vsm, b.caustics_color};
  for (int k = 0; k < kKinds; ++k) glBindTextureUnit(units[k], kinds_[k].array.get());
}

std::uint64_t ReceiverTable::gpu_bytes() const {
  std::uint64_t n = uploaded_.size() * sizeof(ReceiverTableEntry) + sizeof(glm::ivec4);
  for (const Kind& kd : kinds_) n += std::uint64_t(kd.width) * std::uint64_t(kd.height) * std::uint64_t(kd.layers) * texel_bytes(kd.format);
  return built_ ? n : 0;
}

}  // namespace caustix::runtime
