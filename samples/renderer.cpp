#include "caustix/sample/renderer.h"

// The sample renderer behind caustix-render and caustix-view: a client of the
// public Engine API (include/caustix/runtime/engine.h) like any application.
// It owns the camera, the HDR target and the receivers' shading (its own
// shaders, which include caustix.glsl); the engine owns the light side, the
// water surface and the glass.

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "caustix/common/mesh_topology.h"
#include "gl_objects.h"
#include "caustix_sample_shaders.h"

namespace caustix::sample {
namespace {

// The irradiance the display's exposure, the ambient term and the sky are
// relative to (renderer.h, default_exposure_ev): the first directional
// light's E0, else the largest I / d^2 of the point and spot lights at
// `centre`; 1 for a scene whose lights give nothing.
float reference_irradiance(const SceneDesc& scene, const glm::vec3& centre) {
  float reference = 0;
  for (const Light& l : scene.lights) {
    if (l.type == LightType::kDirectional) {
      reference = l.irradiance;
      break;
    }
    const glm::vec3 d = centre - glm::vec3(l.position[0], l.position[1], l.position[2]);
    reference = std::max(reference, l.intensity / std::max(glm::dot(d, d), 1e-12f));
  }
  return reference > 0 && std::isfinite(reference) ? reference : 1.0f;
}

glm::vec3 to_glm(const Vec3f& v) { return {v[0], v[1], v[2]}; }

// A colour (+ auxiliary colour) + depth render target of a given size.
struct Target {
  gl::Framebuffer fbo;
  gl::Texture color, aux;
  gl::Texture depth;
  int width = 0, height = 0;
  GLenum format = 0;

