#include "caustix/runtime/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "caustix_shaders.h"
#include "gl_program.h"

namespace caustix::runtime {
namespace {

constexpr int kShadowSize = 2048;
constexpr int kShadowCubeSize = 1024;
constexpr int kMaxWaves = 256;  // matches water.vert.glsl
constexpr float kAmbient = 0.12f;

glm::vec3 to_glm(const Vec3f& v) { return {v[0], v[1], v[2]}; }
glm::mat4 to_glm(const Mat4f& m) { return glm::make_mat4(m.data()); }

struct GpuMesh {
  gl::VertexArray vao;
  gl::Buffer vertices;
  gl::Buffer indices;
  GLsizei index_count = 0;
};

GpuMesh upload(const TriangleMesh& m) {
  GpuMesh g;
  std::vector<float> interleaved;
  interleaved.reserve(m.positions.size() * 6);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    interleaved.insert(interleaved.end(), m.positions[i].begin(), m.positions[i].end());
    interleaved.insert(interleaved.end(), m.normals[i].begin(), m.normals[i].end());
  }
  g.vertices = gl::make_buffer();
  glNamedBufferStorage(g.vertices.get(), static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data(), 0);
  g.indices = gl::make_buffer();
  glNamedBufferStorage(g.indices.get(), static_cast<GLsizeiptr>(m.triangles.size() * 12), m.triangles.data(), 0);
  g.index_count = static_cast<GLsizei>(m.triangles.size() * 3);
  g.vao = gl::make_vertex_array();
  const GLuint vao = g.vao.get();
  glVertexArrayVertexBuffer(vao, 0, g.vertices.get(), 0, 6 * sizeof(float));
  glVertexArrayElementBuffer(vao, g.indices.get());
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao, 0, 0);
  glEnableVertexArrayAttrib(vao, 1);
  glVertexArrayAttribFormat(vao, 1, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
  glVertexArrayAttribBinding(vao, 1, 0);
  return g;
}

// A colour + depth render target of a given size.
struct Target {
  gl::Framebuffer fbo;
  gl::Texture color;
  gl::Texture depth;
  int width = 0, height = 0;

  void ensure(int w, int h, GLenum color_format, bool with_depth) {
    if (w == width && h == height && fbo.get()) return;
    width = w;
    height = h;
    fbo = gl::make_framebuffer();
    color = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(color.get(), 1, color_format, w, h);
    glTextureParameteri(color.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(color.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
    if (with_depth) {
      depth = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(depth.get(), 1, GL_DEPTH_COMPONENT32F, w, h);
      glNamedFramebufferTexture(fbo.get(), GL_DEPTH_ATTACHMENT, depth.get(), 0);
    }
  }
};

struct WaveBlock {  // std140 layout of the Waves block in water.vert.glsl
  glm::vec4 a[kMaxWaves];
  glm::vec4 b[kMaxWaves];
  glm::ivec4 count;
};

}  // namespace

struct Renderer::Impl {
  SceneDesc scene;
  std::vector<GpuMesh> meshes;
  glm::vec3 lo{0}, hi{0};

  gl::Program receiver, shadow, water, present;
  gl::VertexArray empty_vao;  // for the full-screen triangle

  // Shadow maps: created only for the light kinds the scene has.
  gl::Texture shadow_2d, shadow_cube;
  gl::Framebuffer shadow_fbo;

  // Water grid (only with water).
  gl::VertexArray water_vao;
  gl::Buffer water_vertices, water_indices, wave_ubo;
  GLsizei water_index_count = 0;

  Target hdr, display;
  float exposure = 1.0f;

  void draw_objects(const gl::Program& p, bool casters_only) const {
    for (const Object& o : scene.objects) {
      if (casters_only && is_transparent(o.role)) continue;  // glass casts caustics, not plain shadows
      const glm::mat4 model = to_glm(o.transform);
      p.set("u_model", model);
      p.set("u_normal_matrix", glm::mat3(glm::transpose(glm::inverse(model))));
      p.set("u_albedo", to_glm(o.material.albedo));
      const GpuMesh& m = meshes[o.mesh_index];
      glBindVertexArray(m.vao.get());
      glDrawElements(GL_TRIANGLES, m.index_count, GL_UNSIGNED_INT, nullptr);
    }
  }

  float scene_radius() const { return 0.5f * glm::length(hi - lo) + 1e-3f; }
  glm::vec3 scene_center() const { return 0.5f * (lo + hi); }

