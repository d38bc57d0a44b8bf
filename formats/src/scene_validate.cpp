// The value rules of a scene: one place, used by the JSON front end (which
// turns the JSON pointer into line and column) and by the .cxb decoder.

#include <cfloat>
#include <cmath>
#include <set>

#include "caustix/formats/scene.h"
#include "caustix/formats/spectrum.h"

namespace caustix {
namespace {

bool finite(float v) { return std::isfinite(v); }
bool finite(const Vec3f& v) { return finite(v[0]) && finite(v[1]) && finite(v[2]); }
float length(const Vec3f& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

struct Checker {
  std::optional<ValidationIssue> issue;
  // Records the first failure; returns `ok` so checks can be chained.
  bool expect(bool ok, const std::string& pointer, const std::string& message) {
    if (!ok && !issue) issue = ValidationIssue{pointer, message};
    return ok;
  }
  void finite_vec(const Vec3f& v, const std::string& p) { expect(finite(v), p, "must be finite numbers"); }
  void range(float v, float lo, float hi, const std::string& p, const std::string& what) {
    expect(finite(v) && v >= lo && v <= hi, p, what);
  }
  void coefficients(const Vec3f& v, const std::string& p) {
    for (float k : v) range(k, 0.0f, kMaxCoefficient, p, "each component must be in [0, 10^6] per metre");
  }
  // `p` is the object holding "scattering", "phase" and "anisotropy".
  void scattering(const Scattering& s, const std::string& p) {
    coefficients(s.coefficient, p + "/scattering");
    expect(s.phase == Phase::kIsotropic || s.phase == Phase::kSchlick, p + "/phase",
           "must be \"isotropic\" or \"schlick\"");
    // |k| = 1 makes the Schlick lobe a delta (p(0) = (1 + k) / (4 pi (1 - k))).
    expect(finite(s.anisotropy) && s.anisotropy > -1.0f && s.anisotropy < 1.0f, p + "/anisotropy",
           "must be in (-1, 1)");
    expect(s.phase == Phase::kSchlick || s.anisotropy == 0.0f, p + "/anisotropy",
           "needs \"phase\": \"schlick\"");
  }
};

// A transform is degenerate relative to its own scale, never by an absolute
// determinant: KHR_mesh_quantization files carry node scales of 1e-6 over
// integer positions and centimetre exports 1e-4, and both are as regular
// as a unit scale. The upper 3x3's columns span a parallelepiped; it is
// degenerate when its volume is under 1e-6 of the product of the columns'
// lengths (one direction flattened a million times more than the others:
// the mesh's own extent collapses along it) or a column is shorter than
// the smallest normal float. In double: (1e-6)^3 is far below float range.
bool is_degenerate(const Mat4f& m) {
  double col[3][3], len[3];
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) col[c][r] = m[c * 4 + r];
    len[c] = std::sqrt(col[c][0] * col[c][0] + col[c][1] * col[c][1] + col[c][2] * col[c][2]);
    if (!(len[c] >= FLT_MIN)) return true;
  }
  const double det = col[0][0] * (col[1][1] * col[2][2] - col[2][1] * col[1][2]) -
                     col[1][0] * (col[0][1] * col[2][2] - col[2][1] * col[0][2]) +
                     col[2][0] * (col[0][1] * col[1][2] - col[1][1] * col[0][2]);
  return !(std::fabs(det) > 1e-6 * len[0] * len[1] * len[2]);
}

}  // namespace

bool is_similarity(const Mat4f& m) {
  const Vec3f c[3] = {{m[0], m[1], m[2]}, {m[4], m[5], m[6]}, {m[8], m[9], m[10]}};
  const float l0 = length(c[0]);
  if (!(l0 > 0) || !finite(l0)) return false;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(length(c[i]) - l0) > 1e-4f * l0) return false;
    for (int j = i + 1; j < 3; ++j) {
      const float d = c[i][0] * c[j][0] + c[i][1] * c[j][1] + c[i][2] * c[j][2];
      if (std::fabs(d) > 1e-4f * l0 * l0) return false;
    }
  }
  return true;
}

