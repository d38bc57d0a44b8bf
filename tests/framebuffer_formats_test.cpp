// The view-side draws (draw_water, draw_glass, draw_media) into the
// framebuffers engines have (engine.h, "Scene textures"): half-float,
// packed-float, 8-bit and sRGB colour, depth-stencil and 16-bit depth,
// multisampled or not. The oracle is the same frame drawn into GL_RGBA32F
// and GL_DEPTH_COMPONENT32F, single-sampled: every other target must give
// the same picture within what its formats can hold (their rounding,
// stated per case), and textures the draws cannot read are refused by name.

#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "bake_fixture.h"
#include "caustix/runtime/engine.h"
#include "gl_objects.h"
#include "gl_fixture.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

using runtime::Engine;
namespace gl = runtime::gl;

constexpr int kW = 96, kH = 72;

// The opaque objects as an application draws them: colour from the normal
// (0.2..0.8, inside every format's range), depth by the rasteriser.
constexpr const char* kSceneVert = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_proj;
uniform mat4 u_model;
out vec3 v_normal;
void main() {
  v_normal = normalize(mat3(u_model) * a_normal);
  gl_Position = u_view_proj * u_model * vec4(a_position, 1.0);
}
)";
constexpr const char* kSceneFrag = R"(#version 450 core
in vec3 v_normal;
out vec4 o_color;
void main() { o_color = vec4(0.2 + 0.6 * abs(v_normal), 1.0); }
)";
// Reads any colour texture back as linear floats (sRGB decoded by the
// sampler), averaging the samples of a multisampled one.
constexpr const char* kReadVert = R"(#version 450 core
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";
constexpr const char* kReadFrag = R"(#version 450 core
layout(binding = 0) uniform sampler2D u_single;
layout(binding = 1) uniform sampler2DMS u_multi;
uniform bool u_ms;
out vec4 o_color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  if (u_ms) {
    vec4 c = vec4(0.0);
    int n = textureSamples(u_multi);
    for (int s = 0; s < n; ++s) c += texelFetch(u_multi, p, s);
    o_color = c / float(n);
  } else {
    o_color = texelFetch(u_single, p, 0);
  }
}
)";

struct Target {
  GLenum color_format, depth_format;
  int samples;  // 0: single-sampled
  const char* name;
  // What the formats can hold: |got - want| <= abs + rel |want| per
  // channel, colour clamped to [0, 1] for normalised formats; `share` of
  // the pixels must meet it (1 where the depth is as fine as the oracle's).
  float abs, rel, share;
  bool normalised;
};

class FramebufferFormats : public test::GlTest {
 protected:
  void SetUp() override {
    auto scene = gl::Program::build("app_scene", kSceneVert, kSceneFrag);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    scene_program_ = std::move(*scene);
    auto read = gl::Program::build("app_read", kReadVert, kReadFrag);
    ASSERT_TRUE(read.ok()) << read.error().message;
    read_program_ = std::move(*read);
    vao_ = gl::make_vertex_array();
  }

  static runtime::View view() {
    runtime::View v;
    v.view = glm::lookAt(glm::vec3(2.2f, 2.6f, 3.0f), glm::vec3(0.0f, 0.4f, 0.0f), glm::vec3(0, 1, 0));
    v.aspect = static_cast<float>(kW) / static_cast<float>(kH);
    v.near_plane = 0.5f;
    v.far_plane = 20.0f;
    return v;
  }

  enum class Draws { kNone, kGlassAndMedia, kWater };
  // A framebuffer of `t`'s formats holding the application's opaque
  // scene, then the engine's view-side draws; its colour read back linear.
  std::vector<float> draw(Engine& engine, const Target& t, Draws draws) {
    auto make = [&](GLenum format) {
      gl::Texture tex = gl::make_texture(t.samples ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D);
      if (t.samples) {
        glTextureStorage2DMultisample(tex.get(), t.samples, format, kW, kH, GL_TRUE);
      } else {
        glTextureStorage2D(tex.get(), 1, format, kW, kH);
      }
      return tex;
    };
    gl::Texture color = make(t.color_format), depth = make(t.depth_format);
    gl::Framebuffer fbo = gl::make_framebuffer();
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
    const bool stencil = t.depth_format == GL_DEPTH24_STENCIL8 || t.depth_format == GL_DEPTH32F_STENCIL8;
    glNamedFramebufferTexture(fbo.get(), stencil ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT, depth.get(), 0);
    EXPECT_EQ(glCheckNamedFramebufferStatus(fbo.get(), GL_FRAMEBUFFER), static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE)) << t.name;

