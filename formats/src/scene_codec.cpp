// Payload layouts of the scene chunks (SCNE, OBJS, LGHT, WATR, MDIA, CAMR, RNDR, MESH);
// formats/SPEC.md documents them field by field.

#include <algorithm>

#include "bytes.h"
#include "caustix/formats/scene.h"
#include "chunk_decoder.h"
#include "zstd_frame.h"

namespace caustix {
namespace {

using cxb::detail::ByteWriter;
using cxb::detail::ChunkDecoder;

// --- encoding ----------------------------------------------------------------

std::vector<std::uint8_t> encode_scene_chunk(const SceneDesc& s) {
  ByteWriter w;
  w.str(s.name);
  w.u32(static_cast<std::uint32_t>(s.meshes.size()));
  for (const MeshInfo& m : s.meshes) {
    w.str(m.source);
    w.u32(m.vertex_count);
    w.u32(m.triangle_count);
    w.u8(m.position_bits);
    w.u8(m.normal_bits);
    w.u16(0);
    w.vec3(m.bounds_min);
    w.vec3(m.bounds_max);
  }
  return w.take();
}

std::vector<std::uint8_t> encode_objects(const SceneDesc& s) {
  ByteWriter w;
  w.u32(static_cast<std::uint32_t>(s.objects.size()));
  for (const Object& o : s.objects) {
    w.str(o.name);
    w.u32(o.mesh_index);
    w.u8(static_cast<std::uint8_t>(o.role));
    w.u8(o.material.transparent ? 1 : 0);
    w.u16(0);
    w.vec3(o.material.albedo);
    w.f32(o.material.ior);
    for (float f : o.transform) w.f32(f);
  }
  return w.take();
}

std::vector<std::uint8_t> encode_lights(const SceneDesc& s) {
  ByteWriter w;
  w.u32(static_cast<std::uint32_t>(s.lights.size()));
  for (const Light& l : s.lights) {
    w.u8(static_cast<std::uint8_t>(l.type));
    w.u8(0);
    w.u16(0);
    w.str(l.name);
    w.vec3(l.color);
    w.vec3(l.direction);
    w.f32(l.irradiance);
    w.vec3(l.position);
    w.f32(l.intensity);
  }
  return w.take();
}

std::vector<std::uint8_t> encode_water(const Water& water) {
  ByteWriter w;
  w.f32(water.level);
  w.f32(water.ior);
  w.vec3(water.absorption);
  w.u32(water.cells[0]);
  w.u32(water.cells[1]);
  for (float f : water.extent) w.f32(f);
  w.u32(static_cast<std::uint32_t>(water.waves.size()));
  for (const Wave& wave : water.waves) {
    w.f32(wave.amplitude);
    w.f32(wave.wavelength);
    w.f32(wave.direction[0]);
    w.f32(wave.direction[1]);
    w.f32(wave.speed);
    w.f32(wave.phase);
  }
  return w.take();
}

std::vector<std::uint8_t> encode_camera(const Camera& c) {
  ByteWriter w;
  w.vec3(c.position);
  w.vec3(c.target);
  w.vec3(c.up);
  w.f32(c.fov_y_deg);
  w.f32(c.near_plane);
  w.f32(c.far_plane);
  return w.take();
}

std::vector<std::uint8_t> encode_render(const RenderDefaults& r) {
  ByteWriter w;
  w.str(r.preset);
  w.u32(r.caustics_map_size);
  w.u32(r.glass_map_size);
  w.u32(r.glass_planes);
  w.u32(r.volume_photons);
  w.u32(r.volume_grid);
  w.u32(r.cmap_photons);
  w.u32(r.cmap_map_size);
  w.u32(r.cmap_adaptive_levels);
  w.u32(r.cmap_photon_budget);
  w.u32(r.water_texture);
  w.u32(r.glass_spectral_coarse);
  return w.take();
}

void encode_scattering(ByteWriter& w, const Scattering& s) {
  w.vec3(s.coefficient);
  w.u8(static_cast<std::uint8_t>(s.phase));
  w.u8(0);
  w.u16(0);
  w.f32(s.anisotropy);
}

constexpr std::uint8_t kMediaBox = 1u << 0;
constexpr std::uint8_t kMediaWater = 1u << 1;

std::vector<std::uint8_t> encode_media(const SceneDesc& s) {
  ByteWriter w;
  const bool water = s.water && s.water->scattering.scatters();
  w.u8(static_cast<std::uint8_t>((s.medium ? kMediaBox : 0) | (water ? kMediaWater : 0)));
  w.u8(0);
  w.u16(0);
  if (s.medium) {
    for (float f : s.medium->extent) w.f32(f);
    w.vec3(s.medium->absorption);
    encode_scattering(w, s.medium->scattering);
  }
  if (water) encode_scattering(w, s.water->scattering);
  std::vector<std::uint32_t> scattering_objects;
  for (std::uint32_t i = 0; i < s.objects.size(); ++i) {
    if (s.objects[i].material.scattering.scatters()) scattering_objects.push_back(i);
  }
  w.u32(static_cast<std::uint32_t>(scattering_objects.size()));
  for (std::uint32_t i : scattering_objects) {
    w.u32(i);
    encode_scattering(w, s.objects[i].material.scattering);
  }
  return w.take();
}

// MIRR: u32 count; per mirror object, in object order: u32 object index,
// vec3 reflectance.
std::vector<std::uint8_t> encode_mirrors(const SceneDesc& s) {
  ByteWriter w;
  std::vector<std::uint32_t> mirrors;
  for (std::uint32_t i = 0; i < s.objects.size(); ++i) {
    if (is_mirror(s.objects[i].role)) mirrors.push_back(i);
  }
  w.u32(static_cast<std::uint32_t>(mirrors.size()));
  for (std::uint32_t i : mirrors) {
    w.u32(i);
    w.vec3(s.objects[i].material.reflectance);
  }
  return w.take();
}

// SPOT: u32 count; per spot light, in light order: u32 light
// index, f32 inner and f32 outer half-angle (radians).
bool has_spots(const SceneDesc& s) {
  return std::any_of(s.lights.begin(), s.lights.end(), [](const Light& l) { return l.spot; });
}
std::vector<std::uint8_t> encode_spots(const SceneDesc& s) {
  ByteWriter w;
  w.u32(static_cast<std::uint32_t>(std::count_if(s.lights.begin(), s.lights.end(), [](const Light& l) { return l.spot; })));
  for (std::uint32_t i = 0; i < s.lights.size(); ++i) {
    if (!s.lights[i].spot) continue;
    w.u32(i);
    w.f32(s.lights[i].inner_cone);
    w.f32(s.lights[i].outer_cone);
  }
  return w.take();
}

// TINT: u32 count; per transparent object whose tint is not
// (1, 1, 1), in object order: u32 object index, vec3 tint.
bool has_tints(const SceneDesc& s) {
  return std::any_of(s.objects.begin(), s.objects.end(), [](const Object& o) { return is_tinted(o.material); });
}
std::vector<std::uint8_t> encode_tints(const SceneDesc& s) {
  ByteWriter w;
  w.u32(static_cast<std::uint32_t>(std::count_if(s.objects.begin(), s.objects.end(), [](const Object& o) { return is_tinted(o.material); })));
  for (std::uint32_t i = 0; i < s.objects.size(); ++i) {
    if (!is_tinted(s.objects[i].material)) continue;
    w.u32(i);
    w.vec3(s.objects[i].material.tint);
  }
  return w.take();
}

// SURF: u32 count; per receiver with a Surface, in object order: u32
// object index, f32 metallic, f32 roughness, vec3 emissive.
bool has_surfaces(const SceneDesc& s) {
  return std::any_of(s.objects.begin(), s.objects.end(), [](const Object& o) { return o.material.surface.has_value(); });
}
std::vector<std::uint8_t> encode_surfaces(const SceneDesc& s) {
  ByteWriter w;
  w.u32(static_cast<std::uint32_t>(std::count_if(s.objects.begin(), s.objects.end(), [](const Object& o) { return o.material.surface.has_value(); })));
  for (std::uint32_t i = 0; i < s.objects.size(); ++i) {
    const auto& sf = s.objects[i].material.surface;
    if (!sf) continue;
    w.u32(i);
    w.f32(sf->metallic);
    w.f32(sf->roughness);
    w.vec3(sf->emissive);
  }
  return w.take();
}

// TEXR: u32 image count; per image: string source, u32 width,
// u32 height, u32 data size, one zstd frame of width * height * 3 bytes
// (sRGB RGB, top row first); u32 texture count; per textured receiver, in
// object order: u32 object index, u32 image index, u8 projection, u8 wrap
// s, u8 wrap t, u8 zero, 6 x f32 transform.
constexpr int kTextureZstdLevel = 3;
void encode_texture_ref(ByteWriter& w, const AlbedoTexture& t) {
  w.u32(t.image);
  w.u8(static_cast<std::uint8_t>(t.projection));
  w.u8(static_cast<std::uint8_t>(t.wrap_s));
  w.u8(static_cast<std::uint8_t>(t.wrap_t));
  w.u8(0);
  for (float f : t.transform) w.f32(f);
}
bool has_textures(const SceneDesc& s) {
  return !s.images.empty() || std::any_of(s.objects.begin(), s.objects.end(), [](const Object& o) { return o.material.albedo_texture.has_value(); });
}
std::vector<std::uint8_t> encode_textures(const SceneDesc& s) {
  ByteWriter w;
  w.u32(static_cast<std::uint32_t>(s.images.size()));
  for (const TextureImage& im : s.images) {
    w.str(im.source);
    w.u32(im.width);
    w.u32(im.height);
    cxb::detail::write_zstd_frame(w, im.rgb, kTextureZstdLevel);
  }
  w.u32(static_cast<std::uint32_t>(std::count_if(s.objects.begin(), s.objects.end(), [](const Object& o) { return o.material.albedo_texture.has_value(); })));
  for (std::uint32_t i = 0; i < s.objects.size(); ++i) {
    const auto& t = s.objects[i].material.albedo_texture;
    if (!t) continue;
    w.u32(i);
    encode_texture_ref(w, *t);
  }
  return w.take();
}

// TEXM: u32 alpha-plane count; per image with alpha, in image order: u32
// image index, u32 data size, one zstd frame of width * height bytes;
// u32 count; per receiver with SurfaceMaps, in object order: u32 object
// index, u8 alpha mode, u8 map mask (bit 0 metallic-roughness, 1 normal,
// 2 occlusion, 3 emissive), u16 zero, f32 alpha, f32 alpha cut-off, f32
// normal scale, f32 occlusion strength, then per map in bit order a
// texture record as TEXR's.
bool has_surface_maps(const SceneDesc& s) {
  return std::any_of(s.images.begin(), s.images.end(), [](const TextureImage& im) { return !im.alpha.empty(); }) ||
         std::any_of(s.objects.begin(), s.objects.end(), [](const Object& o) { return o.material.maps.has_value(); });
}
std::vector<std::uint8_t> encode_surface_maps(const SceneDesc& s) {
  ByteWriter w;
  w.u32(static_cast<std::uint32_t>(std::count_if(s.images.begin(), s.images.end(), [](const TextureImage& im) { return !im.alpha.empty(); })));
  for (std::uint32_t i = 0; i < s.images.size(); ++i) {
    if (s.images[i].alpha.empty()) continue;
    w.u32(i);
    cxb::detail::write_zstd_frame(w, s.images[i].alpha, kTextureZstdLevel);
  }
  w.u32(static_cast<std::uint32_t>(std::count_if(s.objects.begin(), s.objects.end(), [](const Object& o) { return o.material.maps.has_value(); })));
  for (std::uint32_t i = 0; i < s.objects.size(); ++i) {
    const auto& m = s.objects[i].material.maps;
    if (!m) continue;
    w.u32(i);
    w.u8(static_cast<std::uint8_t>(m->alpha_mode));
    const std::array<const std::optional<MapTexture>*, 4> slots{&m->metallic_roughness, &m->normal, &m->occlusion, &m->emissive};
    std::uint8_t mask = 0;
    for (std::size_t k = 0; k < slots.size(); ++k) mask |= static_cast<std::uint8_t>(slots[k]->has_value() ? 1u << k : 0u);
    w.u8(mask);
    w.u16(0);
    w.f32(m->alpha);
    w.f32(m->alpha_cutoff);
    w.f32(m->normal_scale);
    w.f32(m->occlusion_strength);
    for (const auto* t : slots) {
      if (*t) encode_texture_ref(w, **t);
    }
  }
  return w.take();
}

// DISP: f32 water dispersion (0 without water); u32 count; per
// transparent object with dispersion > 0, in object order: u32 object
// index, f32 dispersion.
std::vector<std::uint8_t> encode_dispersion(const SceneDesc& s) {
  ByteWriter w;
  w.f32(s.water ? s.water->dispersion : 0.0f);
  std::vector<std::uint32_t> listed;
  for (std::uint32_t i = 0; i < s.objects.size(); ++i) {
    if (is_transparent(s.objects[i].role) && s.objects[i].material.dispersion > 0) listed.push_back(i);
  }
  w.u32(static_cast<std::uint32_t>(listed.size()));
  for (std::uint32_t i : listed) {
    w.u32(i);
    w.f32(s.objects[i].material.dispersion);
  }
  return w.take();
}

bool has_mirrors(const SceneDesc& s) {
  return std::any_of(s.objects.begin(), s.objects.end(), [](const Object& o) { return is_mirror(o.role); });
}

// --- decoding ----------------------------------------------------------------

// Smallest encodings, used to bound counts by the payload size.
constexpr std::size_t kMinMeshRecord = 4 + 4 + 4 + 4 + 24;
constexpr std::size_t kMinObjectRecord = 4 + 4 + 4 + 16 + 64;
constexpr std::size_t kMinLightRecord = 4 + 4 + 12 + 12 + 4 + 12 + 4;
constexpr std::size_t kWaveRecord = 24;

bool decode_scene_chunk(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.str(s.name, "scene name") || !d.count(n, kMaxObjects, kMinMeshRecord, "mesh")) return false;
  s.meshes.resize(n);
  for (MeshInfo& m : s.meshes) {
    if (!d.str(m.source, "mesh source") || !d.u32(m.vertex_count, "mesh vertex count") ||
        !d.u32(m.triangle_count, "mesh triangle count") ||
        !d.u8(m.position_bits, "mesh position bits") || !d.u8(m.normal_bits, "mesh normal bits") ||
        !d.zero16("mesh reserved") || !d.vec3(m.bounds_min, "mesh bounds") ||
        !d.vec3(m.bounds_max, "mesh bounds")) {
      return false;
    }
  }
  return d.finish();
}

bool decode_objects(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.count(n, kMaxObjects, kMinObjectRecord, "object")) return false;
  s.objects.resize(n);
  for (Object& o : s.objects) {
    std::uint8_t role = 0, transparent = 0;
    if (!d.str(o.name, "object name") || !d.u32(o.mesh_index, "object mesh index") ||
        !d.u8(role, "object role") || !d.u8(transparent, "object transparent flag") ||
        !d.zero16("object reserved") || !d.vec3(o.material.albedo, "object albedo") ||
        !d.f32(o.material.ior, "object ior")) {
      return false;
    }
    for (float& f : o.transform) {
      if (!d.f32(f, "object transform")) return false;
    }
    if (role < 1 || role > 5) return d.fail("object '" + o.name + "': role " + std::to_string(role) + " is not 1..5");
    if (transparent > 1) return d.fail("object '" + o.name + "': transparent flag is not 0 or 1");
    o.role = static_cast<Role>(role);
    o.material.transparent = transparent == 1;
  }
  return d.finish();
}

