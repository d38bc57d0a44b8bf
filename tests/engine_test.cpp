// The public Engine API as an application uses it (runtime/include/caustix/
// runtime/engine.h): every call leaves the GL state it found (a list of
// state queries compared before and after, from a deliberately unusual
// starting state), the application's water heights light the pool as the
// wave list does, and bad arguments are refused without side effects.

#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "bake_fixture.h"
#include "caustix/runtime/engine.h"
#include "gl_objects.h"
#include "caustix/runtime/version.h"
#include "caustix/runtime/water_sim.h"
#include "gl_fixture.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

using runtime::Engine;

ErrorCode code_of(const Status& s) { return s.ok() ? ErrorCode::kInternal : s.error().code; }

std::string scene(const std::string& name) { return std::string(CAUSTIX_SOURCE_DIR) + "/assets/scenes/" + name + ".json"; }

// The GL state an embedding application may rely on, as named values.
using Snapshot = std::map<std::string, std::int64_t>;

Snapshot snapshot() {
  Snapshot s;
  auto geti = [&](const char* name, GLenum e) {
    GLint v[4] = {0, 0, 0, 0};
    glGetIntegerv(e, v);
    s[name] = v[0];
  };
  auto get4 = [&](const char* name, GLenum e) {
    GLint v[4] = {0, 0, 0, 0};
    glGetIntegerv(e, v);
    for (int i = 0; i < 4; ++i) s[std::string(name) + "[" + std::to_string(i) + "]"] = v[i];
  };
  auto getb4 = [&](const char* name, GLenum e) {
    GLboolean v[4] = {0, 0, 0, 0};
    glGetBooleanv(e, v);
    for (int i = 0; i < 4; ++i) s[std::string(name) + "[" + std::to_string(i) + "]"] = v[i];
  };
  geti("draw_fbo", GL_DRAW_FRAMEBUFFER_BINDING);
  geti("read_fbo", GL_READ_FRAMEBUFFER_BINDING);
  geti("program", GL_CURRENT_PROGRAM);
  geti("vao", GL_VERTEX_ARRAY_BINDING);
  geti("active_texture", GL_ACTIVE_TEXTURE);
  get4("viewport", GL_VIEWPORT);
  get4("scissor_box", GL_SCISSOR_BOX);
  getb4("color_mask", GL_COLOR_WRITEMASK);
  geti("depth_mask", GL_DEPTH_WRITEMASK);
  geti("depth_func", GL_DEPTH_FUNC);
  geti("cull_face_mode", GL_CULL_FACE_MODE);
  geti("front_face", GL_FRONT_FACE);
  geti("blend_src_rgb", GL_BLEND_SRC_RGB);
  geti("blend_dst_rgb", GL_BLEND_DST_RGB);
  geti("blend_src_alpha", GL_BLEND_SRC_ALPHA);
  geti("blend_dst_alpha", GL_BLEND_DST_ALPHA);
  geti("blend_equation_rgb", GL_BLEND_EQUATION_RGB);
  geti("blend_equation_alpha", GL_BLEND_EQUATION_ALPHA);
  get4("polygon_mode", GL_POLYGON_MODE);
  geti("pack_alignment", GL_PACK_ALIGNMENT);
  geti("unpack_alignment", GL_UNPACK_ALIGNMENT);
  geti("array_buffer", GL_ARRAY_BUFFER_BINDING);
  geti("pixel_pack_buffer", GL_PIXEL_PACK_BUFFER_BINDING);
  geti("pixel_unpack_buffer", GL_PIXEL_UNPACK_BUFFER_BINDING);
  geti("dispatch_indirect_buffer", GL_DISPATCH_INDIRECT_BUFFER_BINDING);
  geti("draw_indirect_buffer", GL_DRAW_INDIRECT_BUFFER_BINDING);
  geti("ssbo_generic", GL_SHADER_STORAGE_BUFFER_BINDING);
  geti("ubo_generic", GL_UNIFORM_BUFFER_BINDING);
  geti("copy_read_buffer", GL_COPY_READ_BUFFER_BINDING);
  geti("copy_write_buffer", GL_COPY_WRITE_BUFFER_BINDING);
  // Every other buffer target's generic binding (an application
  // that updates its own buffer through a generic binding must find its
  // buffer there), and the other objects a context binds.
  geti("atomic_counter_generic", GL_ATOMIC_COUNTER_BUFFER_BINDING);
  geti("transform_feedback_generic", GL_TRANSFORM_FEEDBACK_BUFFER_BINDING);
  geti("query_buffer", GL_QUERY_BUFFER_BINDING);
  geti("texture_buffer_generic", GL_TEXTURE_BUFFER_BINDING);
  geti("element_array_buffer", GL_ELEMENT_ARRAY_BUFFER_BINDING);  // the bound VAO's
  geti("renderbuffer", GL_RENDERBUFFER_BINDING);
  geti("transform_feedback", GL_TRANSFORM_FEEDBACK_BINDING);
  geti("program_pipeline", GL_PROGRAM_PIPELINE_BINDING);
  for (GLenum cap : {GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_CLIP_DISTANCE0,
                     GL_PROGRAM_POINT_SIZE, GL_POLYGON_OFFSET_FILL, GL_DEPTH_CLAMP, GL_RASTERIZER_DISCARD,
                     GL_FRAMEBUFFER_SRGB, GL_PRIMITIVE_RESTART, GL_PRIMITIVE_RESTART_FIXED_INDEX, GL_MULTISAMPLE,
                     GL_SAMPLE_SHADING, GL_SAMPLE_ALPHA_TO_COVERAGE, GL_COLOR_LOGIC_OP}) {
    s["enabled_" + std::to_string(cap)] = glIsEnabled(cap);
  }
  GLint ssbo_points = 0, ubo_points = 0;
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &ssbo_points);
  glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &ubo_points);
  for (GLuint i = 0; i < static_cast<GLuint>(std::min(ssbo_points, 16)); ++i) {
    GLint b = 0;
    glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, i, &b);
    s["ssbo_" + std::to_string(i)] = b;
  }
  for (GLuint i = 0; i < static_cast<GLuint>(std::min(ubo_points, 16)); ++i) {
    GLint b = 0;
    glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, i, &b);
    s["ubo_" + std::to_string(i)] = b;
  }
  for (auto [name, binding, max] : {std::tuple{"atomic_counter_", GL_ATOMIC_COUNTER_BUFFER_BINDING, GL_MAX_ATOMIC_COUNTER_BUFFER_BINDINGS},
                                    std::tuple{"transform_feedback_", GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, GL_MAX_TRANSFORM_FEEDBACK_BUFFERS}}) {
    GLint points = 0;
    glGetIntegerv(max, &points);
    for (GLuint i = 0; i < static_cast<GLuint>(std::min(points, 16)); ++i) {
      GLint b = 0;
      glGetIntegeri_v(binding, i, &b);
      s[std::string(name) + std::to_string(i)] = b;
    }
  }
  for (GLuint i = 0; i < 4; ++i) {
    GLint image = 0;
    glGetIntegeri_v(GL_IMAGE_BINDING_NAME, i, &image);
    s["image_" + std::to_string(i)] = image;
  }
  GLint active = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  for (GLuint u = 0; u < 20; ++u) {
    glActiveTexture(GL_TEXTURE0 + u);
    for (auto [name, e] : {std::pair{"2d", GL_TEXTURE_BINDING_2D}, std::pair{"array", GL_TEXTURE_BINDING_2D_ARRAY},
                           std::pair{"cube", GL_TEXTURE_BINDING_CUBE_MAP}, std::pair{"3d", GL_TEXTURE_BINDING_3D},
                           std::pair{"1d", GL_TEXTURE_BINDING_1D}, std::pair{"1d_array", GL_TEXTURE_BINDING_1D_ARRAY},
                           std::pair{"rectangle", GL_TEXTURE_BINDING_RECTANGLE}, std::pair{"buffer", GL_TEXTURE_BINDING_BUFFER},
                           std::pair{"cube_array", GL_TEXTURE_BINDING_CUBE_MAP_ARRAY},
                           std::pair{"2d_multisample", GL_TEXTURE_BINDING_2D_MULTISAMPLE},
                           std::pair{"2d_multisample_array", GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY},
                           std::pair{"sampler", GL_SAMPLER_BINDING}}) {
      GLint v = 0;
      glGetIntegerv(e, &v);
      s["unit" + std::to_string(u) + "_" + name] = v;
    }
  }
  glActiveTexture(static_cast<GLenum>(active));
  return s;
}

