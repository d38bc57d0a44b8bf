// Texels by need under a memory budget (CausticsOptions::texel_size,
// memory_budget; docs/caustics.md, "Texels by need and the memory
// budget"), on the default pool (floor, walls, a 1 m ball and a block
// under 4 x 4 m of water): a budget takes a small receiver's texels
// first, then coarsens every map until the light side fits and says so
// once, the light on each receiver is kept through the coarsening,
// and a receiver the water's light cannot reach holds no map. Receivers
// out of the application's view keep their maps while the water moves
// and are remade when they come into view.

#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <nlohmann/json.hpp>

#include "bake_fixture.h"
#include "caustix/sample/renderer.h"
#include "gl_fixture.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

using sample::IrradianceRequest;
using sample::Renderer;

class Texels : public test::GlTest {};

constexpr std::uint32_t kFloor = 0, kBall = 2;

// The side of (object, light 0)'s caustics map as the last update left it.
int map_side(Renderer& r, std::uint32_t object) {
  const auto l = r.engine().lighting(object, 0);
  EXPECT_TRUE(l.ok());
  if (!l.ok()) return 0;
  GLint w = 0;
  glGetTextureLevelParameteriv(l->caustics, 0, GL_TEXTURE_WIDTH, &w);
  return w;
}

// E/E0 integrated over the receiver's region seen from above, m^2: the
// power it receives (in E0 m^2).
double power(Renderer& r, const std::string& receiver, float x0, float z0, float x1, float z1,
             const runtime::CausticsOptions& options) {
  IrradianceRequest q;
  q.receiver = receiver;
  q.x0 = x0;
  q.z0 = z0;
  q.x1 = x1;
  q.z1 = z1;
  q.width = q.height = 64;
  q.time = 1.0f;
  q.caustics = options;
  q.pixel_samples = 2;
  const auto img = r.render_irradiance(q);
  EXPECT_TRUE(img.ok()) << img.error().message;
  if (!img.ok()) return 0;
  double sum = 0;
  for (std::size_t i = 0; i < img->rgb.size(); i += 3) sum += img->rgb[i + 1];
  return sum * (x1 - x0) * (z1 - z0) / (q.width * q.height);
}

