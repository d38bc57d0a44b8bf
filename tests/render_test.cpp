// Headless rendering through EGL (llvmpipe here, a GPU where present):
// something lit where a receiver is, the exact background elsewhere, a
// shadow where the light is blocked, and no NaN/Inf anywhere.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "bake_fixture.h"
#include "scene_fixture.h"
#include "caustix/bake/bake.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/runtime/renderer.h"

namespace caustix {
namespace {

using runtime::FrameParams;
using runtime::HeadlessContext;
using runtime::Renderer;

struct Image {
  int w = 0, h = 0;
  std::vector<float> rgba;
  const float* at(int row, int col) const { return &rgba[(static_cast<std::size_t>(row) * w + col) * 4]; }
};

Image render(const std::string& scene_json, int w, int h, float time = 0.0f) {
  auto scene = test::bake_and_load(std::string(CAUSTIX_SOURCE_DIR) + "/" + scene_json);
  auto ctx = HeadlessContext::create();
  EXPECT_TRUE(ctx.ok()) << ctx.error().message;
  auto r = Renderer::create(*scene);
  EXPECT_TRUE(r.ok()) << r.error().message;
  FrameParams f;
  f.camera = (*r)->default_camera();
  f.width = w;
  f.height = h;
  f.time = time;
  Status st = (*r)->render(f);
  EXPECT_TRUE(st.ok()) << st.error().message;
  return Image{w, h, (*r)->read_hdr()};
}

TEST(Render, LitReceiverBackgroundAndShadow) {
  // tests/data/lit_box.json: a 3 m floor and a red unit box seen from 6 m
  // above; sun travelling along (1, -1, 0) with E0 = 2.
  // The sky and the ambient term are relative to the scene's light level
  // (E0: renderer.h, kSkyColor).
  const Image img = render("tests/data/lit_box.json", 96, 96);
  const float* corner = img.at(0, 0);
  EXPECT_EQ(corner[0], 2.0f * runtime::kSkyColor[0]);
  EXPECT_EQ(corner[1], 2.0f * runtime::kSkyColor[1]);
  EXPECT_EQ(corner[2], 2.0f * runtime::kSkyColor[2]);

  // Box top: albedo 0.9 red * (ambient + E0 cos 45deg = 1.41).
  const float* box = img.at(48, 48);
  EXPECT_NEAR(box[0], 0.9f * (0.12f * 2.0f * runtime::kSkyColor[0] + 2.0f * std::sqrt(0.5f)), 0.02f);
  EXPECT_LT(box[1], box[0] * 0.5f);

  // Floor left of the box is lit; right of it (downwind) is in its shadow.
  const float* lit = img.at(48, 26);
  const float* shadow = img.at(48, 70);
  EXPECT_NEAR(lit[0], 0.8f * (0.12f * 2.0f * runtime::kSkyColor[0] + 2.0f * std::sqrt(0.5f)), 0.02f);
  EXPECT_LT(shadow[0], 0.15f * lit[0]);
}

// The automatic camera (a scene without one; issue 45: it was loose on
// wide, flat scenes): the bounds' eight corners all inside a 4:3 frame,
// and the frame filled to within 10 % along one axis. glass_ball's 4 m
// floor and its ball, once framed by the bounding sphere at 2.8 radii
// (the corners reached 0.77 of the frame; now 0.95).
TEST(Render, TheAutomaticCameraFillsTheFrameWithTheScene) {
  nlohmann::json j = test::canonical_scene("glass_ball");
  j.erase("camera");
  auto scene = test::bake_and_load(test::write_scene(j, "render_auto_camera"));
  ASSERT_TRUE(scene);
  auto ctx = HeadlessContext::create();
  ASSERT_TRUE(ctx.ok());
  auto r = Renderer::create(*scene);
  ASSERT_TRUE(r.ok());
  const Camera c = (*r)->default_camera();
  const glm::mat4 vp = glm::perspective(glm::radians(c.fov_y_deg), 4.0f / 3.0f, c.near_plane, c.far_plane) *
                       glm::lookAt(glm::vec3(c.position[0], c.position[1], c.position[2]), glm::vec3(c.target[0], c.target[1], c.target[2]),
                                   glm::vec3(c.up[0], c.up[1], c.up[2]));
  const glm::vec3 lo = (*r)->bounds_min(), hi = (*r)->bounds_max();
  float reach = 0;
  for (int k = 0; k < 8; ++k) {
    const glm::vec4 p = vp * glm::vec4(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z, 1.0f);
    ASSERT_GT(p.w, 0.0f);
    EXPECT_LE(std::fabs(p.x / p.w), 1.0f);
    EXPECT_LE(std::fabs(p.y / p.w), 1.0f);
    reach = std::max({reach, std::fabs(p.x / p.w), std::fabs(p.y / p.w)});
  }
  std::printf("[auto camera] the bounds' corners reach %.3f of the frame\n", reach);
  EXPECT_GT(reach, 0.9f);
}

TEST(Render, DefaultSceneHasNoNanAndIsNotEmpty) {
  for (float t : {0.0f, 3.7f}) {
    const Image img = render("assets/scenes/default.json", 160, 120, t);
    std::size_t non_sky = 0;
    for (std::size_t i = 0; i < img.rgba.size(); i += 4) {
      for (std::size_t k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(img.rgba[i + k])) << "pixel " << i / 4;
      non_sky += img.rgba[i] != runtime::kSkyColor[0] ? 1 : 0;
    }
    EXPECT_GT(non_sky, img.rgba.size() / 4 / 3) << "the scene covers too little of the image";
  }
}

TEST(Render, WavesMoveWithTime) {
  const Image a = render("assets/scenes/default.json", 80, 60, 0.0f);
  const Image b = render("assets/scenes/default.json", 80, 60, 1.0f);
  EXPECT_NE(a.rgba, b.rgba);
}

}  // namespace
}  // namespace caustix