// The keys whose values differ between two snapshots.
std::vector<std::string> changed(const Snapshot& a, const Snapshot& b) {
  std::vector<std::string> out;
  for (const auto& [k, v] : a) {
    if (b.at(k) != v) out.push_back(k + ": " + std::to_string(v) + " -> " + std::to_string(b.at(k)));
  }
  return out;
}

class Engine_ : public test::GlTest {
 protected:
  // An application's own objects, bound everywhere the engine might touch.
  void SetUp() override {
    auto prog = runtime::gl::Program::build_compute("app", "#version 450 core\nlayout(local_size_x = 1) in;\nvoid main() {}\n");
    ASSERT_TRUE(prog.ok()) << prog.error().message;
    program_ = std::move(*prog);
    vao_ = runtime::gl::make_vertex_array();
    fbo_ = runtime::gl::make_framebuffer();
    color_ = runtime::gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(color_.get(), 1, GL_RGBA32F, 64, 48);
    depth_ = runtime::gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(depth_.get(), 1, GL_DEPTH_COMPONENT32F, 64, 48);
    glNamedFramebufferTexture(fbo_.get(), GL_COLOR_ATTACHMENT0, color_.get(), 0);
    glNamedFramebufferTexture(fbo_.get(), GL_DEPTH_ATTACHMENT, depth_.get(), 0);
    buffer_ = runtime::gl::make_buffer();
    glNamedBufferStorage(buffer_.get(), 4096, nullptr, 0);
    sampler_ = 0;
    glCreateSamplers(1, &sampler_);

    glUseProgram(program_.id());
    glBindVertexArray(vao_.get());
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get());
    glViewport(3, 5, 50, 40);
    glScissor(1, 2, 30, 20);
    glEnable(GL_SCISSOR_TEST);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ZERO);
    glBlendEquation(GL_FUNC_REVERSE_SUBTRACT);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_GREATER);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT);
    glFrontFace(GL_CW);
    glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
    glPixelStorei(GL_PACK_ALIGNMENT, 8);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer_.get());
    glBindBuffer(GL_ARRAY_BUFFER, buffer_.get());
    glBindBufferRange(GL_UNIFORM_BUFFER, 0, buffer_.get(), 256, 512);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, buffer_.get());
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    for (GLuint u = 0; u < 20; ++u) glBindTextureUnit(u, color_.get());
    for (GLuint i = 0; i < 4; ++i) glBindImageTexture(i, color_.get(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindSampler(10, sampler_);
    glActiveTexture(GL_TEXTURE5);
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  }
  void TearDown() override {
    glUseProgram(0);
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteSamplers(1, &sampler_);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glFrontFace(GL_CCW);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ZERO);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glActiveTexture(GL_TEXTURE0);
  }

  runtime::gl::Program program_;
  runtime::gl::VertexArray vao_;
  runtime::gl::Framebuffer fbo_;
  runtime::gl::Texture color_, depth_;
  runtime::gl::Buffer buffer_;
  GLuint sampler_ = 0;
};