bool decode_lights(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.count(n, kMaxLights, kMinLightRecord, "light")) return false;
  s.lights.resize(n);
  for (Light& l : s.lights) {
    std::uint8_t type = 0, pad8 = 0;
    if (!d.u8(type, "light type") || !d.u8(pad8, "light reserved") || !d.zero16("light reserved") ||
        !d.str(l.name, "light name") || !d.vec3(l.color, "light color") ||
        !d.vec3(l.direction, "light direction") || !d.f32(l.irradiance, "light irradiance") ||
        !d.vec3(l.position, "light position") || !d.f32(l.intensity, "light intensity")) {
      return false;
    }
    if (pad8 != 0) return d.fail("light reserved byte must be zero");
    if (type < 1 || type > 2) return d.fail("light type " + std::to_string(type) + " is not 1..2");
    l.type = static_cast<LightType>(type);
  }
  return d.finish();
}

bool decode_water(ChunkDecoder& d, Water& w) {
  std::uint32_t n = 0;
  if (!d.f32(w.level, "water level") || !d.f32(w.ior, "water ior") ||
      !d.vec3(w.absorption, "water absorption") || !d.u32(w.cells[0], "water cells") ||
      !d.u32(w.cells[1], "water cells")) {
    return false;
  }
  for (float& f : w.extent) {
    if (!d.f32(f, "water extent")) return false;
  }
  if (!d.count(n, kMaxWaves, kWaveRecord, "wave")) return false;
  w.waves.resize(n);
  for (Wave& wave : w.waves) {
    if (!d.f32(wave.amplitude, "wave") || !d.f32(wave.wavelength, "wave") ||
        !d.f32(wave.direction[0], "wave") || !d.f32(wave.direction[1], "wave") ||
        !d.f32(wave.speed, "wave") || !d.f32(wave.phase, "wave")) {
      return false;
    }
  }
  return d.finish();
}