  void ensure(int w, int h, GLenum color_format, bool with_depth, bool with_aux = false) {
    if (w == width && h == height && color_format == format && fbo.get() && with_aux == (aux.get() != 0)) return;
    width = w;
    height = h;
    format = color_format;
    fbo = gl::make_framebuffer();
    auto attach = [&](gl::Texture& t, GLenum internal, GLenum attachment) {
      t = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(t.get(), 1, internal, w, h);
      glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glNamedFramebufferTexture(fbo.get(), attachment, t.get(), 0);
    };
    attach(color, color_format, GL_COLOR_ATTACHMENT0);
    aux = gl::Texture();
    if (with_aux) attach(aux, GL_RGBA32F, GL_COLOR_ATTACHMENT1);
    depth = gl::Texture();
    if (with_depth) attach(depth, GL_DEPTH_COMPONENT32F, GL_DEPTH_ATTACHMENT);
  }
};

// One camera's receiver passes: where they go and how they are cut (the
// main view, or Mihalik 2008's refraction and reflection textures).
struct PassView {
  GLuint fbo = 0;
  int width = 0, height = 0;
  glm::mat4 view_proj{1.0f};
  std::optional<glm::vec4> clip;  // world plane, a.x + b >= 0 kept
  bool mirrored = false;          // reflection camera: winding flips
  bool fog = false;               // Mihalik 2008 eq. 10, distance from fog_eye
  glm::vec3 fog_eye{0.0f};
  glm::vec3 clear{0.0f};
  bool cleared = false;           // the engine cleared it (water textures)
};

constexpr float kAmbient = 0.12f;

// The analytic sky's terms (Preetham, Shirley & Smits 1999, appendix A.2)
// for turbidity t and the sun at theta_s from the zenith: Perez's A..E for
// (Y, x, y) and the zenith's (Y, x, y) divided by F(0, theta_s), so that the
// shader's value is zenith x F(theta, gamma) / F(0, theta_s) (sky.frag.glsl).
struct SkyTerms {
  std::array<glm::vec3, 5> perez{glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
  glm::vec3 zenith_over_f0{0.0f};
  float zenith_luminance = 1.0f;  // Y_z in kcd/m^2
  bool operator==(const SkyTerms&) const = default;
};
SkyTerms sky_terms(float t, float theta_s) {
  SkyTerms k;
  k.perez = {glm::vec3(0.1787f * t - 1.4630f, -0.0193f * t - 0.2592f, -0.0167f * t - 0.2608f),
             glm::vec3(-0.3554f * t + 0.4275f, -0.0665f * t + 0.0008f, -0.0950f * t + 0.0092f),
             glm::vec3(-0.0227f * t + 5.3251f, -0.0004f * t + 0.2125f, -0.0079f * t + 0.2102f),
             glm::vec3(0.1206f * t - 2.5771f, -0.0641f * t - 0.8989f, -0.0441f * t - 1.6537f),
             glm::vec3(-0.0670f * t + 0.3703f, -0.0033f * t + 0.0452f, -0.0109f * t + 0.0529f)};
  const float th = theta_s, th2 = th * th, th3 = th2 * th;
  const float chi = (4.0f / 9.0f - t / 120.0f) * (3.14159265f - 2.0f * th);
  const float yz = (4.0453f * t - 4.9710f) * std::tan(chi) - 0.2155f * t + 2.4192f;
  const float xz = t * t * (0.00166f * th3 - 0.00375f * th2 + 0.00209f * th) +
                   t * (-0.02903f * th3 + 0.06377f * th2 - 0.03202f * th + 0.00394f) +
                   (0.11693f * th3 - 0.21196f * th2 + 0.06052f * th + 0.25886f);
  const float yyz = t * t * (0.00275f * th3 - 0.00610f * th2 + 0.00317f * th) +
                    t * (-0.04214f * th3 + 0.08970f * th2 - 0.04153f * th + 0.00516f) +
                    (0.15346f * th3 - 0.26756f * th2 + 0.06670f * th + 0.26688f);
  // F(0, theta_s): the zenith (cos theta = 1), gamma = theta_s.
  const glm::vec3 f0 = (1.0f + k.perez[0] * glm::exp(k.perez[1])) *
                       (1.0f + k.perez[2] * glm::exp(k.perez[3] * th) + k.perez[4] * std::cos(th) * std::cos(th));
  k.zenith_over_f0 = glm::vec3(yz, xz, yyz) / f0;
  k.zenith_luminance = yz;
  return k;
}

// The sky as sky_model.glsl draws it, on the CPU (its twin: keep the two
// alike), for the spherical harmonics of the surfaces' image-based light.
struct SkyModelCpu {
  bool analytic = false;
  glm::vec3 flat{0.0f};
  glm::vec3 to_sun{0.0f, 1.0f, 0.0f};
  SkyTerms terms;
  float scale = 1.0f;
  bool operator==(const SkyModelCpu&) const = default;
  glm::vec3 radiance(glm::vec3 d) const {
    if (!analytic) return flat;
    d = glm::normalize(glm::vec3(d.x, std::max(d.y, 0.0f), d.z));
    const float cos_theta = std::max(d.y, 0.02f);
    const float cos_gamma = std::clamp(glm::dot(d, to_sun), -1.0f, 1.0f), gamma = std::acos(cos_gamma);
    const glm::vec3 f = (1.0f + terms.perez[0] * glm::exp(terms.perez[1] / cos_theta)) *
                        (1.0f + terms.perez[2] * glm::exp(terms.perez[3] * gamma) + terms.perez[4] * cos_gamma * cos_gamma);
    const glm::vec3 yxy = terms.zenith_over_f0 * f;
    const float Y = yxy.x, x = yxy.y, y = std::max(yxy.z, 1e-4f);
    const glm::vec3 xyz(x / y * Y, Y, (1.0f - x - y) / y * Y);
    const glm::mat3 to_rgb(3.2406f, -0.9689f, 0.0557f, -1.5372f, 1.8758f, -0.2040f, -0.4986f, 0.0415f, 1.0570f);
    return glm::max(to_rgb * xyz, glm::vec3(0.0f)) * scale;
  }
};

// The real spherical harmonics of order <= 2 at unit d, in receiver.frag's
// order (Ramamoorthi & Hanrahan 2001, eq. 3).
std::array<float, 9> sh_basis(const glm::vec3& d) {
  return {0.282095f,         0.488603f * d.y,         0.488603f * d.z,
          0.488603f * d.x,   1.092548f * d.x * d.y,   1.092548f * d.y * d.z,
          0.315392f * (3.0f * d.z * d.z - 1.0f), 1.092548f * d.x * d.z, 0.546274f * (d.x * d.x - d.y * d.y)};
}

// The environment's irradiance over pi, as order-2 spherical harmonics
// (Ramamoorthi & Hanrahan 2001: the cosine lobe's convolution is A_l =
// pi, 2 pi / 3, pi / 4 per band; order 2 keeps the irradiance to a few
// per cent). The environment: the sky above the horizon; below it ground
// of albedo kGroundAlbedo under the sun (`sun`: its irradiance on a level
// floor, as drawn) and the sky, as a white floor would be drawn there.
constexpr float kGroundAlbedo = 0.2f;
std::array<glm::vec3, 9> sky_harmonics(const SkyModelCpu& sky, float sun) {
  constexpr int kTheta = 48, kPhi = 96;
  constexpr float kPi = 3.14159265358979f;
  std::array<glm::vec3, 9> l{};
  glm::vec3 sky_up(0.0f);  // the sky's irradiance on a level floor over pi
  std::vector<std::pair<glm::vec3, float>> below;  // (direction, solid angle)
  for (int i = 0; i < kTheta; ++i) {
    const float theta = (static_cast<float>(i) + 0.5f) * kPi / kTheta;
    const float d_omega = std::sin(theta) * (kPi / kTheta) * (2.0f * kPi / kPhi);
    for (int j = 0; j < kPhi; ++j) {
      const float phi = (static_cast<float>(j) + 0.5f) * 2.0f * kPi / kPhi;
      const glm::vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      if (d.y < 0.0f) {
        below.emplace_back(d, d_omega);
        continue;
      }
      const glm::vec3 value = sky.radiance(d);
      sky_up += value * d.y * d_omega / kPi;
      const auto y = sh_basis(d);
      for (std::size_t k = 0; k < 9; ++k) l[k] += value * y[k] * d_omega;
    }
  }
  const glm::vec3 ground = kGroundAlbedo * (glm::vec3(sun) + sky_up);
  for (const auto& [d, d_omega] : below) {
    const auto y = sh_basis(d);
    for (std::size_t k = 0; k < 9; ++k) l[k] += ground * y[k] * d_omega;
  }
  constexpr float kBand[3] = {1.0f, 2.0f / 3.0f, 1.0f / 4.0f};  // A_l / pi
  for (std::size_t k = 0; k < 9; ++k) l[k] *= kBand[k == 0 ? 0 : k < 4 ? 1 : 2];
  return l;
}

}  // namespace

struct Renderer::Impl {
  std::unique_ptr<Engine> engine;
  std::vector<bool> closed;  // per mesh: closed and consistently wound
  gl::Program receiver, irradiance, present, luminance, downsample, sky, prefilter;
  // This frame's sky (FrameParams::sky), drawn behind the receivers and
  // lighting those with a surface through its harmonics (sky_harmonics),
  // remade only when the sky or the sun on the ground changes.
  SkyModelCpu sky_model;
  std::optional<std::pair<SkyModelCpu, float>> sky_sh_of;
  std::array<glm::vec3, 9> sky_sh{};
  void set_sky(const gl::Program& p) const {
    p.set("u_sky_analytic", sky_model.analytic ? 1 : 0);
    p.set("u_sky_flat", sky_model.flat);
    p.set("u_to_sun", sky_model.to_sun);
    for (int k = 0; k < 5; ++k) p.set(("u_perez[" + std::to_string(k) + "]").c_str(), sky_model.terms.perez[static_cast<std::size_t>(k)]);
    p.set("u_zenith_over_f0", sky_model.terms.zenith_over_f0);
    p.set("u_scale", sky_model.scale);
  }
  gl::VertexArray empty_vao;
  Target hdr, display, irradiance_target, inscatter_target;
  Target resolved;      // the frame box-filtered down when supersampled
  int supersample = 1;  // the last frame's
  // The last frame at its output size: resolved when supersampled, else hdr.
  const Target& frame() const { return supersample > 1 ? resolved : hdr; }
  gl::Texture opaque_depth;  // the receivers' depth before the glass writes its own (draw_media)
  // The analytic sky as a cube map (kEnvironmentSize^2 a face), for what
  // the glass sees where its rays leave the scene
  // (GlassViewOptions::environment); drawn with the sky's program when the
  // sky changes.
  static constexpr int kEnvironmentSize = 64;
  gl::Texture environment;
  gl::Framebuffer environment_fbo;
  // The environment prefiltered for the surfaces' glossy reflection
  // (prefilter.frag): kPrefilteredLevels mips from kEnvironmentSize, level
  // k for roughness k / (kPrefilteredLevels - 1); bound at
  // prefiltered_unit (-1: the context has too few units, and the receivers
  // blend the sky's radiance towards its irradiance instead).
  static constexpr int kPrefilteredLevels = 6;
  gl::Texture prefiltered;
  gl::Sampler mipmapped;
  int prefiltered_unit = -1;
  void draw_environment() {
    if (!environment.get()) {
      environment = gl::make_texture(GL_TEXTURE_CUBE_MAP);
      glTextureStorage2D(environment.get(), 7, GL_RGBA16F, kEnvironmentSize, kEnvironmentSize);  // 64 .. 1
      glTextureParameteri(environment.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);  // the glass reads level 0
      glTextureParameteri(environment.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      environment_fbo = gl::make_framebuffer();
      prefiltered = gl::make_texture(GL_TEXTURE_CUBE_MAP);
      glTextureStorage2D(prefiltered.get(), kPrefilteredLevels, GL_RGBA16F, kEnvironmentSize, kEnvironmentSize);
      glTextureParameteri(prefiltered.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      glTextureParameteri(prefiltered.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      GLuint sampler = 0;
      glCreateSamplers(1, &sampler);
      glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      mipmapped = gl::Sampler(sampler);
      glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);  // the renderer's context: filtering across the faces' edges
    }
    // The faces as GL lays them out (+x, -x, +y, -y, +z, -z), each a 90
    // degree view from the origin.
    static const std::array<std::pair<glm::vec3, glm::vec3>, 6> kFaces{{{{1, 0, 0}, {0, -1, 0}},
                                                                         {{-1, 0, 0}, {0, -1, 0}},
                                                                         {{0, 1, 0}, {0, 0, 1}},
                                                                         {{0, -1, 0}, {0, 0, -1}},
                                                                         {{0, 0, 1}, {0, -1, 0}},
                                                                         {{0, 0, -1}, {0, -1, 0}}}};
    const glm::mat4 projection = glm::perspective(glm::radians(90.0f), 1.0f, 0.1f, 10.0f);
    glBindFramebuffer(GL_FRAMEBUFFER, environment_fbo.get());
    glViewport(0, 0, kEnvironmentSize, kEnvironmentSize);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    sky.use();
    set_sky(sky);
    glBindVertexArray(empty_vao.get());
    for (int face = 0; face < 6; ++face) {
      glNamedFramebufferTextureLayer(environment_fbo.get(), GL_COLOR_ATTACHMENT0, environment.get(), 0, face);
      const auto& [forward, up] = kFaces[static_cast<std::size_t>(face)];
      sky.set("u_inv_view_proj", glm::inverse(projection * glm::lookAt(glm::vec3(0.0f), forward, up)));
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    // Its mips, the prefilter's source; then each level of the prefiltered
    // cube from them.
    glGenerateTextureMipmap(environment.get());
    prefilter.use();
    prefilter.set("u_source_size", static_cast<float>(kEnvironmentSize));
    glBindTextureUnit(0, environment.get());
    glBindSampler(0, mipmapped.get());
    for (int level = 0; level < kPrefilteredLevels; ++level) {
      const int size = kEnvironmentSize >> level;
      glViewport(0, 0, size, size);
      prefilter.set("u_roughness", static_cast<float>(level) / static_cast<float>(kPrefilteredLevels - 1));
      for (int face = 0; face < 6; ++face) {
        glNamedFramebufferTextureLayer(environment_fbo.get(), GL_COLOR_ATTACHMENT0, prefiltered.get(), level, face);
        const auto& [forward, up] = kFaces[static_cast<std::size_t>(face)];
        prefilter.set("u_inv_view_proj", glm::inverse(projection * glm::lookAt(glm::vec3(0.0f), forward, up)));
        glDrawArrays(GL_TRIANGLES, 0, 3);
      }
    }
    glBindSampler(0, 0);
    glEnable(GL_DEPTH_TEST);
  }
  int opaque_w = 0, opaque_h = 0;
  DisplayOptions display_options;  // the last frame's
  // The frame's log luminance with its mip chain (auto exposure).
  gl::Texture log_luminance;
  gl::Framebuffer log_luminance_fbo;
  int log_luminance_w = 0, log_luminance_h = 0, log_luminance_levels = 0;
  float reference = 1.0f;  // reference_irradiance() of the scene

  // Pass timing: kSlots frames of PassTimes::kCount + 1 timestamps in
  // flight, read back when available.
  static constexpr int kSlots = 3;
  bool timing = false;
  std::array<std::array<gl::Query, PassTimes::kCount + 1>, kSlots> stamps;
  std::array<bool, kSlots> pending{};
  int slot = 0;
  PassTimes times;
  void stamp(int k) {
    if (timing) glQueryCounter(stamps[static_cast<std::size_t>(slot)][static_cast<std::size_t>(k)].get(), GL_TIMESTAMP);
  }
  void collect() {
    for (int i = 0; i < kSlots; ++i) {
      if (!pending[static_cast<std::size_t>(i)]) continue;
      auto& q = stamps[static_cast<std::size_t>(i)];
      GLint ready = 0;
      glGetQueryObjectiv(q[PassTimes::kCount].get(), GL_QUERY_RESULT_AVAILABLE, &ready);
      if (!ready) continue;
      GLuint64 t[PassTimes::kCount + 1];
      for (std::size_t k = 0; k <= PassTimes::kCount; ++k) glGetQueryObjectui64v(q[k].get(), GL_QUERY_RESULT, &t[k]);
      for (std::size_t k = 0; k < PassTimes::kCount; ++k) times.ms[k] = static_cast<float>(static_cast<double>(t[k + 1] - t[k]) * 1e-6);
      times.valid = true;
      pending[static_cast<std::size_t>(i)] = false;
    }
  }

  const SceneDesc& scene() const { return engine->scene(); }

  void set_model(const gl::Program& p, std::uint32_t i) const {
    const glm::mat4 model = glm::make_mat4(scene().objects[i].transform.data());
    p.set("u_model", model);
    p.set("u_normal_matrix", glm::mat3(glm::transpose(glm::inverse(model))));
  }

  // Units of the receiver program's maps (receiver.frag.glsl): 1..3 and,
  // for the emissive map, 16 where the context has more than the 16 units
  // GL 4.5 guarantees (4..15 are caustix's); -1 where it has not, and the
  // emission is then its factor alone.
  int emissive_unit = -1;
  bool has_maps = false;  // some receiver has maps or an alpha mode (the program is built with SAMPLE_MAPS)
  bool blended(std::uint32_t i) const {
    const auto& m = scene().objects[i].material.maps;
    return m && m->alpha_mode == AlphaMode::kBlend;
  }
  // Receiver i's maps and alpha into the receiver program (nothing in a
  // scene without: the uniforms keep their defaults, opaque and unmapped).
  void set_maps(const gl::Program& p, std::uint32_t i) const {
    if (!has_maps) return;
    const std::optional<SurfaceMapBindings> m = engine->surface_maps(i);
    int bits = 0;
    if (m) {
      const std::array<const SurfaceMapBindings::Map*, 4> maps{&m->metallic_roughness, &m->normal, &m->occlusion, &m->emissive};
      for (std::size_t k = 0; k < maps.size(); ++k) {
        const int unit = k < 3 ? static_cast<int>(k) + 1 : emissive_unit;
        if (maps[k]->texture == 0 || unit < 0) continue;
        bits |= 1 << k;
        const auto& t = maps[k]->transform;
        p.set(("u_map_projection[" + std::to_string(k) + "]").c_str(), static_cast<int>(maps[k]->projection));
        p.set(("u_map_rows[" + std::to_string(2 * k) + "]").c_str(), glm::vec3(t[0], t[1], t[2]));
        p.set(("u_map_rows[" + std::to_string(2 * k + 1) + "]").c_str(), glm::vec3(t[3], t[4], t[5]));
        glBindTextureUnit(static_cast<GLuint>(unit), maps[k]->texture);
      }
    }
    p.set("u_maps", bits);
    p.set("u_normal_scale", m ? m->normal_scale : 1.0f);
    p.set("u_occlusion_strength", m ? m->occlusion_strength : 1.0f);
    p.set("u_alpha_mode", m ? static_cast<int>(m->alpha_mode) : 0);
    p.set("u_alpha", m ? m->alpha : 1.0f);
    p.set("u_alpha_cutoff", m ? m->alpha_cutoff : 0.5f);
  }

  // `textured`: p is the receiver program, which takes textures; it then
  // draws the blended receivers only when `only` names one (draw_lit_view
  // composites them last).
  Status draw_receivers(const gl::Program& p, int pass, std::uint32_t li, std::optional<std::uint32_t> only,
                        bool cull_closed = false, bool textured = false) const {
    glVertexAttrib4f(3, 1.0f, 1.0f, 1.0f, 1.0f);  // the vertex colour of meshes without (attribute 3 disabled)
    for (std::uint32_t i = 0; i < scene().objects.size(); ++i) {
      if (only && *only != i) continue;
      if (transmits(scene().objects[i].role)) continue;  // drawn as glass (Engine::draw_glass)
      if (textured && !only && blended(i)) continue;
      if (cull_closed && closed[scene().objects[i].mesh_index]) {
        glEnable(GL_CULL_FACE);
      } else {
        glDisable(GL_CULL_FACE);
      }
      set_model(p, i);
      const Object& o = scene().objects[i];
      // A mirror (its light is the engine's caustic maps) is drawn as a
      // polished metal of its reflectance, showing the sky.
      const bool mirror = textured && is_mirror(o.role);
      p.set("u_albedo", to_glm(mirror ? o.material.reflectance : o.material.albedo));
      if (textured) {
        const std::optional<Surface> sf = mirror ? std::optional(Surface{1.0f, 0.0f, {0, 0, 0}}) : o.material.surface;
        p.set("u_surface", sf ? 1 : 0);
        if (sf) {
          p.set("u_metallic", sf->metallic);
          p.set("u_roughness", sf->roughness);
          p.set("u_emissive", reference * to_glm(sf->emissive));
        }
        const std::optional<AlbedoMap> map = engine->albedo_map(i);
        p.set("u_albedo_projection", map ? static_cast<int>(map->projection) : 0);
        if (map) {
          p.set("u_albedo_rows[0]", glm::vec3(map->transform[0], map->transform[1], map->transform[2]));
          p.set("u_albedo_rows[1]", glm::vec3(map->transform[3], map->transform[4], map->transform[5]));
          glBindTextureUnit(0, map->texture);
        }
        set_maps(p, i);
      }
      if (pass != 0) CAUSTIX_RETURN_IF_ERROR(engine->bind(i, li));
      CAUSTIX_RETURN_IF_ERROR(engine->draw_object(i));
    }
    return Status::success();
  }

  // Receivers into one view: pass 0 clears and lays down ambient and depth,
  // pass 1 adds light `li` (eq. 4-19, 4-20). With `only`, that blended
  // receiver over what is there: pass 0 composites its ambient by its alpha
  // (and writes its depth), pass 1 adds alpha times its light.
  Status draw_view(const PassView& v, int pass, std::uint32_t li, const WaterMedium& medium, std::optional<std::uint32_t> only = std::nullopt) const {
    glBindFramebuffer(GL_FRAMEBUFFER, v.fbo);
    glViewport(0, 0, v.width, v.height);
    glEnable(GL_DEPTH_TEST);
    if (only) {
      glEnable(GL_BLEND);
      if (pass == 0) glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
      else glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE, GL_ZERO, GL_ONE);
      glDepthMask(pass == 0 ? GL_TRUE : GL_FALSE);
      glDepthFunc(GL_LEQUAL);
    } else if (pass == 0) {
      if (!v.cleared) {
        const float clear[4] = {v.clear.r, v.clear.g, v.clear.b, 0.0f};
        glClearNamedFramebufferfv(v.fbo, GL_COLOR, 0, clear);
        glDepthMask(GL_TRUE);
        glClear(GL_DEPTH_BUFFER_BIT);
      }
      glDepthMask(GL_TRUE);
      glDisable(GL_BLEND);
      glDepthFunc(GL_LESS);
    } else {
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE);
      glDepthMask(GL_FALSE);
      glDepthFunc(GL_LEQUAL);
    }
    if (v.clip) glEnable(GL_CLIP_DISTANCE0);
    glFrontFace(v.mirrored ? GL_CW : GL_CCW);
    const gl::Program& p = receiver;
    p.use();
    p.set("u_view_proj", v.view_proj);
    p.set("u_clip_plane", v.clip.value_or(glm::vec4(0.0f)));
    p.set("u_pass", pass);
    p.set("u_ambient", reference * kAmbient * glm::vec3(kSkyColor[0], kSkyColor[1], kSkyColor[2]));
    p.set("u_eye", v.fog_eye);
    set_sky(p);
    for (int k = 0; k < 9; ++k) p.set(("u_sky_sh[" + std::to_string(k) + "]").c_str(), sky_sh[static_cast<std::size_t>(k)]);
    if (prefiltered_unit >= 0) glBindTextureUnit(static_cast<GLuint>(prefiltered_unit), prefiltered.get());
    p.set("u_fog", v.fog ? 1 : 0);
    p.set("u_fog_eye", v.fog_eye);
    p.set("u_fog_k", medium.k);
    p.set("u_water_color", medium.color);
    const Status st = draw_receivers(p, pass, li, only, v.clip.has_value(), /*textured=*/true);
    glDisable(GL_CLIP_DISTANCE0);
    if (only) glBlendFunc(GL_ONE, GL_ONE);
    if (pass == 0 && !only && sky_model.analytic && !v.fog) draw_sky(v);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    return st;
  }

  // The analytic sky where nothing was drawn (depth still 1).
  void draw_sky(const PassView& v) const {
    glDisable(GL_CULL_FACE);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    sky.use();
    sky.set("u_inv_view_proj", glm::inverse(v.view_proj));
    set_sky(sky);
    glBindVertexArray(empty_vao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
  }

  // Ambient, then one additive pass per light; then the blended receivers,
  // farthest first (by their bounds' centres), each composited whole.
  Status draw_lit_view(const PassView& v, const WaterMedium& medium) const {
    CAUSTIX_RETURN_IF_ERROR(draw_view(v, 0, 0, medium));
    for (std::uint32_t li = 0; li < scene().lights.size(); ++li) CAUSTIX_RETURN_IF_ERROR(draw_view(v, 1, li, medium));
    std::vector<std::pair<float, std::uint32_t>> order;
    for (std::uint32_t i = 0; i < scene().objects.size(); ++i) {
      if (!blended(i) || transmits(scene().objects[i].role)) continue;
      const Object& o = scene().objects[i];
      const MeshInfo& m = scene().meshes[o.mesh_index];
      const glm::vec3 centre = 0.5f * (to_glm(m.bounds_min) + to_glm(m.bounds_max));
      const glm::vec3 world = glm::make_mat4(o.transform.data()) * glm::vec4(centre, 1.0f);
      order.emplace_back(-glm::distance(world, v.fog_eye), i);
    }
    std::sort(order.begin(), order.end());
    for (const auto& [d, i] : order) {
      CAUSTIX_RETURN_IF_ERROR(draw_view(v, 0, 0, medium, i));
      for (std::uint32_t li = 0; li < scene().lights.size(); ++li) CAUSTIX_RETURN_IF_ERROR(draw_view(v, 1, li, medium, i));
    }
    return Status::success();
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create(const RuntimeScene& scene) {
  std::unique_ptr<Renderer> r(new Renderer());
  Impl& s = *r->impl_;
  auto engine = Engine::create(scene);
  if (!engine) return engine.error();
  s.engine = std::move(*engine);
  s.reference = reference_irradiance(scene.desc, 0.5f * (s.engine->bounds_min() + s.engine->bounds_max()));
  const std::string lighting = std::string("#version 450 core\n") + s.engine->glsl_include();
  // The maps' code only in a scene with maps (receiver.frag's SAMPLE_MAPS).
  const bool maps = std::any_of(scene.desc.objects.begin(), scene.desc.objects.end(), [](const Object& o) { return o.material.maps.has_value(); });
  const std::string receiver_fs = lighting + (maps ? "#define SAMPLE_MAPS\n" : "") + shaders::k_sky_model_glsl + shaders::k_receiver_frag_glsl;
  s.has_maps = maps;
  const std::string sky_fs = std::string("#version 450 core\n") + shaders::k_sky_model_glsl + shaders::k_sky_frag_glsl;
  const std::string irradiance_fs = lighting + shaders::k_irradiance_frag_glsl;
  const std::string prefilter_fs = std::string("#version 450 core\n") + shaders::k_prefilter_frag_glsl;
  CAUSTIX_RETURN_IF_ERROR(
      gl::build_programs({{&s.receiver, "receiver", shaders::k_mesh_vert_glsl, receiver_fs.c_str()},
                          {&s.irradiance, "irradiance", shaders::k_mesh_vert_glsl, irradiance_fs.c_str()},
                          {&s.present, "present", shaders::k_fullscreen_vert_glsl, shaders::k_present_frag_glsl},
                          {&s.sky, "sky", shaders::k_fullscreen_vert_glsl, sky_fs.c_str()},
                          {&s.prefilter, "prefilter", shaders::k_fullscreen_vert_glsl, prefilter_fs.c_str()},
                          {&s.luminance, "luminance", shaders::k_fullscreen_vert_glsl, shaders::k_luminance_frag_glsl},
                          {&s.downsample, "downsample", shaders::k_fullscreen_vert_glsl, shaders::k_downsample_frag_glsl}}));
  GLint units = 0;
  glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
  s.emissive_unit = units > 16 ? 16 : -1;
  s.prefiltered_unit = units > 17 ? 17 : -1;
  s.receiver.use();
  s.receiver.set("u_emissive_map", std::max(s.emissive_unit, 1));
  s.receiver.set("u_prefiltered", std::max(s.prefiltered_unit, 1));  // a sampler must name a unit; unread at 1
  s.receiver.set("u_has_prefiltered", s.prefiltered_unit >= 0 ? 1 : 0);
  s.receiver.set("u_prefiltered_levels", static_cast<float>(Impl::kPrefilteredLevels - 1));
  s.empty_vao = gl::make_vertex_array();
  for (const TriangleMesh& m : scene.meshes) s.closed.push_back(!m.triangles.empty() && census_edges(m).closed());
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("renderer set-up"));
  return r;
}

Status Renderer::render(const FrameParams& f) {
  Impl& s = *impl_;
  if (f.supersample < 1 || f.supersample > 4) {
    return make_error(ErrorCode::kUsage, "supersample " + std::to_string(f.supersample) + " is outside 1..4");
  }
  // The size every pass renders at; box-filtered down to f's at the end.
  const int ss = f.supersample, width = f.width * ss, height = f.height * ss;
  if (f.width <= 0 || f.height <= 0 || width > 16384 || height > 16384) {
    return make_error(ErrorCode::kUsage, "image size " + std::to_string(f.width) + "x" + std::to_string(f.height) +
                                             (ss > 1 ? " supersampled " + std::to_string(ss) + "x" : std::string()) +
                                             " is outside 1..16384");
  }
  if (!std::isfinite(f.display.exposure_ev) || std::fabs(f.display.exposure_ev) > 16.0f) {
    return make_error(ErrorCode::kUsage, "exposure " + std::to_string(f.display.exposure_ev) + " EV is outside [-16, 16]");
  }
  s.display_options = f.display;
  const SceneDesc& scene = s.scene();
  // The sky's radiance scales with the scene's light level, as the ambient
  // term does (reference_irradiance): a lamp-lit room's sky is not 100
  // times brighter than its floor.
  WaterLook look = f.water;
  look.sky *= s.reference;
  s.hdr.ensure(width, height, GL_RGBA32F, true);
  if (s.timing) {
    s.collect();
    // A slot still waiting is overwritten (its frame's times are lost).
    s.slot = (s.slot + 1) % Impl::kSlots;
  }
  View view;
  view.view = glm::lookAt(to_glm(f.camera.position), to_glm(f.camera.target), to_glm(f.camera.up));
  view.fov_y_deg = f.camera.fov_y_deg;
  view.aspect = static_cast<float>(width) / static_cast<float>(height);
  view.near_plane = f.camera.near_plane;
  view.far_plane = f.camera.far_plane;
  const glm::mat4 view_proj = view.projection() * view.view;

  s.stamp(0);
  FrameUpdate update{f.time, f.caustics};
  if (f.out_of_view_interval > 0) {
    update.camera = view_proj;
    update.out_of_view_interval = f.out_of_view_interval;
  }
  CAUSTIX_RETURN_IF_ERROR(s.engine->update(update));
  s.stamp(1);
  const glm::vec3 sky = s.reference * glm::vec3(kSkyColor[0], kSkyColor[1], kSkyColor[2]);
  // The sky: flat, or the analytic sky of the scene's first directional
  // light; and that sun's irradiance on a level floor (the ground of the
  // surfaces' image-based light).
  SkyModelCpu sky_model;
  sky_model.flat = sky;
  float sun_on_floor = 0.0f;
  const auto sun = std::find_if(scene.lights.begin(), scene.lights.end(), [](const Light& l) { return l.type == LightType::kDirectional; });
  if (sun != scene.lights.end()) {
    const glm::vec3 to_sun = -glm::normalize(to_glm(sun->direction));
    sun_on_floor = sun->irradiance * std::max(to_sun.y, 0.0f);
    if (f.sky == SkyModel::kAnalytic) {
      sky_model.analytic = true;
      sky_model.to_sun = to_sun;
      // A sun below the horizon lights nothing; its sky is the sky at the horizon.
      const float theta_s = std::acos(std::clamp(to_sun.y, 0.0f, 1.0f));
      sky_model.terms = sky_terms(2.5f, theta_s);
      sky_model.scale = glm::dot(sky, glm::vec3(0.2126f, 0.7152f, 0.0722f)) / sky_model.terms.zenith_luminance;
    }
  }
  s.sky_model = sky_model;
  if (!s.sky_sh_of || *s.sky_sh_of != std::pair{sky_model, sun_on_floor}) {
    s.sky_sh = sky_harmonics(sky_model, sun_on_floor);
    s.sky_sh_of = std::pair{sky_model, sun_on_floor};
    s.draw_environment();  // the glass reads it under the analytic sky; the surfaces' prefiltered cube under either
  }
  // The glass sees the analytic sky where its rays leave the scene (the
  // flat sky is draw_glass's own colour), unless the caller gave its own.
  GlassViewOptions glass_view = f.glass_view;
  if (glass_view.environment == 0 && sky_model.analytic) glass_view.environment = s.environment.get();
  const WaterMedium medium = s.engine->water_medium(view, look);

  PassView main{s.hdr.fbo.get(), width, height, view_proj, std::nullopt, false, false, view.eye(), sky};
  if (scene.water && look.textures && medium.camera_under) {  // eq. 10 on everything seen directly; the deep background is water
    main.fog = true;
    main.clear = medium.color;
  }
  glDisable(GL_CULL_FACE);
  CAUSTIX_RETURN_IF_ERROR(s.draw_lit_view(main, medium));
  s.stamp(2);

  glBindFramebuffer(GL_FRAMEBUFFER, s.hdr.fbo.get());
  glViewport(0, 0, width, height);
  if (s.engine->has_media()) {
    if (s.opaque_w != width || s.opaque_h != height) {
      s.opaque_depth = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(s.opaque_depth.get(), 1, GL_DEPTH_COMPONENT32F, width, height);
      s.opaque_w = width;
      s.opaque_h = height;
    }
    glCopyImageSubData(s.hdr.depth.get(), GL_TEXTURE_2D, 0, 0, 0, 0, s.opaque_depth.get(), GL_TEXTURE_2D, 0, 0, 0, 0, width, height, 1);
  }
  CAUSTIX_RETURN_IF_ERROR(s.engine->draw_glass(view, s.hdr.color.get(), s.hdr.depth.get(), sky, glass_view));
  s.stamp(3);
  if (scene.water) {
    Status inner = Status::success();
    CAUSTIX_RETURN_IF_ERROR(s.engine->draw_water(view, look, [&](const WaterPass& p) {
      const PassView v{p.framebuffer, p.size, p.size, p.view_proj, p.clip_plane, p.mirrored, p.fog, p.eye, glm::vec3(0.0f), true};
      if (inner.ok()) inner = s.draw_lit_view(v, medium);
    }, s.hdr.depth.get()));
    CAUSTIX_RETURN_IF_ERROR(inner);
  }
  s.stamp(4);
  if (s.engine->has_media()) {
    // The receivers omit diffuse shading's 1/pi (caustix.glsl); the
    // in-scatter, true radiance, is scaled alike.
    glBindFramebuffer(GL_FRAMEBUFFER, s.hdr.fbo.get());
    glViewport(0, 0, width, height);
    CAUSTIX_RETURN_IF_ERROR(s.engine->draw_media(view_proj, s.hdr.color.get(), s.opaque_depth.get(), 3.14159265f));
  }
  s.stamp(5);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  s.supersample = ss;
  if (ss > 1) {
    s.resolved.ensure(f.width, f.height, GL_RGBA32F, false);
    glBindFramebuffer(GL_FRAMEBUFFER, s.resolved.fbo.get());
    glViewport(0, 0, f.width, f.height);
    glDisable(GL_DEPTH_TEST);
    s.downsample.use();
    s.downsample.set("u_factor", ss);
    glBindTextureUnit(0, s.hdr.color.get());
    glBindVertexArray(s.empty_vao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEnable(GL_DEPTH_TEST);
  }
  glBindVertexArray(0);
  s.stamp(6);
  if (s.timing) s.pending[static_cast<std::size_t>(s.slot)] = true;
  return gl::check_gl("frame");
}

Result<InscatterImage> Renderer::render_inscatter(const InscatterRequest& q) {
  Impl& s = *impl_;
  const SceneDesc& scene = s.scene();
  if (!s.engine->has_media()) {
    return make_error(ErrorCode::kUsage, "nothing in the scene scatters light (no medium, water or glass with \"scattering\")");
  }
  const int S = q.pixel_samples;
  if (q.width <= 0 || q.height <= 0 || S < 1 || S > 16 || q.width * S > 8192 || q.height * S > 8192 || !(q.x1 > q.x0) ||
      !(q.y1 > q.y0) || !std::isfinite(q.x0) || !std::isfinite(q.x1) || !std::isfinite(q.y0) || !std::isfinite(q.y1)) {
    return make_error(ErrorCode::kUsage, "in-scatter region must have x1 > x0, y1 > y0, pixel samples 1..16 and at most 8192 samples per side");
  }
  InscatterImage img;
  img.width = q.width;
  img.height = q.height;
  img.e0 = scene_e0(scene);
  CAUSTIX_RETURN_IF_ERROR(s.engine->update(FrameUpdate{q.time, q.caustics}));
  img.stats = s.engine->volume_stats(true);

  // Orthographic along -z, in front of everything.
  float z_front = s.engine->bounds_max().z, z_back = s.engine->bounds_min().z;
  if (scene.medium) {
    z_front = std::max(z_front, scene.medium->extent[5]);
    z_back = std::min(z_back, scene.medium->extent[2]);
  }
  if (scene.water) {
    z_front = std::max(z_front, scene.water->extent[3]);
    z_back = std::min(z_back, scene.water->extent[1]);
  }
  z_front += 1.0f;
  z_back -= 1.0f;
  const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, z_front), glm::vec3(0, 0, z_front - 1), glm::vec3(0, 1, 0));
  const glm::mat4 proj = glm::ortho(q.x0, q.x1, q.y0, q.y1, 0.0f, z_front - z_back);
  const glm::mat4 view_proj = proj * view;
  const int sw = q.width * S, sh = q.height * S;
  s.inscatter_target.ensure(sw, sh, GL_RGBA32F, true);
  const GLuint fbo = s.inscatter_target.fbo.get();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, sw, sh);
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, zero);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glClear(GL_DEPTH_BUFFER_BIT);
  // The opaque objects' depth: where view rays stop.
  const gl::Program& p = s.receiver;
  p.use();
  p.set("u_view_proj", view_proj);
  p.set("u_clip_plane", glm::vec4(0.0f));
  p.set("u_pass", 0);
  p.set("u_fog", 0);
  CAUSTIX_RETURN_IF_ERROR(s.draw_receivers(p, 0, 0, std::nullopt, false, /*textured=*/true));
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, zero);
  CAUSTIX_RETURN_IF_ERROR(s.engine->draw_media(view_proj, 0, s.inscatter_target.depth.get(), 1.0f / img.e0));
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("in-scatter"));