runtime::View test_view() {
  runtime::View v;
  v.view = glm::lookAt(glm::vec3(5, 7, 7), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
  v.aspect = 64.0f / 48.0f;
  return v;
}

// Runs `call` and expects the snapshot unchanged; `what` names the call.
template <typename F>
void expect_state_kept(const char* what, F&& call) {
  const Snapshot before = snapshot();
  call();
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << what;
  const auto diff = changed(before, snapshot());
  EXPECT_TRUE(diff.empty()) << what << " changed " << diff.size() << " state values, first: " << (diff.empty() ? "" : diff[0]);
}

// Cost: four scenes, some thirty Engine calls each, the whole GL state read
// before and after every one.
TEST_F(Engine_, EveryCallLeavesTheGlStateItFound) {
  ::testing::Test::RecordProperty("gl_state_values", static_cast<int>(snapshot().size()));
  for (const char* name : {"wavy_pool", "glass_ball", "fog_ball", "mirror_ring"}) {
    SCOPED_TRACE(name);
    nlohmann::json j = test::canonical_scene(name);
    const bool pool = std::string(name) == "wavy_pool";
    if (pool) j["water"]["dispersion"] = 1.0;  // the water passes' spectral sums too
    auto loaded = test::bake_and_load(test::write_scene(j, "engine_state"));
    ASSERT_TRUE(loaded);
    std::unique_ptr<Engine> engine;
    expect_state_kept("create", [&] {
      auto e = Engine::create(*loaded);
      ASSERT_TRUE(e.ok()) << e.error().message;
      engine = std::move(*e);
    });
    const SceneDesc& sc = engine->scene();
    runtime::FrameUpdate frame{0.25f, engine->default_options()};
    frame.caustics.wavelengths = 2;
    // Small maps and photon grids: the GL state an update touches is the
    // same at any size, and on llvmpipe the defaults' 512^2 maps, and the
    // mirror's caustic map with its default photons, take seconds an update.
    frame.caustics.map_size = 64;
    frame.caustics.glass_map_size = 64;
    frame.caustics.caustic_map.photons = 64;
    expect_state_kept("update", [&] { ASSERT_TRUE(engine->update(frame).ok()); });
    if (pool) EXPECT_EQ(engine->stats().wavelengths, 2u);
    frame.caustics.method = runtime::CausticsMethod::kVolumetric;
    expect_state_kept("update (volumetric)", [&] { ASSERT_TRUE(engine->update(frame).ok()); });
    frame.caustics.method = runtime::CausticsMethod::kSplat;
    expect_state_kept("update (splat)", [&] { ASSERT_TRUE(engine->update(frame).ok()); });
    frame.caustics.glass_method = runtime::GlassMethod::kCausticMap;
    frame.caustics.caustic_map.two_pass = true;
    expect_state_kept("update (caustic maps, two-pass splats)", [&] { ASSERT_TRUE(engine->update(frame).ok()); });
    frame.caustics.caustic_map.two_pass = false;
    expect_state_kept("update (caustic maps)", [&] { ASSERT_TRUE(engine->update(frame).ok()); });
    expect_state_kept("caustic_map_stats", [&] { (void)engine->caustic_map_stats(); });
    Light light = sc.lights[0];
    light.direction = {0.3f, -1.0f, 0.1f};
    expect_state_kept("set_light", [&] { ASSERT_TRUE(engine->set_light(0, light).ok()); });
    Mat4f t = sc.objects[0].transform;
    t[12] += 0.1f;
    expect_state_kept("set_object_transform", [&] { ASSERT_TRUE(engine->set_object_transform(0, t).ok()); });
    expect_state_kept("draw_object", [&] { ASSERT_TRUE(engine->draw_object(0).ok()); });
    expect_state_kept("lighting", [&] { ASSERT_TRUE(engine->lighting(0, 0).ok()); });
    expect_state_kept("draw_glass", [&] { ASSERT_TRUE(engine->draw_glass(test_view(), color_.get(), depth_.get(), glm::vec3(0.5f)).ok()); });
    const glm::mat4 view_proj = test_view().projection() * test_view().view;
    expect_state_kept("draw_media", [&] { ASSERT_TRUE(engine->draw_media(view_proj, color_.get(), depth_.get()).ok()); });
    expect_state_kept("draw_media (in-scatter only)", [&] { ASSERT_TRUE(engine->draw_media(view_proj, 0, depth_.get()).ok()); });
    expect_state_kept("volume_stats", [&] { (void)engine->volume_stats(); });
    EXPECT_EQ(engine->has_media(), std::string(name) == "fog_ball");
    if (sc.water) {
      runtime::WaterLook look;
      look.texture_size = 32;
      int calls = 0;
      // The callback finds the caller's state but for what WaterPass lists
      // (engine.h: the active unit, a sampler object, multisampling).
      const Snapshot caller = snapshot();
      expect_state_kept("draw_water", [&] {
        ASSERT_TRUE(engine
                        ->draw_water(test_view(), look,
                                     [&](const runtime::WaterPass& pass) {
                                       const Snapshot in = snapshot();
                                       for (const auto& d : changed(caller, in)) {
                                         const bool listed = d.rfind("draw_fbo:", 0) == 0 || d.rfind("read_fbo:", 0) == 0 ||
                                                             d.rfind("viewport[", 0) == 0 || d.rfind("depth_mask:", 0) == 0 ||
                                                             d.rfind("depth_func:", 0) == 0 || d.rfind("front_face:", 0) == 0 ||
                                                             d.rfind("enabled_" + std::to_string(GL_DEPTH_TEST) + ":", 0) == 0 ||
                                                             d.rfind("enabled_" + std::to_string(GL_BLEND) + ":", 0) == 0 ||
                                                             d.rfind("enabled_" + std::to_string(GL_CULL_FACE) + ":", 0) == 0 ||
                                                             d.rfind("enabled_" + std::to_string(GL_CLIP_DISTANCE0) + ":", 0) == 0;
                                         EXPECT_TRUE(listed) << "draw_water's callback found " << d;
                                       }
                                       EXPECT_EQ(in.at("draw_fbo"), static_cast<std::int64_t>(pass.framebuffer));
                                       EXPECT_EQ(in.at("viewport[2]"), pass.size);
                                       EXPECT_EQ(in.at("enabled_" + std::to_string(GL_DEPTH_TEST)), 1);
                                       EXPECT_EQ(in.at("enabled_" + std::to_string(GL_CLIP_DISTANCE0)), 1);
                                       EXPECT_EQ(in.at("depth_mask"), 1);
                                       ++calls;  // an application's pass leaves things as it likes
                                       glEnable(GL_STENCIL_TEST);
                                       glUseProgram(0);
                                       glBindVertexArray(0);
                                       glViewport(0, 0, 1, 1);
                                       glBindTextureUnit(2, 0);
                                     })
                        .ok());
      });
      EXPECT_EQ(calls, 2);  // refraction and reflection textures
      expect_state_kept("draw_water (scene depth: hidden glints do not glow)", [&] {
        ASSERT_TRUE(engine->draw_water(test_view(), look, [&](const runtime::WaterPass&) {}, depth_.get()).ok());
      });
      EXPECT_EQ(code_of(engine->draw_water(test_view(), look, nullptr, color_.get())), ErrorCode::kUsage) << "not a depth texture";
      look.textures = false;
      expect_state_kept("draw_water (plain)", [&] { ASSERT_TRUE(engine->draw_water(test_view(), look, nullptr).ok()); });
      const auto grid = engine->water_grid();
      ASSERT_TRUE(grid);
      std::vector<float> h(std::size_t{grid->columns} * grid->rows, 0.01f);
      expect_state_kept("set_water_heights", [&] { ASSERT_TRUE(engine->set_water_heights(h).ok()); });
      runtime::gl::Texture tex = runtime::gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(tex.get(), 1, GL_R32F, static_cast<GLsizei>(grid->columns), static_cast<GLsizei>(grid->rows));
      expect_state_kept("set_water_heights_texture", [&] { ASSERT_TRUE(engine->set_water_heights_texture(tex.get()).ok()); });
      expect_state_kept("update (heights)", [&] { ASSERT_TRUE(engine->update(frame).ok()); });
      // The interactive water (water_sim.h) keeps the same promise.
      std::unique_ptr<runtime::WaterSimulation> sim;
      expect_state_kept("WaterSimulation::create", [&] {
        auto created = runtime::WaterSimulation::create(*grid);
        ASSERT_TRUE(created.ok()) << created.error().message;
        sim = std::move(*created);
      });
      const std::uint32_t pushed[] = {0};
      expect_state_kept("WaterSimulation::push", [&] { ASSERT_TRUE(sim->push(*engine, pushed).ok()); });
      expect_state_kept("WaterSimulation::push (again)", [&] { ASSERT_TRUE(sim->push(*engine, pushed).ok()); });
      expect_state_kept("WaterSimulation::add_ripple", [&] { ASSERT_TRUE(sim->add_ripple(0, 0, 0.5f, 0.01f).ok()); });
      expect_state_kept("WaterSimulation::step", [&] { ASSERT_TRUE(sim->step(1.0f / 60).ok()); });
      expect_state_kept("WaterSimulation::apply", [&] { ASSERT_TRUE(sim->apply(*engine).ok()); });
      expect_state_kept("WaterSimulation::stats", [&] { EXPECT_TRUE(sim->stats().finite); });
    }
    // bind() changes exactly the block's binding point and its units; not
    // the generic uniform-buffer binding (an application that
    // then updates its own uniform buffer through GL_UNIFORM_BUFFER would
    // write into caustix's light block).
    const Snapshot before = snapshot();
    ASSERT_TRUE(engine->bind(0, 0).ok());
    const Snapshot after = snapshot();
    const runtime::Bindings& b = engine->bindings();
    const auto r = engine->lighting(0, 0);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(after.at("ubo_" + std::to_string(b.block)), static_cast<std::int64_t>(r->buffer));
    std::size_t expected_changes = 0;
    for (const auto& d : changed(before, after)) {
      const bool allowed = d.rfind("ubo_" + std::to_string(b.block) + ":", 0) == 0 || d.rfind("unit", 0) == 0;
      EXPECT_TRUE(allowed) << "bind() changed " << d;
      ++expected_changes;
    }
    EXPECT_GT(expected_changes, 0u);
    EXPECT_EQ(after.at("unit" + std::to_string(b.caustics) + "_2d"), static_cast<std::int64_t>(r->caustics));
    // bind_all() changes exactly the table's storage point and the units
    // (texture arrays), not the generic storage-buffer binding; with the
    // table built, update() keeps it current and still changes nothing.
    const Snapshot before_all = snapshot();
    ASSERT_TRUE(engine->bind_all().ok());
    std::size_t table_changes = 0;
    for (const auto& d : changed(before_all, snapshot())) {
      const bool allowed = d.rfind("ssbo_" + std::to_string(b.table) + ":", 0) == 0 || d.rfind("unit", 0) == 0;
      EXPECT_TRUE(allowed) << "bind_all() changed " << d;
      ++table_changes;
    }
    EXPECT_GT(table_changes, 0u);
    expect_state_kept("update (all-receivers table)", [&] { ASSERT_TRUE(engine->update(frame).ok()); });

    // The matrices are the block's frames: a point at the frame's origin
    // plus half extents along U and W maps to the map's corner (1, 1).
    // After the caustic-map updates, the floor is lit through the light's
    // caustic map (wavy_pool: the water's caustics map).
    const runtime::LightBlock& k = r->block;
    const bool caustics = k.mode.x == static_cast<int>(runtime::LightMode::kCaustics);
    const bool cmap = !caustics && k.cmap_origin.w != 0.0f;
    EXPECT_TRUE(caustics || cmap) << "the floor should be lit through a map in " << name;
    const glm::mat4& m = caustics ? r->world_to_caustics : r->world_to_caustic_map;
    const glm::vec4 o = caustics ? k.frame_origin : k.cmap_origin;
    const glm::vec4 u = caustics ? k.frame_u : k.cmap_u, v = caustics ? k.frame_v : k.cmap_v;
    const glm::vec4 w = caustics ? k.frame_w : k.cmap_w, half = caustics ? k.frame_half : k.cmap_half;
    const glm::vec3 p = glm::vec3(o) + glm::vec3(u) * half.x + glm::vec3(w) * half.z + glm::vec3(v) * 0.25f;
    const glm::vec4 q = m * glm::vec4(p, 1.0f);
    // A caustic map's main map fills the texture's lowest cmap_w.w of its
    // height (a focus window lies above it; engine.h).
    const float share = cmap ? k.cmap_w.w : 1.0f;
    if (cmap) EXPECT_TRUE(share == 1.0f || share == 2.0f / 3.0f) << share;
    EXPECT_NEAR(q.x, 1.0f, 1e-4f);
    EXPECT_NEAR(q.y, share, 1e-4f);
    EXPECT_NEAR(q.z, 0.25f, 1e-4f);
    const glm::vec4 c = m * glm::vec4(glm::vec3(o), 1.0f);
    EXPECT_NEAR(c.x, 0.5f, 1e-4f);
    EXPECT_NEAR(c.y, 0.5f * share, 1e-4f);
  }
}

// docs/embedding.md's table of bindings is the header's (the docs
// and engine.h disagreed on the block's point and the units' count): every
// field of runtime::Bindings, by name and default, and nothing else.
TEST(EngineDocs, TheDocsBindingsTableIsTheHeaders) {
  const runtime::Bindings b;
  const std::map<std::string, unsigned> fields{
      {"block", b.block},
      {"shadow_2d", b.shadow_2d},
      {"shadow_cube", b.shadow_cube},
      {"caustics", b.caustics},
      {"position", b.position},
      {"glass_illumination", b.glass_illumination},
      {"glass_target", b.glass_target},
      {"glass_shadow_2d", b.glass_shadow_2d},
      {"glass_shadow_cube", b.glass_shadow_cube},
      {"caustic_map", b.caustic_map},
      {"shadow_vsm", b.shadow_vsm},
      {"glass_shadow_vsm", b.glass_shadow_vsm},
      {"caustics_color", b.caustics_color},
      {"table", b.table}};
  // A field added to the struct must be added here (and to the docs).
  static_assert(sizeof(runtime::Bindings) == 14 * sizeof(unsigned));
  std::ifstream f(std::string(CAUSTIX_SOURCE_DIR) + "/docs/embedding.md");
  ASSERT_TRUE(f) << "docs/embedding.md";
  std::string line;
  bool in_table = false;
  std::map<std::string, unsigned> documented;
  while (std::getline(f, line)) {
    if (line.find("<!-- bindings:") != std::string::npos) {
      in_table = true;
      continue;
    }
    if (!in_table) continue;
    if (line.empty()) break;
    // | `name` | value | what |
    const auto a = line.find("| `"), b2 = line.find("` | ");
    if (a != 0 || b2 == std::string::npos) continue;
    const std::string name = line.substr(3, b2 - 3);
    documented[name] = static_cast<unsigned>(std::stoul(line.substr(b2 + 4)));
  }
  EXPECT_EQ(documented, fields);
  // The include's defaults are the header's too.
  std::ifstream g(std::string(CAUSTIX_SOURCE_DIR) + "/runtime/include/caustix/runtime/caustix.glsl");
  const std::string glsl((std::istreambuf_iterator<char>(g)), std::istreambuf_iterator<char>());
  EXPECT_NE(glsl.find("#define CAUSTIX_BINDING_BLOCK " + std::to_string(b.block) + "\n"), std::string::npos);
  EXPECT_NE(glsl.find("#define CAUSTIX_BINDING_TABLE " + std::to_string(b.table) + "\n"), std::string::npos);
  EXPECT_NE(glsl.find("#define CAUSTIX_UNIT_CAUSTICS_COLOR " + std::to_string(b.caustics_color) + "\n"), std::string::npos);
  EXPECT_NE(glsl.find("#define CAUSTIX_UNIT_SHADOW_2D " + std::to_string(b.shadow_2d) + "\n"), std::string::npos);
}

// The include twice in one shader compiles (its guards).
TEST_F(Engine_, TheIncludeTwiceInOneShaderCompiles) {
  auto loaded = test::bake_and_load(scene("glass_ball"));
  ASSERT_TRUE(loaded);
  auto e = Engine::create(*loaded);
  ASSERT_TRUE(e.ok()) << e.error().message;
  const std::string inc = (*e)->glsl_include();
  const std::string fs = "#version 450 core\n" + inc + inc + "out vec4 o;\nvoid main() { o = vec4(caustix_irradiance(vec3(0.0), vec3(0.0, 1.0, 0.0)), 1.0); }\n";
  const char* vs = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
  auto prog = runtime::gl::Program::build("twice", vs, fs.c_str());
  EXPECT_TRUE(prog.ok()) << (prog.ok() ? "" : prog.error().message);
}

// Irradiance of the floor seen from above with the application's program:
// the GLSL include's caustix_irradiance through an orthographic top view.
std::vector<float> floor_irradiance(Engine& engine, int n, float half) {
  const std::string fs = std::string("#version 450 core\n") + engine.glsl_include() +
                         "in vec3 v_world;\nin vec3 v_normal;\nout vec4 o;\n"
                         "void main() { o = vec4(caustix_irradiance(v_world, vec3(0.0, 1.0, 0.0)), 1.0); }\n";
  const char* vs =
      "#version 450 core\nlayout(location = 0) in vec3 a_position;\nlayout(location = 1) in vec3 a_normal;\n"
      "uniform mat4 u_model;\nuniform mat4 u_view_proj;\nout vec3 v_world;\nout vec3 v_normal;\n"
      "void main() { v_world = (u_model * vec4(a_position, 1.0)).xyz; v_normal = a_normal;"
      " gl_Position = u_view_proj * vec4(v_world, 1.0); }\n";
  auto prog = runtime::gl::Program::build("app_floor", vs, fs.c_str());
  EXPECT_TRUE(prog.ok()) << (prog.ok() ? "" : prog.error().message);
  if (!prog.ok()) return {};
  runtime::gl::Texture color = runtime::gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, n, n);
  runtime::gl::Framebuffer fbo = runtime::gl::make_framebuffer();
  glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
  glViewport(0, 0, n, n);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(fbo.get(), GL_COLOR, 0, zero);
  prog->use();
  // Straight down over [-half, half]^2: clip x from x, clip y from z.
  const glm::mat4 m = glm::ortho(-half, half, -half, half, -10.0f, 10.0f) *
                      glm::lookAt(glm::vec3(0, 5, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, 1));
  prog->set("u_view_proj", m);
  prog->set("u_model", glm::make_mat4(engine.scene().objects[0].transform.data()));
  EXPECT_TRUE(engine.bind(0, 0).ok());
  EXPECT_TRUE(engine.draw_object(0).ok());
  std::vector<float> px(static_cast<std::size_t>(n) * n * 4);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);  // the fixture's application left one bound
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * 4), px.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glUseProgram(0);
  std::vector<float> r(static_cast<std::size_t>(n) * n);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = px[4 * i];
  return r;
}

