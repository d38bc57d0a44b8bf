// Engine::bind_all() and caustix.glsl's CAUSTIX_ALL_RECEIVERS mode (issue
// 46): a deferred pass -- a G-buffer of world position, normal and object
// index, then one full-screen pass that calls caustix_irradiance_all() --
// must light every receiver from every light as the per-pair path does
// (bind(object, light) and caustix_irradiance() in an additive forward
// pass per light and object), in scenes with water caustics, glass, a
// mirror's caustic map, point and spot lights; and a still scene's update
// copies nothing into the table.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "bake_fixture.h"
#include "caustix/runtime/engine.h"
#include "caustix/runtime/gl_objects.h"
#include "gl_fixture.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

using runtime::Engine;

class AllReceivers : public test::GlTest {};

constexpr int kSize = 192;

const char* kVertex = R"(#version 450 core
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

runtime::gl::Program build(const std::string& name, const char* vs, const std::string& fs) {
  auto p = runtime::gl::Program::build(name.c_str(), vs, fs.c_str());
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error().message);
  return p.ok() ? std::move(*p) : runtime::gl::Program{};
}

struct Images {
  std::vector<float> forward, deferred;  // irradiance rgb per pixel
  std::vector<int> object;               // -1: background
};

// Renders the receivers seen from `view_proj` both ways.
Images render_both(Engine& engine, const glm::mat4& view_proj, bool level0) {
  const SceneDesc& sc = engine.scene();
  Images out;
  runtime::gl::Texture color = runtime::gl::make_texture(GL_TEXTURE_2D), position = runtime::gl::make_texture(GL_TEXTURE_2D),
                       normal = runtime::gl::make_texture(GL_TEXTURE_2D), depth = runtime::gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, kSize, kSize);
  glTextureStorage2D(position.get(), 1, GL_RGBA32F, kSize, kSize);
  glTextureStorage2D(normal.get(), 1, GL_RGBA32F, kSize, kSize);
  glTextureStorage2D(depth.get(), 1, GL_DEPTH_COMPONENT32F, kSize, kSize);
  runtime::gl::Framebuffer gbuffer = runtime::gl::make_framebuffer(), target = runtime::gl::make_framebuffer();
  glNamedFramebufferTexture(gbuffer.get(), GL_COLOR_ATTACHMENT0, position.get(), 0);
  glNamedFramebufferTexture(gbuffer.get(), GL_COLOR_ATTACHMENT1, normal.get(), 0);
  glNamedFramebufferTexture(gbuffer.get(), GL_DEPTH_ATTACHMENT, depth.get(), 0);
  const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(gbuffer.get(), 2, both);
  glNamedFramebufferTexture(target.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  glNamedFramebufferTexture(target.get(), GL_DEPTH_ATTACHMENT, depth.get(), 0);

  // The G-buffer: world position and the object's index, world normal.
  runtime::gl::Program g = build("gbuffer", kVertex, R"(#version 450 core
in vec3 v_world;
in vec3 v_normal;
uniform int u_object;
layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;
void main() { o_position = vec4(v_world, float(u_object)); o_normal = vec4(normalize(v_normal), 0.0); })");
  glBindFramebuffer(GL_FRAMEBUFFER, gbuffer.get());
  glViewport(0, 0, kSize, kSize);
  const float background[4] = {0, 0, 0, -1};
  glClearNamedFramebufferfv(gbuffer.get(), GL_COLOR, 0, background);
  glClearNamedFramebufferfv(gbuffer.get(), GL_COLOR, 1, background);
  glClearNamedFramebufferfi(gbuffer.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  g.use();
  g.set("u_view_proj", view_proj);
  std::vector<std::uint32_t> receivers;
  for (std::uint32_t oi = 0; oi < sc.objects.size(); ++oi) {
    if (transmits(sc.objects[oi].role)) continue;
    receivers.push_back(oi);
    g.set("u_model", glm::make_mat4(sc.objects[oi].transform.data()));
    g.set("u_object", static_cast<int>(oi));
    EXPECT_TRUE(engine.draw_object(oi).ok());
  }

  // Forward, the per-pair path: each light and receiver added, on the
  // G-buffer's depth.
  runtime::gl::Program f = build("forward", kVertex, "#version 450 core\n" + engine.glsl_include() + R"(
in vec3 v_world;
in vec3 v_normal;
out vec4 o;
void main() { o = vec4(caustix_irradiance(v_world, v_normal), 1.0); })");
  glBindFramebuffer(GL_FRAMEBUFFER, target.get());
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(target.get(), GL_COLOR, 0, zero);
  glDepthFunc(GL_EQUAL);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  f.use();
  f.set("u_view_proj", view_proj);
  for (std::uint32_t li = 0; li < sc.lights.size(); ++li) {
    for (std::uint32_t oi : receivers) {
      f.set("u_model", glm::make_mat4(sc.objects[oi].transform.data()));
      EXPECT_TRUE(engine.bind(oi, li).ok());
      // The water's caustics maps have mip levels; the table holds level 0,
      // which is all a deferred pass can pick. The forward pass is made to
      // read level 0 as well, so that the two compare the same texels.
      const auto r = engine.lighting(oi, li);
      for (GLuint t : {r->caustics, r->caustics_color}) glTextureParameteri(t, GL_TEXTURE_MAX_LEVEL, level0 ? 0 : 1000);
      EXPECT_TRUE(engine.draw_object(oi).ok());
      for (GLuint t : {r->caustics, r->caustics_color}) glTextureParameteri(t, GL_TEXTURE_MAX_LEVEL, 1000);
    }
  }
  auto read = [&](GLuint tex) {
    std::vector<float> px(std::size_t{kSize} * kSize * 4);
    glGetTextureImage(tex, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * 4), px.data());
    return px;
  };
  out.forward = read(color.get());

  // Deferred: one full-screen pass over the G-buffer, every light.
  runtime::gl::Program d = build("deferred", "#version 450 core\nvoid main() { gl_Position = vec4(vec2(gl_VertexID & 1, gl_VertexID >> 1) * 4.0 - 1.0, 0.0, 1.0); }\n",
                                 "#version 450 core\n#define CAUSTIX_ALL_RECEIVERS\n" + engine.glsl_include() + R"(
layout(binding = 0) uniform sampler2D u_position;
layout(binding = 1) uniform sampler2D u_normal;
out vec4 o;
void main() {
  vec4 p = texelFetch(u_position, ivec2(gl_FragCoord.xy), 0);
  if (p.w < 0.0) discard;
  o = vec4(caustix_irradiance_all(p.xyz, texelFetch(u_normal, ivec2(gl_FragCoord.xy), 0).xyz, int(p.w)), 1.0);
})");
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glClearNamedFramebufferfv(target.get(), GL_COLOR, 0, zero);
  EXPECT_TRUE(engine.bind_all().ok());
  glBindTextureUnit(0, position.get());
  glBindTextureUnit(1, normal.get());
  runtime::gl::VertexArray vao = runtime::gl::make_vertex_array();
  glBindVertexArray(vao.get());
  d.use();
  glDrawArrays(GL_TRIANGLES, 0, 3);
  out.deferred = read(color.get());
  const std::vector<float> pos = read(position.get());
  for (std::size_t i = 0; i < pos.size(); i += 4) out.object.push_back(static_cast<int>(pos[i + 3]));

  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  return out;
}