  std::vector<float> px(static_cast<std::size_t>(sw) * static_cast<std::size_t>(sh) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(s.inscatter_target.color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * 4), px.data());
  img.rgb.assign(static_cast<std::size_t>(q.width) * static_cast<std::size_t>(q.height) * 3, 0.0f);
  const double n = static_cast<double>(S) * S;
  for (int y = 0; y < q.height; ++y) {
    for (int x = 0; x < q.width; ++x) {
      double e[3] = {0, 0, 0};
      for (int sy = 0; sy < S; ++sy) {
        for (int sx = 0; sx < S; ++sx) {
          const std::size_t k = 4 * (static_cast<std::size_t>(y * S + sy) * static_cast<std::size_t>(sw) + static_cast<std::size_t>(x * S + sx));
          for (int c = 0; c < 3; ++c) e[c] += px[k + c];
        }
      }
      // GL row 0 is at y0; the image's row 0 at y1.
      const std::size_t o = 3 * (static_cast<std::size_t>(q.height - 1 - y) * static_cast<std::size_t>(q.width) + static_cast<std::size_t>(x));
      for (int c = 0; c < 3; ++c) img.rgb[o + c] = static_cast<float>(e[c] / n);
    }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return img;
}

Result<IrradianceImage> Renderer::render_irradiance(const IrradianceRequest& q) {
  Impl& s = *impl_;
  const SceneDesc& scene = s.scene();
  std::optional<std::uint32_t> receiver;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].name == q.receiver) receiver = i;
  }
  if (!receiver) return make_error(ErrorCode::kUsage, "no object named '" + q.receiver + "' in the scene");
  if (transmits(scene.objects[*receiver].role)) {
    return make_error(ErrorCode::kUsage, "'" + q.receiver + "' is transparent; irradiance images are of diffuse receivers");
  }
  if (q.width <= 0 || q.height <= 0 || q.width > 16384 || q.height > 16384 || !(q.x1 > q.x0) || !(q.z1 > q.z0) ||
      !std::isfinite(q.x0) || !std::isfinite(q.x1) || !std::isfinite(q.z0) || !std::isfinite(q.z1)) {
    return make_error(ErrorCode::kUsage, "irradiance region must have x1 > x0, z1 > z0 and a size in 1..16384");
  }
  if (q.pixel_samples < 1 || q.pixel_samples > 16) {
    return make_error(ErrorCode::kUsage, "pixel samples per axis " + std::to_string(q.pixel_samples) + " is outside 1..16");
  }
  IrradianceImage img;
  img.width = q.width;
  img.height = q.height;
  img.e0 = scene_e0(scene);
  CAUSTIX_RETURN_IF_ERROR(s.engine->update(FrameUpdate{q.time, q.caustics}));

  // The direction towards the first light as the receiver's shading sees it
  // (for the auxiliary channels only).
  glm::vec3 to_light(0.0f);
  if (!scene.lights.empty()) {
    auto lit = s.engine->lighting(*receiver, 0);
    if (!lit) return lit.error();
    const LightBlock& b = lit->block;
    if (b.mode.x == static_cast<int>(LightMode::kCaustics)) to_light = glm::vec3(b.frame_v);
    else if (b.mode.y == 1) to_light = -glm::vec3(b.mode.x == static_cast<int>(LightMode::kFlatWater) ? b.refracted : b.light_direction);
  }

  // Tiles of at most 2048^2 samples: each pixel's S x S samples are the
  // fragment centres of a render at S times the resolution.
  const int S = q.pixel_samples;
  const int tile = std::max(1, 2048 / S);
  const float ylo = s.engine->bounds_min().y - 1.0f, yhi = s.engine->bounds_max().y + 1.0f;
  const float px = (q.x1 - q.x0) / static_cast<float>(q.width), pz = (q.z1 - q.z0) / static_cast<float>(q.height);
  const std::size_t pixels = static_cast<std::size_t>(q.width) * static_cast<std::size_t>(q.height);
  img.rgb.assign(pixels * 3, 0.0f);
  img.aux.assign(pixels * 3, 0.0f);
  std::vector<float> color, aux;
  for (int ty = 0; ty < q.height; ty += tile) {
    for (int tx = 0; tx < q.width; tx += tile) {
      const int tw = std::min(tile, q.width - tx), th = std::min(tile, q.height - ty);
      const int sw = tw * S, sh = th * S;
      s.irradiance_target.ensure(sw, sh, GL_RGBA32F, true, true);
      // Straight down: clip x from world x, clip y from world z (GL row 0
      // at the tile's z0), clip z from height (higher is nearer).
      const float x0 = q.x0 + px * static_cast<float>(tx), x1 = q.x0 + px * static_cast<float>(tx + tw);
      const float z0 = q.z0 + pz * static_cast<float>(ty), z1 = q.z0 + pz * static_cast<float>(ty + th);
      glm::mat4 m(0.0f);
      m[0][0] = 2.0f / (x1 - x0);
      m[3][0] = -(x1 + x0) / (x1 - x0);
      m[2][1] = 2.0f / (z1 - z0);
      m[3][1] = -(z1 + z0) / (z1 - z0);
      m[1][2] = -2.0f / (yhi - ylo);
      m[3][2] = (yhi + ylo) / (yhi - ylo);
      m[3][3] = 1.0f;
      const GLuint fbo = s.irradiance_target.fbo.get();
      auto begin_pass = [&](int pass) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1}, colour_only[2] = {GL_COLOR_ATTACHMENT0, GL_NONE};
        glNamedFramebufferDrawBuffers(fbo, 2, pass == 0 ? both : colour_only);
        glViewport(0, 0, sw, sh);
        s.irradiance.use();
        s.irradiance.set("u_view_proj", m);
        s.irradiance.set("u_inv_e0", 1.0f / img.e0);
        s.irradiance.set("u_to_light", to_light);
        s.irradiance.set("u_pass", pass);
      };
      glEnable(GL_DEPTH_TEST);
      glDisable(GL_CULL_FACE);
      glDisable(GL_BLEND);
      glDepthMask(GL_TRUE);
      glDepthFunc(GL_LESS);
      begin_pass(0);
      const float zero[4] = {0, 0, 0, 0};
      glClearNamedFramebufferfv(fbo, GL_COLOR, 0, zero);
      glClearNamedFramebufferfv(fbo, GL_COLOR, 1, zero);
      glClear(GL_DEPTH_BUFFER_BIT);
      CAUSTIX_RETURN_IF_ERROR(s.draw_receivers(s.irradiance, 0, 0, receiver));
      for (std::uint32_t li = 0; li < scene.lights.size(); ++li) {
        begin_pass(1);
        glEnable(GL_DEPTH_TEST);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_LEQUAL);
        CAUSTIX_RETURN_IF_ERROR(s.draw_receivers(s.irradiance, 1, li, receiver));
      }
      glDisable(GL_BLEND);
      glDepthMask(GL_TRUE);
      CAUSTIX_RETURN_IF_ERROR(gl::check_gl("irradiance"));

      const std::size_t samples = static_cast<std::size_t>(sw) * static_cast<std::size_t>(sh);
      color.resize(samples * 4);
      aux.resize(samples * 4);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glGetTextureImage(s.irradiance_target.color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(color.size() * 4), color.data());
      glGetTextureImage(s.irradiance_target.aux.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(aux.size() * 4), aux.data());
      // Box average: irradiance over all S^2 samples (0 where unseen), the
      // auxiliary means over the samples that see the receiver.
      for (int y = 0; y < th; ++y) {
        for (int x = 0; x < tw; ++x) {
          double e[3] = {0, 0, 0}, seen = 0, ny = 0, cosl = 0;
          for (int sy = 0; sy < S; ++sy) {
            for (int sx = 0; sx < S; ++sx) {
              const std::size_t k = 4 * (static_cast<std::size_t>(y * S + sy) * static_cast<std::size_t>(sw) +
                                         static_cast<std::size_t>(x * S + sx));
              for (int c = 0; c < 3; ++c) e[c] += color[k + c];
              seen += aux[k];
              ny += aux[k + 1];
              cosl += aux[k + 2];
            }
          }
          const std::size_t o = 3 * (static_cast<std::size_t>(ty + y) * static_cast<std::size_t>(q.width) + static_cast<std::size_t>(tx + x));
          const double n = static_cast<double>(S) * S;
          for (int c = 0; c < 3; ++c) img.rgb[o + c] = static_cast<float>(e[c] / n);
          img.aux[o] = static_cast<float>(seen / n);
          img.aux[o + 1] = seen > 0 ? static_cast<float>(ny / seen) : 0.0f;
          img.aux[o + 2] = seen > 0 ? static_cast<float>(cosl / seen) : 0.0f;
        }
      }
    }
  }
  return img;
}