// wavy_pool's sine, handed to the engine as heights instead of the wave
// list, lights the floor the same way. The heights path takes normals from
// central differences: on this grid (768 cells over 12 m, h = 1.56 cm,
// k h = 0.098) the slope is low by (k h)^2/6 = 0.16 %, which moves the fold
// lines by well under a pixel here (2 m / 128 px = 1.6 cm); the mean must
// agree to 0.2 % (energy is conserved either way) and the images to 2 %
// relative L1 (the folds are singular: a sub-pixel shift of a bright line
// shows in the pixels it straddles).
TEST_F(Engine_, ApplicationHeightsLightThePoolAsTheWaveListDoes) {
  auto loaded = test::bake_and_load(scene("wavy_pool"));
  ASSERT_TRUE(loaded);
  auto e = Engine::create(*loaded);
  ASSERT_TRUE(e.ok()) << e.error().message;
  Engine& engine = **e;
  const runtime::FrameUpdate frame{0.0f, engine.default_options()};
  ASSERT_TRUE(engine.update(frame).ok());
  const int n = 128;
  const auto waves = floor_irradiance(engine, n, 1.0f);

  const auto grid = engine.water_grid();
  ASSERT_TRUE(grid);
  const Wave& w = engine.scene().water->waves.at(0);
  std::vector<float> h(std::size_t{grid->columns} * grid->rows);
  for (std::uint32_t j = 0; j < grid->rows; ++j) {
    for (std::uint32_t i = 0; i < grid->columns; ++i) {
      const double x = grid->x0 + (grid->x1 - grid->x0) * i / (grid->columns - 1);
      const double z = grid->z0 + (grid->z1 - grid->z0) * j / (grid->rows - 1);
      const double k = 2 * 3.14159265358979 / w.wavelength;
      h[std::size_t{j} * grid->columns + i] = static_cast<float>(w.amplitude * std::sin(k * (w.direction[0] * x + w.direction[1] * z) + w.phase));
    }
  }
  const Status set = engine.set_water_heights(h);
  ASSERT_TRUE(set.ok()) << set.error().message;
  ASSERT_TRUE(engine.update(frame).ok());
  const auto cpu = floor_irradiance(engine, n, 1.0f);

  double sum_w = 0, sum_h = 0, l1 = 0;
  for (std::size_t i = 0; i < waves.size(); ++i) {
    sum_w += waves[i];
    sum_h += cpu[i];
    l1 += std::fabs(waves[i] - cpu[i]);
  }
  ASSERT_GT(sum_w, 0.5 * waves.size());  // lit: flat water would give T(0) = 0.98
  EXPECT_NEAR(sum_h / sum_w, 1.0, 0.002);
  EXPECT_LT(l1 / sum_w, 0.02);
  ::testing::Test::RecordProperty("heights_vs_waves_rel_l1", std::to_string(l1 / sum_w));

  // The same heights from a GL buffer and from a texture: the same image.
  runtime::gl::Buffer buf = runtime::gl::make_buffer();
  glNamedBufferStorage(buf.get(), static_cast<GLsizeiptr>(16 + h.size() * 4), nullptr, GL_DYNAMIC_STORAGE_BIT);
  glNamedBufferSubData(buf.get(), 16, static_cast<GLsizeiptr>(h.size() * 4), h.data());
  ASSERT_TRUE(engine.set_water_heights_buffer(buf.get(), 16).ok());
  ASSERT_TRUE(engine.update(frame).ok());
  EXPECT_EQ(floor_irradiance(engine, n, 1.0f), cpu);
  runtime::gl::Texture tex = runtime::gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(tex.get(), 1, GL_R32F, static_cast<GLsizei>(grid->columns), static_cast<GLsizei>(grid->rows));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(tex.get(), 0, 0, 0, static_cast<GLsizei>(grid->columns), static_cast<GLsizei>(grid->rows), GL_RED, GL_FLOAT, h.data());
  ASSERT_TRUE(engine.set_water_heights_texture(tex.get()).ok());
  ASSERT_TRUE(engine.update(frame).ok());
  EXPECT_EQ(floor_irradiance(engine, n, 1.0f), cpu);
  // Back to the wave list: the first image again.
  engine.use_scene_waves();
  ASSERT_TRUE(engine.update(frame).ok());
  EXPECT_EQ(floor_irradiance(engine, n, 1.0f), waves);
}