  // Renders the directional shadow map; returns world -> shadow texture.
  glm::mat4 render_directional_shadow(const Light& light) {
    const glm::vec3 dir = glm::normalize(to_glm(light.direction));
    const float r = scene_radius();
    const glm::vec3 c = scene_center();
    const glm::vec3 up = std::fabs(dir.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::mat4 view = glm::lookAt(c - dir * (2.0f * r), c, up);
    const glm::mat4 proj = glm::ortho(-r, r, -r, r, 0.01f * r, 4.0f * r);
    glNamedFramebufferTexture(shadow_fbo.get(), GL_DEPTH_ATTACHMENT, shadow_2d.get(), 0);
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo.get());
    glViewport(0, 0, kShadowSize, kShadowSize);
    glClear(GL_DEPTH_BUFFER_BIT);
    shadow.use();
    shadow.set("u_view_proj", proj * view);
    shadow.set("u_linear_depth", 0);
    draw_objects(shadow, true);
    const glm::mat4 bias = glm::translate(glm::mat4(1), glm::vec3(0.5f)) * glm::scale(glm::mat4(1), glm::vec3(0.5f));
    return bias * proj * view;
  }

  float render_point_shadow(const Light& light) {
    const glm::vec3 pos = to_glm(light.position);
    const float far = glm::length(pos - scene_center()) + 2.0f * scene_radius();
    const glm::mat4 proj = glm::perspective(glm::radians(90.0f), 1.0f, 0.01f, far);
    // Cube face orientations (GL convention: +X, -X, +Y, -Y, +Z, -Z).
    const glm::vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    shadow.use();
    shadow.set("u_linear_depth", 1);
    shadow.set("u_light_position", pos);
    shadow.set("u_far", far);
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo.get());
    glViewport(0, 0, kShadowCubeSize, kShadowCubeSize);
    for (int f = 0; f < 6; ++f) {
      glNamedFramebufferTextureLayer(shadow_fbo.get(), GL_DEPTH_ATTACHMENT, shadow_cube.get(), 0, f);
      glClear(GL_DEPTH_BUFFER_BIT);
      shadow.set("u_view_proj", proj * glm::lookAt(pos, pos + dirs[f], ups[f]));
      draw_objects(shadow, true);
    }
    return far;
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create(const RuntimeScene& scene) {
  std::unique_ptr<Renderer> r(new Renderer());
  Impl& s = *r->impl_;
  s.scene = scene.desc;

  auto receiver = gl::Program::build("receiver", shaders::k_mesh_vert_glsl, shaders::k_receiver_frag_glsl);
  if (!receiver) return receiver.error();
  s.receiver = std::move(*receiver);
  auto shadow = gl::Program::build("shadow", shaders::k_mesh_vert_glsl, shaders::k_shadow_frag_glsl);
  if (!shadow) return shadow.error();
  s.shadow = std::move(*shadow);
  auto present = gl::Program::build("present", shaders::k_present_vert_glsl, shaders::k_present_frag_glsl);
  if (!present) return present.error();
  s.present = std::move(*present);
  s.empty_vao = gl::make_vertex_array();

  for (const TriangleMesh& m : scene.meshes) s.meshes.push_back(upload(m));

  // World bounds of the objects (for shadow frusta and the default camera).
  bool first = true;
  for (const Object& o : s.scene.objects) {
    const MeshInfo& mi = s.scene.meshes[o.mesh_index];
    const glm::mat4 model = to_glm(o.transform);
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 corner((c & 1) ? mi.bounds_max[0] : mi.bounds_min[0], (c & 2) ? mi.bounds_max[1] : mi.bounds_min[1],
                             (c & 4) ? mi.bounds_max[2] : mi.bounds_min[2]);
      const glm::vec3 w = glm::vec3(model * glm::vec4(corner, 1.0f));
      s.lo = first ? w : glm::min(s.lo, w);
      s.hi = first ? w : glm::max(s.hi, w);
      first = false;
    }
  }