void Renderer::finish() { glFinish(); }

const SceneDesc& Renderer::scene() const { return impl_->scene(); }
Engine& Renderer::engine() { return *impl_->engine; }

Status Renderer::set_light(std::uint32_t index, const Light& light) { return impl_->engine->set_light(index, light); }

Status Renderer::set_object_transform(std::uint32_t index, const Mat4f& t) { return impl_->engine->set_object_transform(index, t); }

void Renderer::set_wave_scale(float scale) { impl_->engine->set_wave_scale(scale); }

CausticsStats Renderer::caustics_stats(bool wait) { return impl_->engine->stats(wait); }

const char* to_string(ToneMap t) { return t == ToneMap::kFilmic ? "filmic" : "exponential"; }

std::optional<ToneMap> parse_tone_map(const std::string& name) {
  if (name == "filmic") return ToneMap::kFilmic;
  if (name == "exponential") return ToneMap::kExponential;
  return std::nullopt;
}

const char* PassTimes::name(int pass) {
  static const char* const names[kCount] = {"light side", "receivers", "glass", "water", "media", "resolve"};
  return pass >= 0 && pass < kCount ? names[pass] : "?";
}

float PassTimes::total_ms() const {
  float t = 0;
  for (float m : ms) t += m;
  return t;
}