TEST_F(Engine_, BadArgumentsAreRefusedByName) {
  auto loaded = test::bake_and_load(scene("wavy_pool"));
  ASSERT_TRUE(loaded);
  runtime::Bindings clash;
  clash.caustics = clash.position;
  auto bad = Engine::create(*loaded, clash);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, ErrorCode::kUsage);
  EXPECT_NE(bad.error().message.find("given twice"), std::string::npos) << bad.error().message;

  auto e = Engine::create(*loaded);
  ASSERT_TRUE(e.ok());
  Engine& engine = **e;
  EXPECT_EQ(engine.lighting(0, 0).error().code, ErrorCode::kUsage);  // before update()
  ASSERT_TRUE(engine.update(runtime::FrameUpdate{0.0f, engine.default_options()}).ok());
  EXPECT_EQ(engine.lighting(1, 0).error().code, ErrorCode::kUsage);
  EXPECT_EQ(engine.lighting(0, 7).error().code, ErrorCode::kUsage);
  EXPECT_EQ(code_of(engine.bind(9, 0)), ErrorCode::kUsage);
  EXPECT_EQ(code_of(engine.draw_object(3)), ErrorCode::kUsage);
  EXPECT_EQ(code_of(engine.update(runtime::FrameUpdate{NAN, {}})), ErrorCode::kUsage);
  // Options are checked when they change: bad ones after good ones are
  // refused every time they come, and the good ones still work after.
  runtime::FrameUpdate changed{0.1f, engine.default_options()};
  changed.caustics.shadows.vsm_filter = 4;
  for (int k = 0; k < 2; ++k) EXPECT_EQ(code_of(engine.update(changed)), ErrorCode::kUsage) << k;
  changed.caustics.shadows.vsm_filter = engine.default_options().shadows.vsm_filter;
  EXPECT_TRUE(engine.update(changed).ok());
  changed.caustics.wavelengths = 0;
  EXPECT_EQ(code_of(engine.update(changed)), ErrorCode::kUsage);
  std::vector<float> h(10, 0.0f);
  const Status short_heights = engine.set_water_heights(h);
  EXPECT_EQ(code_of(short_heights), ErrorCode::kUsage);
  const auto grid = engine.water_grid();
  h.assign(std::size_t{grid->columns} * grid->rows, 0.0f);
  h[grid->columns + 2] = NAN;
  const Status nan_height = engine.set_water_heights(h);
  ASSERT_FALSE(nan_height.ok());
  EXPECT_NE(nan_height.error().message.find("column 2, row 1"), std::string::npos) << nan_height.error().message;
  EXPECT_EQ(code_of(engine.set_water_heights_buffer(123456)), ErrorCode::kUsage);
  runtime::gl::Buffer small = runtime::gl::make_buffer();
  glNamedBufferStorage(small.get(), 64, nullptr, 0);
  EXPECT_EQ(code_of(engine.set_water_heights_buffer(small.get())), ErrorCode::kUsage);
  runtime::gl::Texture wrong = runtime::gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(wrong.get(), 1, GL_RGBA8, 4, 4);
  EXPECT_EQ(code_of(engine.set_water_heights_texture(wrong.get())), ErrorCode::kUsage);
  EXPECT_TRUE(engine.draw_glass(test_view(), wrong.get(), wrong.get(), glm::vec3(0)).ok());  // no glass: a no-op
  runtime::WaterLook look;
  look.steps = 0;
  EXPECT_EQ(code_of(engine.draw_water(test_view(), look, nullptr)), ErrorCode::kUsage);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST(Version, LibraryMatchesHeaders) {
  const Version v = version_numbers();
  EXPECT_EQ(v.major, CAUSTIX_VERSION_MAJOR);
  EXPECT_EQ(v.minor, CAUSTIX_VERSION_MINOR);
  EXPECT_EQ(v.patch, CAUSTIX_VERSION_PATCH);
  EXPECT_EQ(std::string(version()),
            std::to_string(v.major) + "." + std::to_string(v.minor) + "." + std::to_string(v.patch));
  EXPECT_NE(std::string(runtime::glsl_include_source()).find("vec3 caustix_irradiance(vec3 world_position, vec3 world_normal)"),
            std::string::npos);
}

}  // namespace
}  // namespace caustix