bool decode_camera(ChunkDecoder& d, Camera& c) {
  return d.vec3(c.position, "camera") && d.vec3(c.target, "camera") && d.vec3(c.up, "camera") &&
         d.f32(c.fov_y_deg, "camera") && d.f32(c.near_plane, "camera") &&
         d.f32(c.far_plane, "camera") && d.finish();
}

bool decode_render(ChunkDecoder& d, RenderDefaults& r) {
  if (!d.str(r.preset, "preset name") || !d.u32(r.caustics_map_size, "render defaults") ||
      !d.u32(r.glass_map_size, "render defaults") || !d.u32(r.glass_planes, "render defaults")) {
    return false;
  }
  // The media's pair came later: files without it keep the defaults.
  if (d.remaining() > 0 && (!d.u32(r.volume_photons, "render defaults") || !d.u32(r.volume_grid, "render defaults"))) return false;
  // So did the caustic maps' four.
  if (d.remaining() > 0 && (!d.u32(r.cmap_photons, "render defaults") || !d.u32(r.cmap_map_size, "render defaults") ||
                            !d.u32(r.cmap_adaptive_levels, "render defaults") || !d.u32(r.cmap_photon_budget, "render defaults"))) {
    return false;
  }
  // And the water textures' limit.
  if (d.remaining() > 0 && !d.u32(r.water_texture, "render defaults")) return false;
  // And the dispersive glass's coarse focus windows.
  if (d.remaining() > 0 && !d.u32(r.glass_spectral_coarse, "render defaults")) return false;
  return d.finish();
}