std::optional<ValidationIssue> validate_scene(const SceneDesc& s, bool check_meshes) {
  Checker c;
  c.expect(s.name.size() <= kMaxNameLength, "/name", "longer than 4096 bytes");
  c.expect(!s.objects.empty(), "/objects", "the scene needs at least one object");
  c.expect(s.objects.size() <= kMaxObjects, "/objects", "more than 65536 objects");
  c.expect(s.lights.size() <= kMaxLights, "/lights", "more than 4096 lights");

  for (std::size_t i = 0; check_meshes && i < s.meshes.size(); ++i) {
    const MeshInfo& m = s.meshes[i];
    const std::string p = "/meshes/" + std::to_string(i);
    c.expect(m.vertex_count >= 3 && m.vertex_count <= kMaxMeshVertices, p + "/vertex_count",
             "must be 3.." + std::to_string(kMaxMeshVertices));
    c.expect(m.triangle_count >= 1 && m.triangle_count <= 2 * kMaxMeshVertices, p + "/triangle_count",
             "must be at least 1 and at most twice the vertex limit");
    c.expect(m.position_bits >= 1 && m.position_bits <= 30, p + "/position_bits", "must be 1..30");
    c.expect(m.normal_bits >= 1 && m.normal_bits <= 30, p + "/normal_bits", "must be 1..30");
    c.expect(finite(m.bounds_min) && finite(m.bounds_max), p + "/bounds", "must be finite");
  }

  for (std::size_t i = 0; i < s.images.size(); ++i) {
    const TextureImage& im = s.images[i];
    const std::string p = "/images/" + std::to_string(i);
    c.expect(im.width >= 1 && im.width <= kMaxTextureSize && im.height >= 1 && im.height <= kMaxTextureSize, p,
             "must be 1.." + std::to_string(kMaxTextureSize) + " texels a side");
    c.expect(im.rgb.size() == std::size_t{im.width} * im.height * 3, p, "holds " + std::to_string(im.rgb.size()) + " bytes, not width x height x 3");
    c.expect(im.alpha.empty() || im.alpha.size() == std::size_t{im.width} * im.height, p + "/alpha",
             "holds " + std::to_string(im.alpha.size()) + " bytes, not width x height");
  }
  // A texture record (TEXR's and TEXM's).
  const auto check_texture = [&](const MapTexture& t, const std::string& tp) {
    c.expect(!check_meshes || t.image < s.images.size(), tp, "image " + std::to_string(t.image) + " is out of range");
    c.expect(t.projection == TextureProjection::kUv || t.projection == TextureProjection::kBox, tp + "/projection", "must be uv or box");
    for (TextureWrap w : {t.wrap_s, t.wrap_t}) {
      c.expect(w == TextureWrap::kRepeat || w == TextureWrap::kClamp || w == TextureWrap::kMirror, tp + "/wrap", "must be repeat, clamp or mirror");
    }
    bool finite_transform = true;
    for (float f : t.transform) finite_transform = finite_transform && finite(f) && std::fabs(f) < 1e6f;
    c.expect(finite_transform, tp + "/transform", "must be finite numbers below 1e6 in magnitude");
  };

  std::set<std::string> names;
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const Object& o = s.objects[i];
    const std::string p = "/objects/" + std::to_string(i);
    c.expect(!o.name.empty(), p + "/name", "must not be empty");
    c.expect(names.insert(o.name).second, p + "/name", "'" + o.name + "' is used by an earlier object");
    c.expect(o.mesh_index < s.meshes.size(), p + "/mesh",
             "mesh index " + std::to_string(o.mesh_index) + " is out of range");
    c.expect(o.role == Role::kReceiver || o.role == Role::kTransparent || o.role == Role::kBoth || o.role == Role::kMirror ||
                 o.role == Role::kThin,
             p + "/role", "must be receiver, transparent, both, mirror or thin");
    if (is_mirror(o.role)) {
      for (float r : o.material.reflectance) {
        c.range(r, 0.0f, 1.0f, p + "/material/reflectance", "each component must be in [0, 1]");
      }
      c.expect(!o.material.transparent, p + "/material", "a mirror cannot have a transparent material");
    }
    for (float a : o.material.albedo) {
      c.range(a, 0.0f, 1.0f, p + "/material/albedo", "each component must be in [0, 1]");
    }
    c.expect(!is_tinted(o.material) || transmits(o.role), p + "/material/tint", "only a transparent object has a tint");
    if (const auto& sf = o.material.surface) {
      c.expect(o.role == Role::kReceiver, p + "/material", "only a receiver has metallic, roughness or emissive");
      c.range(sf->metallic, 0.0f, 1.0f, p + "/material/metallic", "must be in [0, 1]");
      c.range(sf->roughness, 0.0f, 1.0f, p + "/material/roughness", "must be in [0, 1]");
      for (float e : sf->emissive) c.range(e, 0.0f, 1e6f, p + "/material/emissive", "each component must be in [0, 1e6]");
    }
    if (const auto& t = o.material.albedo_texture) {
      const std::string tp = p + "/material/albedo_texture";
      c.expect(o.role == Role::kReceiver, tp, "only a receiver takes an albedo texture");
      check_texture(*t, tp);
    }
    if (const auto& m = o.material.maps) {
      const std::string mp = p + "/material";
      c.expect(o.role == Role::kReceiver, mp, "only a receiver has maps or an alpha mode");
      c.expect(m->alpha_mode == AlphaMode::kOpaque || m->alpha_mode == AlphaMode::kMask || m->alpha_mode == AlphaMode::kBlend,
               mp + "/alpha_mode", "must be opaque, mask or blend");
      c.range(m->alpha, 0.0f, 1.0f, mp + "/alpha", "must be in [0, 1]");
      c.range(m->alpha_cutoff, 0.0f, 1.0f, mp + "/alpha_cutoff", "must be in [0, 1]");
      c.range(m->normal_scale, -1000.0f, 1000.0f, mp + "/normal_scale", "must be in [-1000, 1000]");
      c.range(m->occlusion_strength, 0.0f, 1.0f, mp + "/occlusion_strength", "must be in [0, 1]");
      for (const auto& [slot, name] : {std::pair{&m->metallic_roughness, "metallic_roughness_texture"}, std::pair{&m->normal, "normal_texture"},
                                       std::pair{&m->occlusion, "occlusion_texture"}, std::pair{&m->emissive, "emissive_texture"}}) {
        if (*slot) check_texture(**slot, mp + "/" + name);
      }
    }
    if (o.material.transparent || transmits(o.role)) {
      c.range(o.material.ior, 1.0f, kMaxIor, p + "/material/ior", "must be in [1, 10]");
      c.range(o.material.dispersion, 0.0f, kMaxDispersion, p + "/material/dispersion", "must be in [0, 20] (20 / Abbe number)");
      c.expect(o.material.transparent, p + "/material",
               "an object with role transparent, both or thin needs a transparent material");
      // A thin wall has no inside: nothing to absorb, scatter or disperse in.
      if (is_thin(o.role)) {
        c.expect(o.material.dispersion == 0, p + "/material/dispersion", "a thin-walled object does not disperse (it has no inside)");
        c.expect(o.material.absorption == Vec3f{0, 0, 0}, p + "/material/absorption", "a thin-walled object has no inside to absorb in; use tint");
        c.expect(!o.material.scattering.scatters(), p + "/material/scattering", "a thin-walled object has no inside to scatter in");
      }
      c.coefficients(o.material.absorption, p + "/material/absorption");
      for (float t : o.material.tint) c.range(t, 0.0f, 1.0f, p + "/material/tint", "each component must be in [0, 1]");
      c.scattering(o.material.scattering, p + "/material");
      // Light-transport tables are baked in object space: refraction angles
      // survive rotation, translation and uniform scale, not shear or
      // non-uniform scale.
      if (is_transparent(o.role)) {
        c.expect(is_similarity(o.transform), p + "/transform",
                 "a transparent object's transform must be a rotation, translation and uniform scale");
      }
    }
    if (o.tables_from) {
      const std::uint32_t from = *o.tables_from;
      c.expect(from < i && can_share_tables(s.objects[from], o), p + "/tables_from",
               "object " + std::to_string(from) + " is not an earlier solid transparent object with its own tables on the same mesh, "
               "with the same IOR, dispersion and absorption");
    }
    bool finite_transform = true;
    for (float f : o.transform) finite_transform = finite_transform && finite(f);
    c.expect(finite_transform, p + "/transform", "must be finite numbers");
    c.expect(o.transform[3] == 0 && o.transform[7] == 0 && o.transform[11] == 0 && o.transform[15] == 1,
             p + "/transform", "must be affine (last row 0 0 0 1)");
    c.expect(!finite_transform || !is_degenerate(o.transform), p + "/transform",
             "is degenerate: it flattens the object (a zero scale, or one direction scaled under 1e-6 of another)");
  }

  for (std::size_t i = 0; i < s.lights.size(); ++i) {
    const Light& l = s.lights[i];
    const std::string p = "/lights/" + std::to_string(i);
    c.expect(l.type == LightType::kDirectional || l.type == LightType::kPoint, p + "/type",
             "must be directional or point");
    c.expect(finite(l.color) && l.color[0] >= 0 && l.color[1] >= 0 && l.color[2] >= 0, p + "/color",
             "components must be finite and >= 0");
    if (l.type == LightType::kDirectional) {
      c.expect(finite(l.direction) && length(l.direction) > 1e-6f, p + "/direction",
               "must be a finite, non-zero vector");
      c.range(l.irradiance, 0.0f, 1e9f, p + "/irradiance", "must be in [0, 1e9] W/m^2");
    } else {
      c.finite_vec(l.position, p + "/position");
      c.range(l.intensity, 0.0f, 1e9f, p + "/intensity", "must be in [0, 1e9] W/sr");
    }
    if (l.spot) {
      c.expect(l.type == LightType::kPoint, p + "/type", "only a point light can have a cone");
      c.expect(finite(l.direction) && length(l.direction) > 1e-6f, p + "/direction",
               "a spot light's axis must be a finite, non-zero vector");
      c.range(l.outer_cone, 1e-4f, 1.5707964f, p + "/outer_cone_deg", "must be in (0, 90] degrees");
      c.expect(finite(l.inner_cone) && l.inner_cone >= 0.0f && l.inner_cone < l.outer_cone, p + "/inner_cone_deg",
               "must be >= 0 and less than the outer cone");
    }
  }

  if (s.water) {
    const Water& w = *s.water;
    c.expect(finite(w.level), "/water/level", "must be finite");
    c.range(w.ior, 1.0f, kMaxIor, "/water/ior", "must be in [1, 10]");
    c.range(w.dispersion, 0.0f, kMaxDispersion, "/water/dispersion", "must be in [0, 20] (20 / Abbe number)");
    c.coefficients(w.absorption, "/water/absorption");
    c.scattering(w.scattering, "/water");
    for (std::uint32_t n : w.cells) {
      c.expect(n >= 1 && n <= kMaxWaterCells, "/water/grid/cells",
               "each must be 1.." + std::to_string(kMaxWaterCells));
    }
    bool extent_ok = true;
    for (float f : w.extent) extent_ok = extent_ok && finite(f);
    c.expect(extent_ok && w.extent[2] > w.extent[0] && w.extent[3] > w.extent[1], "/water/grid/extent",
             "must be finite [x0, z0, x1, z1] with x1 > x0 and z1 > z0");
    c.expect(w.waves.size() <= kMaxWaves, "/water/waves", "more than 256 waves");
    for (std::size_t i = 0; i < w.waves.size(); ++i) {
      const Wave& wave = w.waves[i];
      const std::string p = "/water/waves/" + std::to_string(i);
      c.range(wave.amplitude, 0.0f, 1e4f, p + "/amplitude", "must be in [0, 1e4] m");
      c.range(wave.wavelength, 1e-4f, 1e6f, p + "/wavelength", "must be in [1e-4, 1e6] m");
      c.expect(finite(wave.direction[0]) && finite(wave.direction[1]) &&
                   std::hypot(wave.direction[0], wave.direction[1]) > 1e-6f,
               p + "/direction", "must be a finite, non-zero [x, z] vector");
      c.expect(finite(wave.speed), p + "/speed", "must be finite");
      c.expect(finite(wave.phase), p + "/phase", "must be finite");
    }
  }

  if (s.medium) {
    const Medium& m = *s.medium;
    bool extent_ok = true;
    for (float f : m.extent) extent_ok = extent_ok && finite(f) && std::fabs(f) <= 1e6f;
    c.expect(extent_ok && m.extent[3] > m.extent[0] && m.extent[4] > m.extent[1] && m.extent[5] > m.extent[2],
             "/medium/extent", "must be finite [x0, y0, z0, x1, y1, z1] within 10^6 m with x1 > x0, y1 > y0, z1 > z0");
    c.coefficients(m.absorption, "/medium/absorption");
    c.scattering(m.scattering, "/medium");
  }
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const Material& m = s.objects[i].material;
    c.expect(!m.scattering.scatters() || m.transparent, "/objects/" + std::to_string(i) + "/material/scattering",
             "only a transparent material scatters inside");
  }

  if (s.camera) {
    const Camera& cam = *s.camera;
    c.finite_vec(cam.position, "/camera/position");
    c.finite_vec(cam.target, "/camera/target");
    c.finite_vec(cam.up, "/camera/up");
    const Vec3f fwd{cam.target[0] - cam.position[0], cam.target[1] - cam.position[1],
                    cam.target[2] - cam.position[2]};
    c.expect(length(fwd) > 1e-6f, "/camera/target", "must differ from the camera position");
    c.expect(length(cam.up) > 1e-6f, "/camera/up", "must be non-zero");
    c.range(cam.fov_y_deg, 1.0f, 170.0f, "/camera/fov_y_deg", "must be in [1, 170] degrees");
    c.expect(finite(cam.near_plane) && cam.near_plane > 0, "/camera/near", "must be > 0");
    c.expect(finite(cam.far_plane) && cam.far_plane > cam.near_plane, "/camera/far",
             "must be greater than near");
  }
  if (s.render) {
    const RenderDefaults& r = *s.render;
    c.expect(r.preset.size() <= kMaxNameLength, "/render/preset", "longer than 4096 bytes");
    c.expect(r.caustics_map_size >= 1 && r.caustics_map_size <= kMaxRuntimeMapSize, "/render/caustics_map_size",
             "must be in [1, 8192]");
    c.expect(r.glass_map_size >= 1 && r.glass_map_size <= kMaxRuntimeMapSize, "/render/glass_map_size",
             "must be in [1, 8192]");
    c.expect(r.glass_planes >= 1 && r.glass_planes <= kMaxGlassPlanes, "/render/glass_planes", "must be in [1, 16]");
    c.expect(r.volume_photons >= 1 && r.volume_photons <= 8192, "/render/volume_photons", "must be in [1, 8192]");
    c.expect(r.volume_grid >= 2 && r.volume_grid <= 1024, "/render/volume_grid", "must be in [2, 1024]");
    c.expect(r.cmap_photons >= 1 && r.cmap_photons <= 4096, "/render/cmap_photons", "must be in [1, 4096]");
    c.expect(r.cmap_map_size >= 16 && r.cmap_map_size <= 4096, "/render/cmap_map_size", "must be in [16, 4096]");
    c.expect(r.cmap_adaptive_levels <= 8, "/render/cmap_adaptive_levels", "must be in [0, 8]");
    c.expect(r.cmap_photon_budget >= 1 && r.cmap_photon_budget <= (1u << 24), "/render/cmap_photon_budget", "must be in [1, 2^24]");
    c.expect(r.water_texture == 0 || (r.water_texture >= 16 && r.water_texture <= kMaxRuntimeMapSize), "/render/water_texture",
             "must be 0 or in [16, 8192]");
    c.expect(r.glass_spectral_coarse <= 1, "/render/glass_spectral_coarse", "must be 0 or 1");
  }
  return c.issue;
}

