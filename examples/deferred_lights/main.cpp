// A deferred renderer with several lights, caustics on every surface
// (docs/embedding.md, "Deferred and multi-light renderers"):
//   1. a G-buffer pass of its own: world position with the object's index
//      in alpha, world normal, albedo;
//   2. the light side: engine->update(), then engine->bind_all() once;
//   3. ONE lighting pass: a full-screen triangle whose shader includes
//      caustix.glsl with CAUSTIX_ALL_RECEIVERS and calls
//      caustix_irradiance_all(position, normal, object) -- every light,
//      whatever receiver the pixel shows, nothing bound per receiver;
//   4. and the clustered-forward way: each object drawn once, its shader
//      looping over the lights with caustix_irradiance_at().
// The test: a floor under flat water and a deck above it, lit by a white
// sun at 30 degrees and a blue sky light at 50 degrees; per channel, the
// floor reads sum_l E_l T(theta_l) cos(theta_l) c_l and the deck
// sum_l E_l cos(theta_l) c_l (Fresnel on the CPU below) to 1 %, in both passes.
// Exit status 0 when they do, 1 when they do not, 2 on any error.

#include <epoxy/gl.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "caustix/runtime/engine.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/runtime/scene_loader.h"

namespace {

int fail(const std::string& what) {
  std::fprintf(stderr, "deferred_lights: %s\n", what.c_str());
  return 2;
}

GLuint program(const char* vs, const std::string& fs) {
  GLuint p = glCreateProgram();
  for (auto [type, src] : {std::pair{GL_VERTEX_SHADER, std::string(vs)}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
    GLuint s = glCreateShader(type);
    const char* text = src.c_str();
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[4096];
      glGetShaderInfoLog(s, sizeof log, nullptr, log);
      std::fprintf(stderr, "deferred_lights: shader: %s\n", log);
    }
    glAttachShader(p, s);
  }
  glLinkProgram(p);
  GLint linked = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &linked);
  return linked ? p : 0;
}

// The application's mesh shader: its own camera uniform and layout.
const char* kMeshVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
void main() {
  v_world = (u_model * vec4(a_position, 1.0)).xyz;
  v_normal = transpose(inverse(mat3(u_model))) * a_normal;
  gl_Position = u_view_proj * vec4(v_world, 1.0);
})";

const char* kGBuffer = R"(#version 450 core
in vec3 v_world;
in vec3 v_normal;
uniform int u_object;
uniform vec3 u_albedo;
layout(location = 0) out vec4 o_position;  // xyz world, w the object's index (-1: nothing)
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_albedo;
void main() {
  o_position = vec4(v_world, float(u_object));
  o_normal = vec4(normalize(v_normal), 0.0);
  o_albedo = vec4(u_albedo, 1.0);
})";

// The lighting pass: every light at once for whatever receiver the pixel shows.
const char* kFullScreen = R"(#version 450 core
void main() { gl_Position = vec4(vec2(gl_VertexID & 1, gl_VertexID >> 1) * 4.0 - 1.0, 0.0, 1.0); })";
const char* kLighting = R"(
layout(binding = 0) uniform sampler2D g_position;
layout(binding = 1) uniform sampler2D g_normal;
layout(binding = 2) uniform sampler2D g_albedo;
out vec4 o_color;
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec4 p = texelFetch(g_position, px, 0);
  if (p.w < 0.0) discard;
  vec3 n = texelFetch(g_normal, px, 0).xyz;
  // W/m^2 x colour from every light; a Lambertian surface's radiance would be albedo E / pi.
  o_color = vec4(texelFetch(g_albedo, px, 0).rgb * caustix_irradiance_all(p.xyz, n, int(p.w)), 1.0);
})";

// Clustered forward: one draw per object, the lights looped in the shader.
const char* kForward = R"(
in vec3 v_world;
in vec3 v_normal;
uniform int u_object;
uniform vec3 u_albedo;
out vec4 o_color;
void main() {
  vec3 e = vec3(0.0);
  for (int light = 0; light < caustix_light_count(); ++light) e += caustix_irradiance_at(v_world, v_normal, u_object, light);
  o_color = vec4(u_albedo * e, 1.0);
})";