constexpr std::size_t kScatteringRecord = 12 + 4 + 4;

bool decode_scattering(ChunkDecoder& d, Scattering& s, const char* what) {
  std::uint8_t phase = 0, pad = 0;
  if (!d.vec3(s.coefficient, what) || !d.u8(phase, what) || !d.u8(pad, what) || !d.zero16(what) ||
      !d.f32(s.anisotropy, what)) {
    return false;
  }
  if (pad != 0) return d.fail(std::string(what) + ": reserved byte must be zero");
  // validate_scene() names the field of any other value.
  s.phase = static_cast<Phase>(phase);
  return true;
}

bool decode_media(ChunkDecoder& d, SceneDesc& s) {
  std::uint8_t flags = 0, pad = 0;
  if (!d.u8(flags, "media flags") || !d.u8(pad, "media reserved") || !d.zero16("media reserved")) return false;
  if (pad != 0 || (flags & ~(kMediaBox | kMediaWater)) != 0) return d.fail("media flags: unknown bits set");
  if (flags & kMediaBox) {
    Medium& m = s.medium.emplace();
    for (float& f : m.extent) {
      if (!d.f32(f, "medium extent")) return false;
    }
    if (!d.vec3(m.absorption, "medium absorption") || !decode_scattering(d, m.scattering, "medium scattering")) {
      return false;
    }
  }
  if (flags & kMediaWater) {
    if (!s.water) return d.fail("water scattering given but the scene has no 'WATR' chunk");
    if (!decode_scattering(d, s.water->scattering, "water scattering")) return false;
  }
  std::uint32_t n = 0;
  if (!d.count(n, s.objects.size(), 4 + kScatteringRecord, "scattering object")) return false;
  for (std::uint32_t k = 0, prev = 0; k < n; ++k) {
    std::uint32_t obj = 0;
    if (!d.u32(obj, "scattering object index")) return false;
    if (obj >= s.objects.size() || (k > 0 && obj <= prev)) {
      return d.fail("scattering object index " + std::to_string(obj) + " is out of range or out of order");
    }
    prev = obj;
    if (!decode_scattering(d, s.objects[obj].material.scattering, "object scattering")) return false;
  }
  return d.finish();
}

bool decode_mirrors(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.count(n, s.objects.size(), 16, "mirror")) return false;
  std::uint32_t listed = 0;
  for (std::uint32_t k = 0, prev = 0; k < n; ++k) {
    std::uint32_t obj = 0;
    if (!d.u32(obj, "mirror object index")) return false;
    if (obj >= s.objects.size() || (k > 0 && obj <= prev) || !is_mirror(s.objects[obj].role)) {
      return d.fail("mirror object index " + std::to_string(obj) + " is out of range, out of order or not a mirror");
    }
    prev = obj;
    ++listed;
    if (!d.vec3(s.objects[obj].material.reflectance, "mirror reflectance")) return false;
  }
  const auto mirrors = std::count_if(s.objects.begin(), s.objects.end(), [](const Object& o) { return is_mirror(o.role); });
  if (listed != static_cast<std::uint32_t>(mirrors)) {
    return d.fail(std::to_string(listed) + " reflectance records for " + std::to_string(mirrors) + " mirrors");
  }
  return d.finish();
}

bool decode_spots(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.count(n, s.lights.size(), 12, "spot light")) return false;
  if (n == 0) return d.fail("a 'SPOT' chunk lists no spot light");
  for (std::uint32_t k = 0, prev = 0; k < n; ++k) {
    std::uint32_t li = 0;
    if (!d.u32(li, "spot light index")) return false;
    if (li >= s.lights.size() || (k > 0 && li <= prev) || s.lights[li].type != LightType::kPoint) {
      return d.fail("spot light index " + std::to_string(li) + " is out of range, out of order or not a point light");
    }
    prev = li;
    Light& l = s.lights[li];
    l.spot = true;
    if (!d.f32(l.inner_cone, "spot inner cone") || !d.f32(l.outer_cone, "spot outer cone")) return false;
  }
  return d.finish();
}