    // The application's frame: its sRGB target written encoded, and, in a
    // multisampled target, every sample of a pixel alike (multisampling
    // off), so that the resolved picture is the single-sampled one's.
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
    glViewport(0, 0, kW, kH);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glDisable(GL_MULTISAMPLE);
    const float sky[4] = {0.35f, 0.5f, 0.7f, 1.0f};
    glClearNamedFramebufferfv(fbo.get(), GL_COLOR, 0, sky);
    glClearNamedFramebufferfi(fbo.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    const runtime::View v = view();
    const glm::mat4 view_proj = v.projection() * v.view;
    scene_program_.use();
    scene_program_.set("u_view_proj", view_proj);
    const SceneDesc& sc = engine.scene();
    for (std::uint32_t i = 0; i < sc.objects.size(); ++i) {
      if (transmits(sc.objects[i].role)) continue;
      scene_program_.set("u_model", glm::make_mat4(sc.objects[i].transform.data()));
      EXPECT_TRUE(engine.draw_object(i).ok());
    }
    // The engine's draws, with the scene's textures attached where they are drawn into.
    if (draws == Draws::kWater) {
      runtime::WaterLook look;
      look.texture_size = 64;
      look.glow = true;
      const Status s = engine.draw_water(v, look, [&](const runtime::WaterPass& pass) {
        scene_program_.use();
        scene_program_.set("u_view_proj", pass.view_proj);
        for (std::uint32_t i = 0; i < sc.objects.size(); ++i) {
          if (transmits(sc.objects[i].role)) continue;
          scene_program_.set("u_model", glm::make_mat4(sc.objects[i].transform.data()));
          (void)engine.draw_object(i);
        }
      }, depth.get());
      EXPECT_TRUE(s.ok()) << t.name << ": " << s.error().message;
    } else if (draws == Draws::kGlassAndMedia) {
      const Status g = engine.draw_glass(v, color.get(), depth.get(), glm::vec3(0.4f, 0.5f, 0.6f));
      EXPECT_TRUE(g.ok()) << t.name << ": " << g.error().message;
      const Status m = engine.draw_media(view_proj, color.get(), depth.get(), 0.5f);
      EXPECT_TRUE(m.ok()) << t.name << ": " << m.error().message;
    }
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << t.name;
    glDisable(GL_FRAMEBUFFER_SRGB);
    glEnable(GL_MULTISAMPLE);
    glDisable(GL_DEPTH_TEST);

    // Read back linear through a sampler.
    gl::Texture out = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(out.get(), 1, GL_RGBA32F, kW, kH);
    gl::Framebuffer out_fbo = gl::make_framebuffer();
    glNamedFramebufferTexture(out_fbo.get(), GL_COLOR_ATTACHMENT0, out.get(), 0);
    glBindFramebuffer(GL_FRAMEBUFFER, out_fbo.get());
    read_program_.use();
    read_program_.set("u_ms", t.samples ? 1 : 0);
    glBindTextureUnit(t.samples ? 1 : 0, color.get());
    glBindVertexArray(vao_.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindTextureUnit(0, 0);
    glBindTextureUnit(1, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    std::vector<float> rgba(std::size_t{4} * kW * kH);
    glGetTextureImage(out.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.size() * 4), rgba.data());
    return rgba;
  }

  // Compares `got` with the oracle `want` as `t` allows; returns the share
  // of pixels within the bound and prints the figures.
  static double compare(const std::vector<float>& want, const std::vector<float>& got, const Target& t, const char* what) {
    std::size_t ok = 0;
    double worst = 0, sum = 0;
    for (std::size_t p = 0; p < want.size() / 4; ++p) {
      bool pixel_ok = true;
      for (int c = 0; c < 3; ++c) {  // alpha: R11G11B10F has none
        float w = want[4 * p + c];
        if (t.normalised) w = std::clamp(w, 0.0f, 1.0f);
        const double e = std::fabs(got[4 * p + c] - w);
        worst = std::max(worst, e);
        sum += e;
        pixel_ok = pixel_ok && e <= t.abs + t.rel * std::fabs(w);
      }
      ok += pixel_ok ? 1 : 0;
    }
    const double share = static_cast<double>(ok) / static_cast<double>(want.size() / 4);
    std::printf("[%s, %s] %.2f %% of pixels within %.4f + %.4f |x|; mean |error| %.2e, largest %.3f\n", what, t.name,
                100.0 * share, t.abs, t.rel, sum / static_cast<double>(want.size() / 4 * 3), worst);
    return share;
  }

  // The engine of canonical scene `name`, updated once at `time`; baked
  // and made once for the suite.
  static Engine* engine_of(const std::string& name, float time) {
    auto& slot = engines_[name];
    if (!slot) {
      auto loaded = test::bake_and_load(test::kScenes + name + ".json");
      if (!loaded) return nullptr;
      auto created = Engine::create(*loaded);
      EXPECT_TRUE(created.ok()) << created.error().message;
      if (!created.ok()) return nullptr;
      slot = std::move(*created);
      EXPECT_TRUE(slot->update(runtime::FrameUpdate{time, slot->default_options()}).ok());
    }
    return slot.get();
  }
  static void TearDownTestSuite() {
    engines_.clear();  // before the context goes
    test::GlTest::TearDownTestSuite();
  }

  // Every target of `targets` against the oracle's picture.
  void expect_every_format_agrees(Engine& engine, Draws draws, const char* what, const Target& oracle,
                                  std::span<const Target> targets) {
    const std::vector<float> want = draw(engine, oracle, draws);
    // The oracle shows what the engine drew, not the application's scene alone.
    EXPECT_LT(compare(want, draw(engine, oracle, Draws::kNone), oracle, "without the engine's draws"), 0.5) << what;
    for (const Target& t : targets) {
      SCOPED_TRACE(t.name);
      EXPECT_GE(compare(want, draw(engine, t, draws), t, what), t.share);
    }
  }
  void expect_every_format_agrees(Engine& engine, Draws draws, const char* what);

  gl::Program scene_program_, read_program_;
  gl::VertexArray vao_;
  inline static std::map<std::string, std::unique_ptr<Engine>> engines_;
};

// The rounding each format adds, once per write of the frame (the scene's
// colour as stored, the glass composited over it, the fog blended over
// that: three): half floats 2^-11 relative, R11G11B10F's 5-bit blue
// mantissa 2^-6, 8-bit unorm 1/510, sRGB's steepest step (at 1.0, 2.4 x
// 1/510) -- plus a little for the shaders' float evaluation order. D16
// moves depth by up to 1/65535, which at 3 m and this near plane flips the
// odd depth test at a silhouette: 98 % of its pixels must agree.
const Target kTargets[] = {
    {GL_RGBA16F, GL_DEPTH24_STENCIL8, 0, "RGBA16F + D24S8", 2e-4f, 2.5e-3f, 1.0f, false},
    {GL_RGBA16F, GL_DEPTH24_STENCIL8, 4, "RGBA16F + D24S8, 4 samples", 2e-4f, 2.5e-3f, 1.0f, false},
    {GL_R11F_G11F_B10F, GL_DEPTH_COMPONENT32F, 0, "R11G11B10F + D32F", 1e-3f, 0.05f, 1.0f, false},
    {GL_SRGB8_ALPHA8, GL_DEPTH32F_STENCIL8, 0, "SRGB8_ALPHA8 + D32FS8", 0.015f, 0.0f, 1.0f, true},
    {GL_RGBA8, GL_DEPTH_COMPONENT16, 0, "RGBA8 + D16", 0.006f, 0.0f, 0.98f, true},
    {GL_RGBA32F, GL_DEPTH_COMPONENT32F, 4, "RGBA32F + D32F, 4 samples", 1e-5f, 1e-5f, 1.0f, false},
};
const Target kOracle{GL_RGBA32F, GL_DEPTH_COMPONENT32F, 0, "RGBA32F + D32F", 0, 0, 1, false};

void FramebufferFormats::expect_every_format_agrees(Engine& engine, Draws draws, const char* what) {
  expect_every_format_agrees(engine, draws, what, kOracle, kTargets);
}

TEST_F(FramebufferFormats, GlassAndMediaDrawIntoTheFormatsEnginesUse) {
  Engine* engine = engine_of("fog_ball", 0.0f);
  ASSERT_TRUE(engine);
  expect_every_format_agrees(*engine, Draws::kGlassAndMedia, "fog_ball: glass and media");
}

TEST_F(FramebufferFormats, WaterDrawsIntoTheFormatsEnginesUse) {
  Engine* engine = engine_of("wavy_pool", 0.25f);
  ASSERT_TRUE(engine);
  expect_every_format_agrees(*engine, Draws::kWater, "wavy_pool: water");
}

TEST_F(FramebufferFormats, TexturesTheDrawsCannotReadAreRefusedByName) {
  Engine* found = engine_of("fog_ball", 0.0f);
  ASSERT_TRUE(found);
  Engine& engine = *found;
  auto tex = [](GLenum format) {
    gl::Texture t = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(t.get(), 1, format, kW, kH);
    return t;
  };
  const gl::Texture integer = tex(GL_RGBA8UI), depth = tex(GL_DEPTH24_STENCIL8), color = tex(GL_RGBA16F);
  const Status a = engine.draw_glass(view(), integer.get(), depth.get(), glm::vec3(0.5f));
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(a.error().code, ErrorCode::kUsage);
  EXPECT_NE(a.error().message.find("GL_RGBA8UI"), std::string::npos) << a.error().message;
  const Status b = engine.draw_media(view().projection() * view().view, color.get(), color.get());
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("scene depth"), std::string::npos) << b.error().message;
  EXPECT_NE(b.error().message.find("GL_RGBA16F"), std::string::npos) << b.error().message;
  glTextureParameteri(depth.get(), GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
  const Status c = engine.draw_glass(view(), color.get(), depth.get(), glm::vec3(0.5f));
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("GL_DEPTH_STENCIL_TEXTURE_MODE"), std::string::npos) << c.error().message;
  const gl::Texture small = [] {
    gl::Texture t = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(t.get(), 1, GL_DEPTH_COMPONENT24, kW / 2, kH);
    return t;
  }();
  EXPECT_FALSE(engine.draw_glass(view(), color.get(), small.get(), glm::vec3(0.5f)).ok()) << "colour and depth differ in size";
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

}  // namespace
}  // namespace caustix