// Cost: about 8 s on llvmpipe (one bake, eight irradiance images of the
// default pool at 512^2 maps).
TEST_F(Texels, MapsFollowTheReceiversAndTheBudgetKeepingTheLight) {
  auto r = test::bake_and_create(test::write_scene(test::canonical_scene("default"), "texels"));
  ASSERT_TRUE(r);
  runtime::CausticsOptions o;  // map_size 512, 128 MiB
  o.memory_budget = 0;
  const double floor0 = power(*r, "floor", -2, -2, 2, 2, o);
  const double ball0 = power(*r, "ball", -1.1f, -0.2f, -0.1f, 0.8f, o);
  const runtime::CausticsStats free = r->caustics_stats();
  // The floor has the most water above it: map_size. The 1 m ball's frame
  // at the floor's texel would need about 128 texels; without a budget it
  // keeps map_size too (kLeastShare).
  EXPECT_EQ(map_side(*r, kFloor), 512);
  EXPECT_EQ(map_side(*r, kBall), 512);
  EXPECT_EQ(free.texels.coarsened, 1.0f);
  EXPECT_TRUE(free.warnings.empty());
  EXPECT_GT(floor0, 0.5) << "the floor is lit";

  // Budgets a third and two thirds of the maps' bytes below what they
  // hold: first the small receivers give up texels towards their need
  // (the floor keeps its own), then every texel coarsens, until the light
  // side fits; each new step is warned of once. The maps' texels hold the
  // light that lands on them: coarser texels move none of it. The floor
  // is flat (each texel's flux is exact; only the bilinear reading of the
  // folds near its edges moves); the ball's outline seen from the light
  // is filtered over wider texels.
  for (const int cut : {1, 2}) {
    o.memory_budget = free.memory.light_side() - free.texels.map_bytes * cut / 3;
    const double floor1 = power(*r, "floor", -2, -2, 2, 2, o);
    const double ball1 = power(*r, "ball", -1.1f, -0.2f, -0.1f, 0.8f, o);
    const runtime::CausticsStats tight = r->caustics_stats();
    std::printf("budget %.1f MiB: texels %.2fx coarser, floor %d texels, ball %d; power floor %+.3f %%, ball %+.3f %%\n",
                static_cast<double>(o.memory_budget) / 1048576.0, tight.texels.coarsened, map_side(*r, kFloor), map_side(*r, kBall),
                100 * (floor1 / floor0 - 1), 100 * (ball1 / ball0 - 1));
    EXPECT_LE(tight.texels.light_side, o.memory_budget);
    EXPECT_LE(tight.memory.light_side(), o.memory_budget) << "what the engine holds, not only what it planned";
    EXPECT_FALSE(tight.texels.over_budget);
    EXPECT_LT(map_side(*r, kBall), 512);
    if (cut == 1) {
      EXPECT_EQ(tight.texels.coarsened, 1.0f);
      EXPECT_EQ(map_side(*r, kFloor), 512);
    } else {
      EXPECT_GT(tight.texels.coarsened, 1.0f);
      EXPECT_LT(map_side(*r, kFloor), 512);
    }
    ASSERT_EQ(tight.warnings.size(), 1u);
    EXPECT_NE(tight.warnings[0].find("memory budget"), std::string::npos) << tight.warnings[0];
    EXPECT_TRUE(r->caustics_stats().warnings.empty()) << "warned once";
    EXPECT_NEAR(floor1 / floor0, 1.0, 0.005);
    EXPECT_NEAR(ball1 / ball0, 1.0, 0.02);
  }

  // A budget below what the light side holds besides its caustics maps:
  // no coarsening could meet it, so every receiver keeps a map at its
  // need (the ball's frame at the floor's texel: 128), and it says so.
  o.memory_budget = 1;
  power(*r, "floor", -2, -2, 2, 2, o);
  const runtime::CausticsStats over = r->caustics_stats();
  EXPECT_TRUE(over.texels.over_budget);
  EXPECT_EQ(over.texels.maps, 4u);
  EXPECT_EQ(map_side(*r, kFloor), 512);
  EXPECT_EQ(map_side(*r, kBall), 128);
  ASSERT_EQ(over.warnings.size(), 1u);
  EXPECT_NE(over.warnings[0].find("besides its caustics maps"), std::string::npos) << over.warnings[0];

  // The ball moved 20 m away, out from under the water: no map, no light,
  // and its texels given back.
  o.memory_budget = 0;
  const Status moved = r->set_object_transform(kBall, Mat4f{0.5f, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0, 0.5f, 0, 20, 0.5f, 0, 1});
  ASSERT_TRUE(moved.ok()) << moved.error().message;
  EXPECT_EQ(power(*r, "ball", 19.5f, -0.5f, 20.5f, 0.5f, o), 0.0);
  const runtime::CausticsStats gone = r->caustics_stats();
  EXPECT_EQ(gone.texels.unreachable, 1u);
  EXPECT_EQ(gone.texels.maps, 3u);
  EXPECT_EQ(map_side(*r, kBall), 1) << "the black 1 x 1 texture";
  EXPECT_LT(gone.texels.map_bytes, free.texels.map_bytes);
}