// n entries of a u32 object index (strictly ascending; its role one that
// `accepts`, which `kind` names in the message), each followed by what
// read(object) decodes (DISP: solid glass; TINT: solid or thin-walled;
// SURF: receivers).
template <class Read>
bool per_object(ChunkDecoder& d, SceneDesc& s, std::uint32_t n, const char* what, bool (*accepts)(Role), const char* kind, Read read) {
  for (std::uint32_t k = 0, prev = 0; k < n; ++k) {
    std::uint32_t obj = 0;
    if (!d.u32(obj, what)) return false;
    if (obj >= s.objects.size() || (k > 0 && obj <= prev) || !accepts(s.objects[obj].role)) {
      return d.fail(std::string(what) + " " + std::to_string(obj) + " is out of range, out of order or not " + kind);
    }
    prev = obj;
    if (!read(s.objects[obj])) return false;
  }
  return true;
}
template <class Read>
bool per_transparent_object(ChunkDecoder& d, SceneDesc& s, std::uint32_t n, const char* what, bool (*accepts)(Role), Read read) {
  return per_object(d, s, n, what, accepts, "transparent", read);
}

bool decode_tints(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.count(n, s.objects.size(), 16, "tinted object")) return false;
  if (n == 0) return d.fail("a 'TINT' chunk lists no tinted object");
  return per_transparent_object(d, s, n, "tinted object index", transmits,
                                [&](Object& o) { return d.vec3(o.material.tint, "tint"); }) &&
         d.finish();
}

bool decode_surfaces(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.count(n, s.objects.size(), 24, "object with a surface")) return false;
  if (n == 0) return d.fail("a 'SURF' chunk lists no object");
  return per_object(d, s, n, "surface object index", [](Role r) { return r == Role::kReceiver; }, "a receiver",
                    [&](Object& o) {
                      Surface& sf = o.material.surface.emplace();
                      return d.f32(sf.metallic, "metallic") && d.f32(sf.roughness, "roughness") && d.vec3(sf.emissive, "emissive");
                    }) &&
         d.finish();
}

// LTTR: u32 count; per solid transparent object that uses an
// earlier object's light-transport tables, in object order: u32 object
// index, u32 the index of the object whose tables it uses
// (Object::tables_from; validate_scene checks that it may).
bool shares_tables(const SceneDesc& s) {
  return std::any_of(s.objects.begin(), s.objects.end(), [](const Object& o) { return o.tables_from.has_value(); });
}
std::vector<std::uint8_t> encode_table_sharing(const SceneDesc& s) {
  ByteWriter w;
  w.u32(static_cast<std::uint32_t>(std::count_if(s.objects.begin(), s.objects.end(), [](const Object& o) { return o.tables_from.has_value(); })));
  for (std::uint32_t i = 0; i < s.objects.size(); ++i) {
    if (!s.objects[i].tables_from) continue;
    w.u32(i);
    w.u32(*s.objects[i].tables_from);
  }
  return w.take();
}
bool decode_table_sharing(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.count(n, s.objects.size(), 8, "object sharing tables")) return false;
  if (n == 0) return d.fail("an 'LTTR' chunk lists no object");
  return per_transparent_object(d, s, n, "object sharing tables", is_transparent,
                                [&](Object& o) {
                                  std::uint32_t from = 0;
                                  if (!d.u32(from, "object whose tables it uses")) return false;
                                  o.tables_from = from;
                                  return true;
                                }) &&
         d.finish();
}

// A texture record of TEXR and TEXM: u32 image index, u8 projection, u8
// wrap s, u8 wrap t, u8 zero, 6 x f32 transform.
bool decode_texture_ref(ChunkDecoder& d, AlbedoTexture& t) {
  std::uint8_t projection = 0, wrap_s = 0, wrap_t = 0, zero = 0;
  if (!d.u32(t.image, "texture image index") || !d.u8(projection, "texture projection") || !d.u8(wrap_s, "texture wrap s") ||
      !d.u8(wrap_t, "texture wrap t") || !d.u8(zero, "texture reserved byte")) {
    return false;
  }
  t.projection = static_cast<TextureProjection>(projection);
  t.wrap_s = static_cast<TextureWrap>(wrap_s);
  t.wrap_t = static_cast<TextureWrap>(wrap_t);
  for (float& f : t.transform) {
    if (!d.f32(f, "texture transform")) return false;
  }
  return true;
}

bool decode_textures(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.count(n, 65536, 16, "texture image")) return false;
  s.images.resize(n);
  for (TextureImage& im : s.images) {
    std::uint32_t packed_size = 0;
    std::span<const std::uint8_t> packed;
    if (!d.str(im.source, "image source") || !d.u32(im.width, "image width") || !d.u32(im.height, "image height")) return false;
    if (im.width < 1 || im.width > kMaxTextureSize || im.height < 1 || im.height > kMaxTextureSize) {
      return d.fail("image '" + im.source + "' is " + std::to_string(im.width) + " x " + std::to_string(im.height) +
                    " texels (1.." + std::to_string(kMaxTextureSize) + " a side)");
    }
    if (!d.u32(packed_size, "image data size") || !d.span(packed, packed_size, "image data")) return false;
    const std::size_t texels = std::size_t{im.width} * im.height;
    if (!cxb::detail::zstd_decompress_exact(d, packed, 3 * texels, "image data", std::to_string(texels) + " RGB texels", im.rgb)) return false;
  }
  std::uint32_t m = 0;
  if (!d.count(m, s.objects.size(), 36, "textured object")) return false;
  for (std::uint32_t k = 0, prev = 0; k < m; ++k) {
    std::uint32_t obj = 0;
    AlbedoTexture t;
    if (!d.u32(obj, "textured object index")) return false;
    if (obj >= s.objects.size() || (k > 0 && obj <= prev)) {
      return d.fail("textured object index " + std::to_string(obj) + " is out of range or out of order");
    }
    prev = obj;
    if (!decode_texture_ref(d, t)) return false;
    s.objects[obj].material.albedo_texture = t;  // values checked by validate_scene
  }
  return d.finish();
}