double fresnel_t(double cos_i, double n2) {
  const double sin_t2 = (1 - cos_i * cos_i) / (n2 * n2);
  const double cos_t = std::sqrt(1 - sin_t2);
  const double rs = (cos_i - n2 * cos_t) / (cos_i + n2 * cos_t);
  const double rp = (n2 * cos_i - cos_t) / (n2 * cos_i + cos_t);
  return 1 - 0.5 * (rs * rs + rp * rp);
}

GLuint texture(GLenum format, int n) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &t);
  glTextureStorage2D(t, 1, format, n, n);
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return fail("usage: deferred_lights <scene.cxb>");
  auto context = caustix::runtime::HeadlessContext::create();
  if (!context) return fail(context.error().message);
  std::printf("deferred_lights: %s\n", (*context)->description().c_str());
  auto scene = caustix::runtime::load_scene_file(argv[1]);
  if (!scene) return fail(scene.error().message);
  auto created = caustix::runtime::Engine::create(*scene);
  if (!created) return fail(created.error().message);
  caustix::runtime::Engine& engine = **created;
  const caustix::SceneDesc& desc = engine.scene();

  const std::string include = "#version 450 core\n#define CAUSTIX_ALL_RECEIVERS\n" + engine.glsl_include();
  const GLuint gbuffer_program = program(kMeshVertex, std::string(kGBuffer));
  const GLuint lighting_program = program(kFullScreen, include + kLighting);
  const GLuint forward_program = program(kMeshVertex, include + kForward);
  if (!gbuffer_program || !lighting_program || !forward_program) return fail("a program does not link");

  // The application's targets: a top view of [-8, 8]^2.
  const int n = 128;
  const float half = 8.0f;
  const GLuint position = texture(GL_RGBA32F, n), normal = texture(GL_RGBA32F, n), albedo = texture(GL_RGBA8, n);
  const GLuint depth = texture(GL_DEPTH_COMPONENT32F, n), lit = texture(GL_RGBA32F, n), forward = texture(GL_RGBA32F, n);
  GLuint fbo[3] = {0, 0, 0};
  glCreateFramebuffers(3, fbo);
  glNamedFramebufferTexture(fbo[0], GL_COLOR_ATTACHMENT0, position, 0);
  glNamedFramebufferTexture(fbo[0], GL_COLOR_ATTACHMENT1, normal, 0);
  glNamedFramebufferTexture(fbo[0], GL_COLOR_ATTACHMENT2, albedo, 0);
  glNamedFramebufferTexture(fbo[0], GL_DEPTH_ATTACHMENT, depth, 0);
  const GLenum three[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glNamedFramebufferDrawBuffers(fbo[0], 3, three);
  glNamedFramebufferTexture(fbo[1], GL_COLOR_ATTACHMENT0, lit, 0);
  glNamedFramebufferTexture(fbo[2], GL_COLOR_ATTACHMENT0, forward, 0);
  glNamedFramebufferTexture(fbo[2], GL_DEPTH_ATTACHMENT, depth, 0);
  // Orthographic, straight down: clip x = x / half, clip y = z / half, depth from height.
  const float view_proj[16] = {1 / half, 0, 0, 0, 0, 0, -0.1f, 0, 0, 1 / half, 0, 0, 0, 0, 0, 1};

  caustix::runtime::FrameUpdate frame;
  frame.caustics = engine.default_options();
  if (auto st = engine.update(frame); !st) return fail(st.error().message);

  // Every object with `program` (the mesh shader's uniforms: camera, model, index, albedo).
  auto draw_objects = [&](GLuint program) -> caustix::Status {
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_view_proj"), 1, GL_FALSE, view_proj);
    for (std::uint32_t oi = 0; oi < desc.objects.size(); ++oi) {
      const auto& a = desc.objects[oi].material.albedo;
      glUniformMatrix4fv(glGetUniformLocation(program, "u_model"), 1, GL_FALSE, desc.objects[oi].transform.data());
      glUniform1i(glGetUniformLocation(program, "u_object"), static_cast<int>(oi));
      glUniform3f(glGetUniformLocation(program, "u_albedo"), a[0], a[1], a[2]);
      if (auto st = engine.draw_object(oi); !st) return st;
    }
    return caustix::Status::success();
  };

  // 1. The G-buffer.
  glBindFramebuffer(GL_FRAMEBUFFER, fbo[0]);
  glViewport(0, 0, n, n);
  const float empty[4] = {0, 0, 0, -1};
  for (int i = 0; i < 3; ++i) glClearBufferfv(GL_COLOR, i, empty);
  glClearBufferfi(GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glEnable(GL_DEPTH_TEST);
  if (auto st = draw_objects(gbuffer_program); !st) return fail(st.error().message);

  // 2-3. Every receiver, every light: one bind, one full-screen pass.
  if (auto st = engine.bind_all(); !st) return fail(st.error().message);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo[1]);
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  glDisable(GL_DEPTH_TEST);
  glBindTextureUnit(0, position);
  glBindTextureUnit(1, normal);
  glBindTextureUnit(2, albedo);
  GLuint vao = 0;
  glCreateVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glUseProgram(lighting_program);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  // 4. Clustered forward: each object once, on the G-buffer's depth.
  glBindFramebuffer(GL_FRAMEBUFFER, fbo[2]);
  glClearBufferfv(GL_COLOR, 0, zero);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  if (auto st = draw_objects(forward_program); !st) return fail(st.error().message);

  auto read = [&](GLuint tex) {
    std::vector<float> px(std::size_t{n} * n * 4);
    glGetTextureImage(tex, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
    return px;
  };
  const std::vector<float> deferred_px = read(lit), forward_px = read(forward);
  if (glGetError() != GL_NO_ERROR) return fail("a GL error in the application's passes");

  // The physics, per channel: the floor through flat water, the deck in air.
  double floor_e[3] = {0, 0, 0}, deck_e[3] = {0, 0, 0};
  for (const caustix::Light& l : desc.lights) {
    const double cos_i = -l.direction[1] / std::sqrt(l.direction[0] * l.direction[0] + l.direction[1] * l.direction[1] + l.direction[2] * l.direction[2]);
    for (int c = 0; c < 3; ++c) {
      floor_e[c] += l.irradiance * l.color[c] * fresnel_t(cos_i, desc.water->ior) * cos_i;
      deck_e[c] += l.irradiance * l.color[c] * cos_i;
    }
  }
  int failures = 0;
  for (auto [name, px] : {std::pair{"deferred", &deferred_px}, std::pair{"forward", &forward_px}}) {
    // Pixel centres: x = (i + 0.5) / n * 2 half - half, z likewise from the row.
    double worst_floor = 0, worst_deck = 0;
    int floor_count = 0, deck_count = 0;
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) / n * 2 * half - half, z = (j + 0.5) / n * 2 * half - half;
        const float* p = &(*px)[(std::size_t(j) * n + i) * 4];
        const bool on_floor = std::fabs(x) < 1.5 && std::fabs(z) < 1.5;
        const bool on_deck = std::fabs(x + 6) < 0.8 && std::fabs(z) < 0.8;
        for (int c = 0; c < 3; ++c) {
          if (on_floor) worst_floor = std::max(worst_floor, std::fabs(p[c] / floor_e[c] - 1));
          if (on_deck) worst_deck = std::max(worst_deck, std::fabs(p[c] / deck_e[c] - 1));
        }
        floor_count += on_floor;
        deck_count += on_deck;
      }
    }
    std::printf("deferred_lights: %s: floor (%d px) worst channel off by %.3f %% of %.4f/%.4f/%.4f; deck (%d px) off by %.3f %% of %.4f/%.4f/%.4f\n",
                name, floor_count, 100 * worst_floor, floor_e[0], floor_e[1], floor_e[2], deck_count, 100 * worst_deck, deck_e[0],
                deck_e[1], deck_e[2]);
    failures += !(worst_floor < 0.01 && worst_deck < 0.01 && floor_count > 0 && deck_count > 0);
  }
  return failures == 0 ? 0 : 1;
}