// FrameUpdate::camera on the default pool with its water moving: a camera
// that sees none of the receivers keeps every map as it was (the same
// texels, counted in maps_out_of_view, fewer draws), the first update in
// view remakes them, and with out_of_view_interval 2 the unseen ones take
// turns, each remade every other update. Cost: about 3 s on llvmpipe.
TEST_F(Texels, ReceiversOutOfViewKeepTheirMapsUntilSeen) {
  auto r = test::bake_and_create(test::write_scene(test::canonical_scene("default"), "out_of_view"));
  ASSERT_TRUE(r);
  runtime::Engine& e = r->engine();
  const runtime::CausticsOptions o = e.default_options();
  const auto texels = [&](std::uint32_t object) {
    const auto l = e.lighting(object, 0);
    EXPECT_TRUE(l.ok());
    GLint w = 0, h = 0;
    glGetTextureLevelParameteriv(l->caustics, 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(l->caustics, 0, GL_TEXTURE_HEIGHT, &h);
    std::vector<float> px(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
    glGetTextureImage(l->caustics, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * 4), px.data());
    return px;
  };
  // Looking up from far above the pool: nothing in view.
  const glm::mat4 away = glm::perspective(glm::radians(40.0f), 1.0f, 0.1f, 100.0f) *
                         glm::lookAt(glm::vec3(0, 50, 0), glm::vec3(0, 60, 0), glm::vec3(0, 0, 1));
  float t = 1.0f;
  const auto update = [&](std::optional<glm::mat4> camera, std::uint32_t interval = 8) {
    runtime::FrameUpdate f{t, o};
    f.camera = camera;
    f.out_of_view_interval = interval;
    t += 0.05f;  // the water moves every update
    EXPECT_TRUE(e.update(f).ok());
    return e.stats();
  };
  const runtime::CausticsStats seen = update(std::nullopt);
  EXPECT_EQ(seen.maps_out_of_view, 0u);
  const std::vector<float> floor0 = texels(kFloor), ball0 = texels(kBall);
  const runtime::CausticsStats unseen = update(away, 64);  // no map's turn (map i's turn: (update + i) mod 64 = 0)
  EXPECT_EQ(unseen.maps_out_of_view, unseen.texels.maps) << "every map kept";
  EXPECT_GE(unseen.texels.maps, 2u);
  EXPECT_TRUE(texels(kFloor) == floor0 && texels(kBall) == ball0) << "kept as they were";
  if (seen.gl.counted) {
    EXPECT_LT(unseen.gl.draws + unseen.gl.dispatches, seen.gl.draws + seen.gl.dispatches);
    std::printf("[out of view] draws + dispatches in view %llu, none in view %llu\n",
                static_cast<unsigned long long>(seen.gl.draws + seen.gl.dispatches),
                static_cast<unsigned long long>(unseen.gl.draws + unseen.gl.dispatches));
  }
  const runtime::CausticsStats back = update(std::nullopt);
  EXPECT_EQ(back.maps_out_of_view, 0u);
  EXPECT_TRUE(texels(kFloor) != floor0 && texels(kBall) != ball0) << "remade once in view";
  // With the interval 2 the unseen maps take turns: each is kept by one
  // update of two, so that two updates keep as many as there are maps.
  const std::uint32_t first = update(away, 2).maps_out_of_view, second = update(away, 2).maps_out_of_view;
  EXPECT_GT(first, 0u);
  EXPECT_GT(second, 0u);
  EXPECT_EQ(first + second, back.texels.maps);
  runtime::FrameUpdate bad{t, o};
  bad.out_of_view_interval = 0;
  const Status refused = e.update(bad);
  EXPECT_FALSE(refused.ok());
  if (!refused.ok()) EXPECT_NE(refused.error().message.find("out_of_view_interval must be 1..64"), std::string::npos) << refused.error().message;
}

// CausticsOptions::map_batching on the default pool with twelve pebbles
// (balls and blocks) added on its floor, its water moving: drawn as
// batches (the maps of one size in one array, one set of calls for them
// all) every map holds what it holds drawn map by map, to the rounding of
// the order the beams are added in; and the calls the water's caustics
// make stay a few per batch instead of some per map; and maps kept out of
// view are untouched while others of their array are drawn; and when the
// water moves again a batch that keeps its windows (no windows pass)
// still holds what map by map holds, in fewer calls. Cost: about 9 s on
// llvmpipe.
TEST_F(Texels, BatchedMapsMatchMapByMapInAFewCalls) {
  nlohmann::json j = test::canonical_scene("default");
  for (int i = 0; i < 12; ++i) {
    const bool ball = i % 2 == 0;
    j["objects"].push_back({{"name", "pebble" + std::to_string(i)},
                            {"mesh", test::kScenes + (ball ? "../meshes/sphere.obj" : "../meshes/box.obj")},
                            {"role", "receiver"},
                            {"material", {{"albedo", {0.8, 0.5, 0.3}}}},
                            {"transform", {{"translate", {-1.5 + 0.6 * (i % 6), 0.15, i < 6 ? 1.4 : -1.5}}, {"scale", ball ? 0.15 : 0.25}}}});
  }
  auto r = test::bake_and_create(test::write_scene(j, "batched"));
  ASSERT_TRUE(r);
  runtime::Engine& e = r->engine();
  const std::uint32_t objects = static_cast<std::uint32_t>(e.scene().objects.size());
  // Every map's level 0 after an update with `batch` and `method`, and the
  // update's draws and dispatches.
  struct Maps {
    std::vector<std::vector<float>> texels;
    std::uint64_t calls = 0;
    bool counted = false;
    std::uint32_t kept = 0;
  };
  const auto update = [&](bool batch, runtime::CausticsMethod method, std::optional<glm::mat4> camera = std::nullopt,
                          float time = 1.0f) {
    runtime::FrameUpdate f{time, e.default_options()};
    f.camera = camera;
    f.out_of_view_interval = 2;  // out of view, every other map remade
    f.caustics.map_batching = batch ? runtime::MapBatching::kAlways : runtime::MapBatching::kNever;
    f.caustics.method = method;
    f.caustics.memory_budget = 0;  // the batches' window depths would count, and the sides differ
    EXPECT_TRUE(e.update(f).ok());
    const runtime::CausticsStats st = e.stats();
    Maps m;
    m.calls = st.gl.draws + st.gl.dispatches;
    m.counted = st.gl.counted;
    m.kept = st.maps_out_of_view;
    EXPECT_FALSE(r->caustics_stats(true).overflowed) << "every entry listed";
    for (std::uint32_t i = 0; i < objects && method != runtime::CausticsMethod::kNone; ++i) {
      const auto l = e.lighting(i, 0);
      std::vector<float> px;
      if (l.ok() && l->caustics) {
        GLint w = 0, h = 0;
        glGetTextureLevelParameteriv(l->caustics, 0, GL_TEXTURE_WIDTH, &w);
        glGetTextureLevelParameteriv(l->caustics, 0, GL_TEXTURE_HEIGHT, &h);
        px.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
        glGetTextureImage(l->caustics, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * 4), px.data());
      }
      m.texels.push_back(std::move(px));
    }
    return m;
  };
  // What a first update does once (and the lists measured for this water:
  // a list that overflows draws what fits, then grows).
  update(true, runtime::CausticsMethod::kLevelMap);
  const Maps single = update(false, runtime::CausticsMethod::kLevelMap);
  const Maps batched = update(true, runtime::CausticsMethod::kLevelMap);
  // The water moves while the camera sees none of the receivers: every
  // other map is remade in its array's layer, and the others are kept as
  // they were, texel for texel.
  const glm::mat4 away = glm::perspective(glm::radians(40.0f), 1.0f, 0.1f, 100.0f) *
                         glm::lookAt(glm::vec3(0, 50, 0), glm::vec3(0, 60, 0), glm::vec3(0, 0, 1));
  const Maps turns = update(true, runtime::CausticsMethod::kLevelMap, away, 1.05f);
  std::uint32_t same = 0, remade = 0;
  for (std::size_t i = 0; i < turns.texels.size(); ++i) {
    if (turns.texels[i].size() <= 4) continue;
    (turns.texels[i] == batched.texels[i] ? same : remade) += 1;
  }
  EXPECT_EQ(same, turns.kept) << "the kept maps untouched";
  EXPECT_GT(same, 0u);
  EXPECT_GT(remade, 0u);
  // Every map of the batches drawn again (the water moved on): each keeps
  // the windows the last updates made.
  const Maps kept = update(true, runtime::CausticsMethod::kLevelMap, std::nullopt, 1.1f);
  const Maps none = update(true, runtime::CausticsMethod::kNone);
  const Maps single_later = update(false, runtime::CausticsMethod::kLevelMap, std::nullopt, 1.1f);
  // The maps compared, every one checked.
  const auto compare = [](const Maps& batch, const Maps& alone, const char* what) {
    if (batch.texels.size() != alone.texels.size()) {
      ADD_FAILURE() << what << ": " << batch.texels.size() << " maps against " << alone.texels.size();
      return 0u;
    }
    std::uint32_t maps = 0, lit = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < batch.texels.size(); ++i) {
      const std::vector<float>& a = batch.texels[i];
      const std::vector<float>& b = alone.texels[i];
      if (a.size() != b.size()) {
        ADD_FAILURE() << what << ", object " << i << ": " << a.size() << " values against " << b.size();
        continue;
      }
      if (a.size() <= 4) continue;
      ++maps;
      // The irradiance (R) and presence (A): beams add in another order,
      // so float rounding, a few parts in 10^6 of the map's brightest texel.
      float peak = 0.0f;
      double sum_a = 0.0, sum_b = 0.0, diff = 0.0;
      for (std::size_t k = 0; k < a.size(); k += 4) {
        peak = std::max(peak, b[k]);
        sum_a += a[k];
        sum_b += b[k];
        diff = std::max(diff, static_cast<double>(std::fabs(a[k] - b[k])));
        EXPECT_EQ(a[k + 3], b[k + 3]) << what << ", presence, object " << i << " texel " << k / 4;
      }
      if (peak <= 0.0f) continue;
      ++lit;
      worst = std::max(worst, diff / peak);
      EXPECT_LE(diff, 1e-4 * peak) << what << ", object " << i;
      EXPECT_NEAR(sum_a, sum_b, 1e-5 * sum_b) << what << ", object " << i;
    }
    EXPECT_GE(maps, 16u);  // floor, walls, ball, block and the pebbles
    EXPECT_GE(lit, 14u);
    std::printf("[batched] %s: %u maps (%u lit): largest difference %.2e of a map's peak\n", what, maps, lit, worst);
    return maps;
  };
  const std::uint32_t maps = compare(batched, single, "windows made");
  compare(kept, single_later, "windows kept");
  if (batched.counted) {
    // Per batch: cull, fix-up, windows, geometry, one or two draws,
    // presence; map by map at least that many per map.
    const std::uint64_t in_batches = batched.calls - none.calls, map_by_map = single.calls - none.calls;
    const std::uint64_t windows_kept = kept.calls - none.calls;
    std::printf("[batched] the water's caustics: %llu draws + dispatches in batches (%llu keeping the windows), %llu map by map\n",
                static_cast<unsigned long long>(in_batches), static_cast<unsigned long long>(windows_kept),
                static_cast<unsigned long long>(map_by_map));
    EXPECT_LT(windows_kept, in_batches) << "no windows pass";
    // At most four runs here: the floor's and the walls' lists take a
    // run each, and the pebbles' maps (four times their need) two sizes.
    EXPECT_LE(in_batches, 3u + 7u * 4u);
    EXPECT_GE(map_by_map, 5u * maps);
  }
}

TEST_F(Texels, BadTexelOptionsAreRefused) {
  auto r = test::bake_and_create(test::write_scene(test::canonical_scene("flat_pool"), "texels_bad"));
  ASSERT_TRUE(r);
  runtime::FrameUpdate f;
  f.caustics.texel_size = -0.01f;
  EXPECT_EQ(r->engine().update(f).error().code, ErrorCode::kUsage);
  f.caustics.texel_size = std::nanf("");
  EXPECT_EQ(r->engine().update(f).error().code, ErrorCode::kUsage);
  f.caustics.texel_size = 0.0f;
  f.caustics.map_size = 0;
  EXPECT_EQ(r->engine().update(f).error().code, ErrorCode::kUsage);
  f.caustics.map_size = 512;
  f.caustics.texel_size = 0.01f;  // 1 cm texels over flat_pool's floor
  ASSERT_TRUE(r->engine().update(f).ok());
  EXPECT_NEAR(r->caustics_stats().texels.texel, 0.01f, 1e-6f);
}

}  // namespace
}  // namespace caustix