bool decode_surface_maps(ChunkDecoder& d, SceneDesc& s) {
  std::uint32_t n = 0;
  if (!d.count(n, s.images.size(), 8, "image alpha plane")) return false;
  for (std::uint32_t k = 0, prev = 0; k < n; ++k) {
    std::uint32_t i = 0, packed_size = 0;
    std::span<const std::uint8_t> packed;
    if (!d.u32(i, "alpha plane's image index")) return false;
    if (i >= s.images.size() || (k > 0 && i <= prev)) {
      return d.fail("alpha plane's image index " + std::to_string(i) + " is out of range or out of order (a 'TEXR' chunk lists " +
                    std::to_string(s.images.size()) + " images)");
    }
    prev = i;
    TextureImage& im = s.images[i];
    if (!d.u32(packed_size, "alpha data size") || !d.span(packed, packed_size, "alpha data")) return false;
    const std::size_t texels = std::size_t{im.width} * im.height;
    if (!cxb::detail::zstd_decompress_exact(d, packed, texels, "alpha data", std::to_string(texels) + " alpha texels", im.alpha)) return false;
  }
  std::uint32_t m = 0;
  if (!d.count(m, s.objects.size(), 24, "object with maps")) return false;
  if (n == 0 && m == 0) return d.fail("a 'TEXM' chunk lists no alpha plane and no object");
  return per_object(d, s, m, "maps' object index", [](Role r) { return r == Role::kReceiver; }, "a receiver",
                    [&](Object& o) {
                      SurfaceMaps& sm = o.material.maps.emplace();
                      std::uint8_t mode = 0, mask = 0;
                      std::uint16_t zero = 0;
                      if (!d.u8(mode, "alpha mode") || !d.u8(mask, "map mask") || !d.u16(zero, "maps' reserved bytes") ||
                          !d.f32(sm.alpha, "alpha") || !d.f32(sm.alpha_cutoff, "alpha cut-off") || !d.f32(sm.normal_scale, "normal scale") ||
                          !d.f32(sm.occlusion_strength, "occlusion strength")) {
                        return false;
                      }
                      if (mode > 2) return d.fail("alpha mode " + std::to_string(mode) + " (0 opaque, 1 mask, 2 blend)");
                      if (mask > 15) return d.fail("map mask " + std::to_string(mask) + " sets bits above 3");
                      if (zero != 0) return d.fail("maps' reserved bytes are not zero");
                      sm.alpha_mode = static_cast<AlphaMode>(mode);
                      const std::array<std::optional<MapTexture>*, 4> slots{&sm.metallic_roughness, &sm.normal, &sm.occlusion, &sm.emissive};
                      for (std::size_t k = 0; k < slots.size(); ++k) {
                        if (!(mask & (1u << k))) continue;
                        if (!decode_texture_ref(d, slots[k]->emplace())) return false;
                      }
                      return true;  // values checked by validate_scene
                    }) &&
         d.finish();
}

bool decode_dispersion(ChunkDecoder& d, SceneDesc& s) {
  float water = 0;
  if (!d.f32(water, "water dispersion")) return false;
  if (s.water) {
    s.water->dispersion = water;
  } else if (water != 0) {
    return d.fail("water dispersion without a 'WATR' chunk");
  }
  std::uint32_t n = 0;
  if (!d.count(n, s.objects.size(), 8, "dispersive object")) return false;
  return per_transparent_object(d, s, n, "dispersive object index", is_transparent,
                                [&](Object& o) { return d.f32(o.material.dispersion, "object dispersion"); }) &&
         d.finish();
}

Error container_error(const std::string& msg) { return make_error(ErrorCode::kContainer, msg); }

}  // namespace

std::vector<std::uint8_t> encode_scene(const SceneDesc& scene,
                                       const std::vector<std::vector<std::uint8_t>>& draco_meshes,
                                       const std::vector<LevelMap>& level_maps,
                                       const std::vector<ObjectBox>& boxes,
                                       const std::vector<LightTransportTable>& tables,
                                       const std::vector<IndexGrid>& index_grids) {
  cxb::ContainerWriter w;
  w.add_chunk(cxb::kTagScene, cxb::kChunkRequired, encode_scene_chunk(scene));
  w.add_chunk(cxb::kTagObjects, cxb::kChunkRequired, encode_objects(scene));
  w.add_chunk(cxb::kTagLights, cxb::kChunkRequired, encode_lights(scene));
  if (scene.water) w.add_chunk(cxb::kTagWater, cxb::kChunkRequired, encode_water(*scene.water));
  if (scene.medium || scene_scatters(scene)) w.add_chunk(cxb::kTagMedia, cxb::kChunkRequired, encode_media(scene));
  if (has_mirrors(scene)) w.add_chunk(cxb::kTagMirrors, cxb::kChunkRequired, encode_mirrors(scene));
  if (scene_disperses(scene)) w.add_chunk(cxb::kTagDispersion, cxb::kChunkRequired, encode_dispersion(scene));
  if (has_spots(scene)) w.add_chunk(cxb::kTagSpots, cxb::kChunkRequired, encode_spots(scene));
  if (has_tints(scene)) w.add_chunk(cxb::kTagTint, cxb::kChunkRequired, encode_tints(scene));
  if (shares_tables(scene)) w.add_chunk(cxb::kTagTransportShared, cxb::kChunkRequired, encode_table_sharing(scene));
  // Optional: a reader that predates it draws the receivers untextured; the
  // light does not depend on it.
  if (has_textures(scene)) w.add_chunk(cxb::kTagTextures, 0, encode_textures(scene));
  // Optional: a reader that predates it draws the receivers Lambertian.
  if (has_surfaces(scene)) w.add_chunk(cxb::kTagSurfaces, 0, encode_surfaces(scene));
  // Optional: a reader that predates it draws the receivers without their
  // maps, opaque.
  if (has_surface_maps(scene)) w.add_chunk(cxb::kTagSurfaceMaps, 0, encode_surface_maps(scene));
  if (scene.camera) w.add_chunk(cxb::kTagCamera, 0, encode_camera(*scene.camera));
  if (scene.render) w.add_chunk(cxb::kTagRender, 0, encode_render(*scene.render));
  for (const auto& m : draco_meshes) w.add_chunk(cxb::kTagMesh, cxb::kChunkRequired, m);
  if (!boxes.empty()) w.add_chunk(cxb::kTagObjectBoxes, 0, encode_object_boxes(boxes));
  for (const auto& lm : level_maps) w.add_chunk(cxb::kTagLevelMap, cxb::kChunkRequired, encode_level_map(lm));
  for (const auto& t : tables) {
    w.add_chunk(t.wavelength_nm > 0 ? cxb::kTagSpectralTransport : cxb::kTagTransport, cxb::kChunkRequired, encode_transport_table(t));
  }
  // Optional: a reader that predates it drops triangles torn between path
  // classes instead of cutting them at the switch.
  for (const auto& t : tables) {
    if (!t.switches.empty()) w.add_chunk(cxb::kTagTransportSwitches, 0, encode_transport_switches(t));
  }
  for (const auto& g : index_grids) w.add_chunk(cxb::kTagIndexGrid, cxb::kChunkRequired, encode_index_grid(g));
  return w.finish();
}