float scene_e0(const SceneDesc& s) {
  for (const Light& l : s.lights) {
    if (l.type == LightType::kDirectional) return l.irradiance > 0 ? l.irradiance : 1.0f;
  }
  return 1.0f;
}

bool scene_scatters(const SceneDesc& s) {
  if (s.medium && s.medium->scattering.scatters()) return true;
  if (s.water && s.water->scattering.scatters()) return true;
  for (const Object& o : s.objects) {
    if (is_transparent(o.role) && o.material.scattering.scatters()) return true;
  }
  return false;
}

bool scene_disperses(const SceneDesc& s) {
  if (s.water && s.water->dispersion > 0) return true;
  for (const Object& o : s.objects) {
    if (is_transparent(o.role) && o.material.dispersion > 0) return true;
  }
  return false;
}

void normalize_scene(SceneDesc& s) {
  for (Light& l : s.lights) {
    const float n = length(l.direction);
    if (n > 0 && std::isfinite(n)) {
      for (float& f : l.direction) f /= n;
    }
  }
  if (s.water) {
    for (Wave& w : s.water->waves) {
      const float n = std::hypot(w.direction[0], w.direction[1]);
      if (n > 0 && std::isfinite(n)) {
        w.direction[0] /= n;
        w.direction[1] /= n;
      }
    }
  }
}

}  // namespace caustix