struct Case {
  const char* scene;
  nlohmann::json extra_light;
};

// The deferred pass gives the per-pair image: the two read the same
// texels through the same code, so they agree to float rounding. Where the
// forward path minifies the water's mipmapped caustics map it reads a
// coarser level than the table's level 0; that difference is printed (the
// aliasing a deferred pass accepts; docs/embedding.md).
TEST_F(AllReceivers, ADeferredPassLightsEveryReceiverFromEveryLightAsBindDoes) {
  const Case cases[] = {
      {"wavy_pool", {{"type", "point"}, {"position", {1.0, 4.0, 0.5}}, {"intensity", 6.0}, {"color", {1.0, 0.6, 0.3}}}},
      {"glass_ball", {{"type", "spot"}, {"position", {-1.0, 2.5, 0.5}}, {"direction", {0.3, -1.0, -0.2}}, {"intensity", 3.0},
                      {"inner_cone_deg", 20.0}, {"outer_cone_deg", 35.0}}},
      {"mirror_ring", {{"type", "directional"}, {"direction", {-0.3, -1.0, 0.2}}, {"irradiance", 0.5}, {"color", {0.4, 0.7, 1.0}}}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.scene);
    nlohmann::json j = test::canonical_scene(c.scene);
    j["lights"].push_back(c.extra_light);
    auto loaded = test::bake_and_load(test::write_scene(j, std::string("all_receivers_") + c.scene));
    ASSERT_TRUE(loaded);
    auto created = Engine::create(*loaded);
    ASSERT_TRUE(created.ok()) << created.error().message;
    Engine& engine = **created;
    ASSERT_EQ(engine.scene().lights.size(), 2u);
    runtime::FrameUpdate frame;
    frame.time = 0.7f;
    frame.caustics = engine.default_options();
    ASSERT_TRUE(engine.update(frame).ok());
    const auto& cam = j["camera"];
    const glm::vec3 eye(cam["position"][0], cam["position"][1], cam["position"][2]);
    const glm::vec3 at(cam["target"][0], cam["target"][1], cam["target"][2]);
    const glm::mat4 view_proj = glm::perspective(glm::radians(cam.value("fov_y_deg", 45.0f)), 1.0f, 0.05f, 100.0f) *
                                glm::lookAt(eye, at, glm::vec3(0, 1, 0));
    const Images im = render_both(engine, view_proj, true);
    double worst = 0, sum_f = 0, sum_d = 0;
    std::size_t lit = 0;
    for (std::size_t i = 0; i < im.object.size(); ++i) {
      if (im.object[i] < 0) continue;
      const glm::dvec3 f(im.forward[4 * i], im.forward[4 * i + 1], im.forward[4 * i + 2]);
      const glm::dvec3 d(im.deferred[4 * i], im.deferred[4 * i + 1], im.deferred[4 * i + 2]);
      sum_f += f.r + f.g + f.b;
      sum_d += d.r + d.g + d.b;
      worst = std::max(worst, glm::length(f - d) / std::max(glm::length(f), 0.05));
      ++lit;
    }
    std::printf("%s: %zu receiver pixels, both lights: forward total %.6g, deferred %.6g, worst pixel off by %.2e\n", c.scene, lit,
                sum_f, sum_d, worst);
    ASSERT_GT(lit, 1000u);
    EXPECT_GT(sum_f, 100.0);
    EXPECT_NEAR(sum_d / sum_f, 1.0, 1e-5);
    EXPECT_LT(worst, 1e-4);
    // A still frame copies nothing into the table; moving water copies its
    // caustics maps (those of the lights whose products were remade).
    ASSERT_TRUE(engine.update(frame).ok());
    runtime::CausticsStats st = engine.stats();
    EXPECT_EQ(st.work.table_copies, 0u);
    EXPECT_EQ(st.gl.syncs, 0u);
    EXPECT_GT(st.memory.receiver_table, 0u);
    engine.set_wave_scale(0.9f);  // wavy_pool's sine stands still in time
    ASSERT_TRUE(engine.update(frame).ok());
    st = engine.stats();
    std::printf("%s: table %.2f MB; moving water: %u textures, %.2f MB copied per frame\n", c.scene, st.memory.receiver_table / 1048576.0,
                st.work.table_copies, st.work.table_copied_bytes / 1048576.0);
    EXPECT_EQ(st.work.table_copies > 0, engine.scene().water.has_value());
    if (engine.scene().water) {
      const Images mip = render_both(engine, view_proj, false);
      double l1 = 0, total = 0;
      for (std::size_t i = 0; i < mip.forward.size(); ++i) {
        if (i % 4 == 3) continue;
        l1 += std::fabs(mip.forward[i] - mip.deferred[i]);
        total += mip.forward[i];
      }
      std::printf("%s, forward with the maps' mip levels: total %.6g, relative L1 %.2f %%\n", c.scene, total, 100 * l1 / total);
    }
  }
}

}  // namespace
}  // namespace caustix