  bool has_directional = false, has_point = false;
  for (const Light& l : s.scene.lights) {
    has_directional = has_directional || l.type == LightType::kDirectional;
    has_point = has_point || l.type == LightType::kPoint;
  }
  if (has_directional || has_point) {
    s.shadow_fbo = gl::make_framebuffer();
    glNamedFramebufferDrawBuffer(s.shadow_fbo.get(), GL_NONE);
  }
  auto shadow_params = [](GLuint tex) {
    glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(tex, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  };
  if (has_directional) {
    s.shadow_2d = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(s.shadow_2d.get(), 1, GL_DEPTH_COMPONENT32F, kShadowSize, kShadowSize);
    shadow_params(s.shadow_2d.get());
  }
  if (has_point) {
    s.shadow_cube = gl::make_texture(GL_TEXTURE_CUBE_MAP);
    glTextureStorage2D(s.shadow_cube.get(), 1, GL_DEPTH_COMPONENT32F, kShadowCubeSize, kShadowCubeSize);
    shadow_params(s.shadow_cube.get());
  }

  if (s.scene.water) {
    const Water& w = *s.scene.water;
    auto water = gl::Program::build("water", shaders::k_water_vert_glsl, shaders::k_water_frag_glsl);
    if (!water) return water.error();
    s.water = std::move(*water);
    const std::uint32_t nx = w.cells[0], nz = w.cells[1];
    std::vector<float> xz;
    xz.reserve(std::size_t{nx + 1} * (nz + 1) * 2);
    for (std::uint32_t j = 0; j <= nz; ++j) {
      for (std::uint32_t i = 0; i <= nx; ++i) {
        xz.push_back(w.extent[0] + (w.extent[2] - w.extent[0]) * static_cast<float>(i) / static_cast<float>(nx));
        xz.push_back(w.extent[1] + (w.extent[3] - w.extent[1]) * static_cast<float>(j) / static_cast<float>(nz));
      }
    }
    std::vector<std::uint32_t> idx;
    idx.reserve(std::size_t{nx} * nz * 6);
    for (std::uint32_t j = 0; j < nz; ++j) {
      for (std::uint32_t i = 0; i < nx; ++i) {
        const std::uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
        idx.insert(idx.end(), {a, c, b, b, c, d});  // counter-clockwise seen from +y
      }
    }
    s.water_vertices = gl::make_buffer();
    glNamedBufferStorage(s.water_vertices.get(), static_cast<GLsizeiptr>(xz.size() * sizeof(float)), xz.data(), 0);
    s.water_indices = gl::make_buffer();
    glNamedBufferStorage(s.water_indices.get(), static_cast<GLsizeiptr>(idx.size() * 4), idx.data(), 0);
    s.water_index_count = static_cast<GLsizei>(idx.size());
    s.water_vao = gl::make_vertex_array();
    glVertexArrayVertexBuffer(s.water_vao.get(), 0, s.water_vertices.get(), 0, 2 * sizeof(float));
    glVertexArrayElementBuffer(s.water_vao.get(), s.water_indices.get());
    glEnableVertexArrayAttrib(s.water_vao.get(), 0);
    glVertexArrayAttribFormat(s.water_vao.get(), 0, 2, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(s.water_vao.get(), 0, 0);

    auto block = std::make_unique<WaveBlock>();
    std::memset(block.get(), 0, sizeof(WaveBlock));
    const std::size_t n = std::min<std::size_t>(w.waves.size(), kMaxWaves);
    for (std::size_t i = 0; i < n; ++i) {
      const Wave& wave = w.waves[i];
      const float k = 2.0f * 3.14159265358979f / wave.wavelength;
      block->a[i] = glm::vec4(wave.amplitude, k, wave.direction[0], wave.direction[1]);
      block->b[i] = glm::vec4(k * wave.speed, wave.phase, 0, 0);
    }
    block->count = glm::ivec4(static_cast<int>(n), 0, 0, 0);
    s.wave_ubo = gl::make_buffer();
    glNamedBufferStorage(s.wave_ubo.get(), sizeof(WaveBlock), block.get(), 0);
  }
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("renderer set-up"));
  return r;
}

Status Renderer::render(const FrameParams& f) {
  Impl& s = *impl_;
  if (f.width <= 0 || f.height <= 0 || f.width > 16384 || f.height > 16384) {
    return make_error(ErrorCode::kUsage, "image size " + std::to_string(f.width) + "x" + std::to_string(f.height) +
                                             " is outside 1..16384");
  }
  s.hdr.ensure(f.width, f.height, GL_RGBA32F, true);

  const glm::vec3 eye = to_glm(f.camera.position);
  const glm::mat4 view = glm::lookAt(eye, to_glm(f.camera.target), to_glm(f.camera.up));
  const glm::mat4 proj = glm::perspective(glm::radians(f.camera.fov_y_deg),
                                          static_cast<float>(f.width) / static_cast<float>(f.height),
                                          f.camera.near_plane, f.camera.far_plane);
  const glm::mat4 view_proj = proj * view;
  const glm::vec3 sky(kSkyColor[0], kSkyColor[1], kSkyColor[2]);

  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);