Result<DecodedScene> decode_scene(const cxb::Container& c) {
  DecodedScene out;
  SceneDesc& s = out.scene;

  // Singleton chunks: exactly once (required) or at most once (optional).
  auto single = [&](cxb::Tag tag, bool required) -> Result<std::optional<std::size_t>> {
    const auto idx = c.find(tag);
    if (idx.size() > 1) {
      return container_error("chunk '" + tag.str() + "' appears " + std::to_string(idx.size()) +
                             " times; at most once is allowed");
    }
    if (idx.empty()) {
      if (required) return container_error("required chunk '" + tag.str() + "' is missing");
      return std::optional<std::size_t>{};
    }
    return std::optional<std::size_t>{idx[0]};
  };
  auto run = [&](cxb::Tag tag, std::size_t index, auto&& decode) -> Status {
    ChunkDecoder d(tag, c.payload(index));
    if (!decode(d)) return d.error();
    return Status::success();
  };

  auto scne = single(cxb::kTagScene, true);
  if (!scne) return scne.error();
  CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagScene, **scne, [&](ChunkDecoder& d) { return decode_scene_chunk(d, s); }));
  auto objs = single(cxb::kTagObjects, true);
  if (!objs) return objs.error();
  CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagObjects, **objs, [&](ChunkDecoder& d) { return decode_objects(d, s); }));
  auto lght = single(cxb::kTagLights, true);
  if (!lght) return lght.error();
  CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagLights, **lght, [&](ChunkDecoder& d) { return decode_lights(d, s); }));
  auto watr = single(cxb::kTagWater, false);
  if (!watr) return watr.error();
  if (*watr) {
    s.water.emplace();
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagWater, **watr, [&](ChunkDecoder& d) { return decode_water(d, *s.water); }));
  }
  // After WATR and OBJS: it refers to both.
  auto mdia = single(cxb::kTagMedia, false);
  if (!mdia) return mdia.error();
  if (*mdia) {
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagMedia, **mdia, [&](ChunkDecoder& d) { return decode_media(d, s); }));
  }
  auto mirr = single(cxb::kTagMirrors, false);
  if (!mirr) return mirr.error();
  if (*mirr) {
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagMirrors, **mirr, [&](ChunkDecoder& d) { return decode_mirrors(d, s); }));
  } else if (has_mirrors(s)) {
    return container_error("the scene has mirrors but no 'MIRR' chunk");
  }
  auto disp = single(cxb::kTagDispersion, false);
  if (!disp) return disp.error();
  if (*disp) {
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagDispersion, **disp, [&](ChunkDecoder& d) { return decode_dispersion(d, s); }));
  }
  auto spot = single(cxb::kTagSpots, false);
  if (!spot) return spot.error();
  if (*spot) {
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagSpots, **spot, [&](ChunkDecoder& d) { return decode_spots(d, s); }));
  }
  auto tint = single(cxb::kTagTint, false);
  if (!tint) return tint.error();
  if (*tint) {
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagTint, **tint, [&](ChunkDecoder& d) { return decode_tints(d, s); }));
  }
  auto lttr = single(cxb::kTagTransportShared, false);
  if (!lttr) return lttr.error();
  if (*lttr) {
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagTransportShared, **lttr, [&](ChunkDecoder& d) { return decode_table_sharing(d, s); }));
  }
  auto texr = single(cxb::kTagTextures, false);
  if (!texr) return texr.error();
  if (*texr) {
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagTextures, **texr, [&](ChunkDecoder& d) { return decode_textures(d, s); }));
  }
  auto surf = single(cxb::kTagSurfaces, false);
  if (!surf) return surf.error();
  if (*surf) {
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagSurfaces, **surf, [&](ChunkDecoder& d) { return decode_surfaces(d, s); }));
  }
  auto texm = single(cxb::kTagSurfaceMaps, false);
  if (!texm) return texm.error();
  if (*texm) {
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagSurfaceMaps, **texm, [&](ChunkDecoder& d) { return decode_surface_maps(d, s); }));
  }
  auto camr = single(cxb::kTagCamera, false);
  if (!camr) return camr.error();
  if (*camr) {
    s.camera.emplace();
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagCamera, **camr, [&](ChunkDecoder& d) { return decode_camera(d, *s.camera); }));
  }
  auto rndr = single(cxb::kTagRender, false);
  if (!rndr) return rndr.error();
  if (*rndr) {
    s.render.emplace();
    CAUSTIX_RETURN_IF_ERROR(run(cxb::kTagRender, **rndr, [&](ChunkDecoder& d) { return decode_render(d, *s.render); }));
  }

  const auto meshes = c.find(cxb::kTagMesh);
  if (meshes.size() != s.meshes.size()) {
    return container_error("chunk 'SCNE' lists " + std::to_string(s.meshes.size()) +
                           " meshes but the file has " + std::to_string(meshes.size()) +
                           " 'MESH' chunks");
  }
  for (std::size_t i : meshes) out.draco_meshes.push_back(c.payload(i));

  if (auto issue = validate_scene(s)) {
    return container_error("scene chunks: " + issue->pointer + ": " + issue->message);
  }

  auto obbs = single(cxb::kTagObjectBoxes, false);
  if (!obbs) return obbs.error();
  if (*obbs) {
    auto boxes = decode_object_boxes(c.payload(**obbs), s);
    if (!boxes) return boxes.error();
    out.boxes = std::move(*boxes);
  }
  for (std::size_t i : c.find(cxb::kTagLevelMap)) {
    auto lm = decode_level_map(c.payload(i), s);
    if (!lm) return Error{lm.error().code, "chunk " + std::to_string(i) + ": " + lm.error().message};
    for (const LevelMap& prev : out.level_maps) {
      if (prev.object == lm->object && prev.light == lm->light) {
        return container_error("chunk " + std::to_string(i) + " 'LMAP': a second level map for object " +
                               std::to_string(lm->object) + " and light " + std::to_string(lm->light));
      }
    }
    out.level_maps.push_back(std::move(*lm));
  }
  // Exactly one table per transparent object that does not use another's
  // (LTTR), in object order; it carries the material's absorption.
  std::vector<bool> has_table(s.objects.size(), false);
  for (std::size_t i : c.find(cxb::kTagTransport)) {
    auto t = decode_transport_table(c.payload(i), s);
    if (!t) return Error{t.error().code, "chunk " + std::to_string(i) + ": " + t.error().message};
    if (has_table[t->object] || (!out.transport_tables.empty() && out.transport_tables.back().object > t->object)) {
      return container_error("chunk " + std::to_string(i) + " 'LTTB': tables must be one per transparent object, in object order");
    }
    if (const auto from = s.objects[t->object].tables_from) {
      return container_error("chunk " + std::to_string(i) + " 'LTTB': object '" + s.objects[t->object].name + "' uses object '" +
                             s.objects[*from].name + "''s tables ('LTTR') and may not have its own");
    }
    has_table[t->object] = true;
    s.objects[t->object].material.absorption = t->absorption;
    out.transport_tables.push_back(std::move(*t));
  }
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    if (is_transparent(s.objects[i].role) && !has_table[i] && !s.objects[i].tables_from) {
      return container_error("transparent object '" + s.objects[i].name + "' has no 'LTTB' light-transport table");
    }
    if (const auto from = s.objects[i].tables_from) s.objects[i].material.absorption = s.objects[*from].material.absorption;
  }
  // Tables at other wavelengths: dispersive objects only, by
  // object, then by strictly ascending wavelength; each as its object's
  // LTTB in everything but the index.
  for (std::size_t i : c.find(cxb::kTagSpectralTransport)) {
    auto t = decode_transport_table(c.payload(i), s, true);
    if (!t) return Error{t.error().code, "chunk " + std::to_string(i) + ": " + t.error().message};
    const LightTransportTable* prev = out.spectral_tables.empty() ? nullptr : &out.spectral_tables.back();
    if (prev && (prev->object > t->object || (prev->object == t->object && prev->wavelength_nm >= t->wavelength_nm))) {
      return container_error("chunk " + std::to_string(i) + " 'LTTS': tables must be in object order, then in ascending wavelength");
    }
    if (s.objects[t->object].tables_from) {
      return container_error("chunk " + std::to_string(i) + " 'LTTS': object '" + s.objects[t->object].name +
                             "' uses another object's tables ('LTTR') and may not have its own");
    }
    const LightTransportTable* base = nullptr;
    for (const LightTransportTable& b : out.transport_tables) base = b.object == t->object ? &b : base;
    if (!base || base->resolution != t->resolution || base->max_bounces != t->max_bounces || base->vertex_count != t->vertex_count ||
        base->absorption != t->absorption) {
      return container_error("chunk " + std::to_string(i) + " 'LTTS': its resolution, bounces, vertex count or absorption differ from object '" +
                             s.objects[t->object].name + "''s 'LTTB' table");
    }
    ++s.objects[t->object].material.spectral_tables;
    out.spectral_tables.push_back(std::move(*t));
  }
  for (Object& o : s.objects) {
    if (o.tables_from) o.material.spectral_tables = s.objects[*o.tables_from].material.spectral_tables;
  }
  // Where the tables' path classes switch: at most one LTTW per
  // table, naming it by object and wavelength.
  for (std::size_t i : c.find(cxb::kTagTransportSwitches)) {
    std::vector<LightTransportTable*> tables;
    for (auto& t : out.transport_tables) tables.push_back(&t);
    for (auto& t : out.spectral_tables) tables.push_back(&t);
    const Status st = decode_transport_switches(c.payload(i), tables);
    if (!st) return Error{st.error().code, "chunk " + std::to_string(i) + ": " + st.error().message};
  }
  // Index grids: in a scene that scatters, exactly one per transparent
  // object, in object order; none otherwise.
  const bool scatters = scene_scatters(s);
  std::size_t next = 0;
  for (std::size_t i : c.find(cxb::kTagIndexGrid)) {
    auto g = decode_index_grid(c.payload(i), s);
    if (!g) return Error{g.error().code, "chunk " + std::to_string(i) + ": " + g.error().message};
    while (next < s.objects.size() && !is_transparent(s.objects[next].role)) ++next;
    if (!scatters || g->object != next) {
      return container_error("chunk " + std::to_string(i) + " 'IGRD': index grids must be one per transparent object, in object order, "
                             "and only in a scene that scatters");
    }
    ++next;
    out.index_grids.push_back(std::move(*g));
  }
  while (next < s.objects.size() && !is_transparent(s.objects[next].role)) ++next;
  if (scatters && next < s.objects.size()) {
    return container_error("transparent object '" + s.objects[next].name + "' of a scene that scatters has no 'IGRD' index grid");
  }
  return out;
}

}  // namespace caustix