void Renderer::set_pass_timing(bool enabled) {
  Impl& s = *impl_;
  if (enabled && !s.timing) {
    for (auto& slot : s.stamps) {
      for (auto& q : slot) q = gl::make_query(GL_TIMESTAMP);
    }
    s.pending.fill(false);
  }
  s.timing = enabled;
}

PassTimes Renderer::pass_times() {
  Impl& s = *impl_;
  if (s.timing) s.collect();
  return s.times;
}

void Renderer::present(unsigned framebuffer, int width, int height) {
  Impl& s = *impl_;
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glBindVertexArray(s.empty_vao.get());
  glBindTextureUnit(0, s.frame().color.get());
  glBindTextureUnit(1, s.frame().color.get());  // unread without auto exposure
  if (s.display_options.auto_exposure) {
    // Log luminance at the frame's size, averaged down its mip chain
    // (non-power-of-two sizes: the driver's box filter, close to the mean).
    if (s.log_luminance_w != s.frame().width || s.log_luminance_h != s.frame().height) {
      s.log_luminance_w = s.frame().width;
      s.log_luminance_h = s.frame().height;
      s.log_luminance_levels = 1 + static_cast<int>(std::floor(std::log2(std::max(s.frame().width, s.frame().height))));
      s.log_luminance = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(s.log_luminance.get(), s.log_luminance_levels, GL_RG32F, s.frame().width, s.frame().height);
      glTextureParameteri(s.log_luminance.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
      s.log_luminance_fbo = gl::make_framebuffer();
      glNamedFramebufferTexture(s.log_luminance_fbo.get(), GL_COLOR_ATTACHMENT0, s.log_luminance.get(), 0);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, s.log_luminance_fbo.get());
    glViewport(0, 0, s.frame().width, s.frame().height);
    s.luminance.use();
    glBindTextureUnit(2, s.hdr.depth.get());  // the full-size frame's depth: where nothing was drawn is sky
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glGenerateTextureMipmap(s.log_luminance.get());
    glBindTextureUnit(1, s.log_luminance.get());
  }
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  s.present.use();
  s.present.set("u_exposure", std::exp2(s.display_options.exposure_ev));
  s.present.set("u_auto_exposure", s.display_options.auto_exposure ? 1 : 0);
  s.present.set("u_last_level", static_cast<float>(std::max(0, s.log_luminance_levels - 1)));
  s.present.set("u_tone_map", s.display_options.tone_map == ToneMap::kFilmic ? 0 : 1);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glEnable(GL_DEPTH_TEST);
}

namespace {

template <typename T>
void flip_rows(std::vector<T>& px, int width, int height, int channels) {
  const std::size_t row = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
  for (int y = 0; y < height / 2; ++y) {
    std::swap_ranges(px.begin() + static_cast<std::ptrdiff_t>(y * row), px.begin() + static_cast<std::ptrdiff_t>((y + 1) * row),
                     px.begin() + static_cast<std::ptrdiff_t>((height - 1 - y) * row));
  }
}

}  // namespace

std::vector<float> Renderer::read_hdr() {
  Impl& s = *impl_;
  std::vector<float> px(static_cast<std::size_t>(s.frame().width) * static_cast<std::size_t>(s.frame().height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(s.frame().color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  flip_rows(px, s.frame().width, s.frame().height, 4);
  return px;
}

std::vector<std::uint8_t> Renderer::read_display() {
  Impl& s = *impl_;
  s.display.ensure(s.frame().width, s.frame().height, GL_RGBA8, false);
  present(s.display.fbo.get(), s.frame().width, s.frame().height);
  std::vector<std::uint8_t> px(static_cast<std::size_t>(s.frame().width) * static_cast<std::size_t>(s.frame().height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(s.display.color.get(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(px.size()), px.data());
  flip_rows(px, s.frame().width, s.frame().height, 4);
  return px;
}

Camera Renderer::default_camera() const {
  if (impl_->scene().camera) return *impl_->scene().camera;
  Camera c;
  const glm::vec3 lo = impl_->engine->bounds_min(), hi = impl_->engine->bounds_max();
  const glm::vec3 center = 0.5f * (lo + hi);
  const float r = 0.5f * glm::length(hi - lo) + 1e-3f;
  // From above one corner, at the distance where the bounds' eight
  // corners just fit the vertical field of view and a 4:3 frame's
  // horizontal one (wider frames have room to spare; a square one crops
  // the far corners a little), with 5 % to spare: a wide, flat scene (a
  // floor and small objects) fills the frame, where the bounding sphere's
  // distance left it small.
  const glm::vec3 back = glm::normalize(glm::vec3(0.6f, 0.7f, 1.0f));
  const glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0, 1, 0), back)), up = glm::cross(back, right);
  const float slope_y = std::tan(0.5f * glm::radians(c.fov_y_deg)), slope_x = slope_y * 4.0f / 3.0f;
  const auto corner = [&](int k) { return glm::vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z); };
  // The distance from `target` along `back` at which every corner fits.
  const auto fit = [&](const glm::vec3& target) {
    float d = 0;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 p = corner(k) - target;
      const float nearer = glm::dot(p, back);  // how much nearer the eye than the target
      d = std::max({d, std::fabs(glm::dot(p, right)) / slope_x + nearer, std::fabs(glm::dot(p, up)) / slope_y + nearer});
    }
    return d;
  };
  // Then the target moves across the view to the middle of the corners'
  // projections (a floor below the bounds' centre sat low in the frame),
  // and the distance is fitted again: twice is enough to settle.
  glm::vec3 target = center;
  float distance = fit(target);
  for (int pass = 0; pass < 2; ++pass) {
    float x0 = 1e30f, x1 = -1e30f, y0 = 1e30f, y1 = -1e30f;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 p = corner(k) - target;
      const float z = distance - glm::dot(p, back);
      x0 = std::min(x0, glm::dot(p, right) / z), x1 = std::max(x1, glm::dot(p, right) / z);
      y0 = std::min(y0, glm::dot(p, up) / z), y1 = std::max(y1, glm::dot(p, up) / z);
    }
    target += distance * (0.5f * (x0 + x1) * right + 0.5f * (y0 + y1) * up);
    distance = fit(target);
  }
  distance = std::max(1.05f * distance, 1.2f * r);  // outside the bounding sphere
  const glm::vec3 eye = target + back * distance;
  c.position = {eye.x, eye.y, eye.z};
  c.target = {target.x, target.y, target.z};
  c.near_plane = 0.01f * r;
  c.far_plane = distance + 2.0f * r;
  return c;
}

float Renderer::default_exposure_ev() const { return std::clamp(-1.0f - std::log2(impl_->reference), -16.0f, 16.0f); }

glm::vec3 Renderer::bounds_min() const { return impl_->engine->bounds_min(); }
glm::vec3 Renderer::bounds_max() const { return impl_->engine->bounds_max(); }

}  // namespace caustix::sample