  // Ambient pass: lays down depth.
  glBindFramebuffer(GL_FRAMEBUFFER, s.hdr.fbo.get());
  glViewport(0, 0, f.width, f.height);
  const float clear[4] = {sky.r, sky.g, sky.b, 0.0f};
  glClearNamedFramebufferfv(s.hdr.fbo.get(), GL_COLOR, 0, clear);
  glClear(GL_DEPTH_BUFFER_BIT);
  glDepthFunc(GL_LESS);
  s.receiver.use();
  s.receiver.set("u_view_proj", view_proj);
  s.receiver.set("u_pass", 0);
  s.receiver.set("u_ambient", kAmbient * sky);
  s.draw_objects(s.receiver, false);

  // One additive pass per light (eq. 4-20's sum over lights, without caustics yet).
  for (const Light& light : s.scene.lights) {
    glm::mat4 shadow_matrix(1.0f);
    float shadow_far = 1.0f;
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    if (light.type == LightType::kDirectional) shadow_matrix = s.render_directional_shadow(light);
    else shadow_far = s.render_point_shadow(light);

    glBindFramebuffer(GL_FRAMEBUFFER, s.hdr.fbo.get());
    glViewport(0, 0, f.width, f.height);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LEQUAL);
    s.receiver.use();
    s.receiver.set("u_view_proj", view_proj);
    const bool dir = light.type == LightType::kDirectional;
    s.receiver.set("u_pass", dir ? 1 : 2);
    s.receiver.set("u_light_direction", to_glm(light.direction));
    s.receiver.set("u_light_position", to_glm(light.position));
    s.receiver.set("u_light_power", to_glm(light.color) * (dir ? light.irradiance : light.intensity));
    s.receiver.set("u_shadow_matrix", shadow_matrix);
    s.receiver.set("u_shadow_far", shadow_far);
    s.receiver.set("u_shadow_texel", 2.0f * s.scene_radius() / kShadowSize);
    glBindTextureUnit(0, s.shadow_2d.get());
    glBindTextureUnit(1, s.shadow_cube.get());
    s.draw_objects(s.receiver, false);
  }

  if (s.scene.water) {
    glm::vec3 sun_dir(0.0f), sun_color(0.0f);
    for (const Light& l : s.scene.lights) {
      if (l.type == LightType::kDirectional) {
        sun_dir = to_glm(l.direction);
        sun_color = to_glm(l.color) * l.irradiance;
        break;
      }
    }
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LESS);
    s.water.use();
    s.water.set("u_view_proj", view_proj);
    s.water.set("u_level", s.scene.water->level);
    s.water.set("u_time", f.time);
    s.water.set("u_eye", eye);
    s.water.set("u_sky", sky);
    s.water.set("u_ior", s.scene.water->ior);
    s.water.set("u_sun_direction", sun_dir);
    s.water.set("u_sun_color", sun_color);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, s.wave_ubo.get());
    glBindVertexArray(s.water_vao.get());
    glDrawElements(GL_TRIANGLES, s.water_index_count, GL_UNSIGNED_INT, nullptr);
  }
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glBindVertexArray(0);
  return gl::check_gl("frame");
}

void Renderer::present(unsigned framebuffer, int width, int height) {
  Impl& s = *impl_;
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  s.present.use();
  s.present.set("u_exposure", s.exposure);
  glBindTextureUnit(0, s.hdr.color.get());
  glBindVertexArray(s.empty_vao.get());
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
  std::vector<float> px(static_cast<std::size_t>(s.hdr.width) * static_cast<std::size_t>(s.hdr.height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(s.hdr.color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  flip_rows(px, s.hdr.width, s.hdr.height, 4);
  return px;
}

std::vector<std::uint8_t> Renderer::read_display() {
  Impl& s = *impl_;
  s.display.ensure(s.hdr.width, s.hdr.height, GL_RGBA8, false);
  present(s.display.fbo.get(), s.hdr.width, s.hdr.height);
  std::vector<std::uint8_t> px(static_cast<std::size_t>(s.hdr.width) * static_cast<std::size_t>(s.hdr.height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(s.display.color.get(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(px.size()), px.data());
  flip_rows(px, s.hdr.width, s.hdr.height, 4);
  return px;
}

Camera Renderer::default_camera() const {
  if (impl_->scene.camera) return *impl_->scene.camera;
  Camera c;
  const glm::vec3 center = impl_->scene_center();
  const float r = impl_->scene_radius();
  const glm::vec3 eye = center + glm::normalize(glm::vec3(0.6f, 0.7f, 1.0f)) * (2.8f * r);
  c.position = {eye.x, eye.y, eye.z};
  c.target = {center.x, center.y, center.z};
  c.near_plane = 0.01f * r;
  c.far_plane = 10.0f * r;
  return c;
}

glm::vec3 Renderer::bounds_min() const { return impl_->lo; }
glm::vec3 Renderer::bounds_max() const { return impl_->hi; }

}  // namespace caustix::runtime
