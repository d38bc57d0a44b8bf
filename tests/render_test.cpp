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
#include "caustix/sample/image_output.h"
#include "caustix/sample/renderer.h"
#include "gltf_fixture.h"

namespace caustix {
namespace {

using sample::FrameParams;
using runtime::HeadlessContext;
using sample::Renderer;

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
  EXPECT_EQ(corner[0], 2.0f * sample::kSkyColor[0]);
  EXPECT_EQ(corner[1], 2.0f * sample::kSkyColor[1]);
  EXPECT_EQ(corner[2], 2.0f * sample::kSkyColor[2]);

  // Box top: albedo 0.9 red * (ambient + E0 cos 45deg = 1.41).
  const float* box = img.at(48, 48);
  EXPECT_NEAR(box[0], 0.9f * (0.12f * 2.0f * sample::kSkyColor[0] + 2.0f * std::sqrt(0.5f)), 0.02f);
  EXPECT_LT(box[1], box[0] * 0.5f);

  // Floor left of the box is lit; right of it (downwind) is in its shadow.
  const float* lit = img.at(48, 26);
  const float* shadow = img.at(48, 70);
  EXPECT_NEAR(lit[0], 0.8f * (0.12f * 2.0f * sample::kSkyColor[0] + 2.0f * std::sqrt(0.5f)), 0.02f);
  EXPECT_LT(shadow[0], 0.15f * lit[0]);
}

// The automatic camera (a scene without one; it was once loose
// on wide, flat scenes): the bounds' eight corners all inside a 4:3 frame,
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
      non_sky += img.rgba[i] != sample::kSkyColor[0] ? 1 : 0;
    }
    EXPECT_GT(non_sky, img.rgba.size() / 4 / 3) << "the scene covers too little of the image";
  }
}

TEST(Render, WavesMoveWithTime) {
  const Image a = render("assets/scenes/default.json", 80, 60, 0.0f);
  const Image b = render("assets/scenes/default.json", 80, 60, 1.0f);
  EXPECT_NE(a.rgba, b.rgba);
}


// Albedo textures: a 3 m floor under a sun straight down, seen
// from above (image right = +x, image up = -z), textured with a 64 x 64
// image whose red is sRGB 60 on its left half and 200 on its right, green
// 200 on its top rows and 60 on its bottom ones, blue 128. Ambient and sun
// both scale with the albedo, so two texels' pixels stand in the ratio of
// their linear albedos -- the sRGB transfer function of IEC 61966-2-1,
// written here -- whatever the light level; blue, equal everywhere, is
// the same at all four places. The image's first row is its top, glTF's
// v = 0. Once with box projection in world metres, once through a glTF
// quad's TEXCOORD_0 shifted by KHR_texture_transform (offset 0.5 on a
// repeating sampler puts the image's right half on the floor's left).
double srgb_to_linear(double c) {
  c /= 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

std::string write_quadrant_png(const std::string& tag) {
  std::vector<std::uint8_t> px(64 * 64 * 3);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      std::uint8_t* p = &px[static_cast<std::size_t>(y * 64 + x) * 3];
      p[0] = x < 32 ? 60 : 200;
      p[1] = y < 32 ? 200 : 60;
      p[2] = 128;
    }
  }
  const std::string path = (std::filesystem::temp_directory_path() / ("caustix_" + tag + ".png")).string();
  EXPECT_TRUE(sample::write_u8_image(path, 64, 64, 3, px).ok());
  return path;
}

void expect_texture_ratios(const Image& img, bool swapped_s) {
  // Pixel centres of the floor's four quadrants (world x, z = +-0.75).
  const float* tl = img.at(img.h / 4, img.w / 4);
  const float* tr = img.at(img.h / 4, 3 * img.w / 4);
  const float* bl = img.at(3 * img.h / 4, img.w / 4);
  const double red = srgb_to_linear(60) / srgb_to_linear(200), green = srgb_to_linear(200) / srgb_to_linear(60);
  const double left_over_right = swapped_s ? 1.0 / red : red;
  EXPECT_NEAR(tl[0] / tr[0], left_over_right, 0.01 * left_over_right);
  EXPECT_NEAR(tl[1] / bl[1], green, 0.01 * green);
  EXPECT_NEAR(tl[2] / tr[2], 1.0, 0.01);
  EXPECT_NEAR(tl[2] / bl[2], 1.0, 0.01);
  std::printf("[albedo texture] red left/right %.4f (expected %.4f), green top/bottom %.4f (expected %.4f)\n", tl[0] / tr[0],
              left_over_right, tl[1] / bl[1], green);
}

nlohmann::json top_down_scene() {
  return {{"name", "textured floor"},
          {"lights", {{{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", 1.0}}}},
          {"camera", {{"position", {0, 4.2, 0}}, {"target", {0, 0, 0}}, {"up", {0, 0, -1}}, {"fov_y_deg", 39.3}}}};
}

Image render_file(const std::string& path, int w, int h) {
  auto scene = test::bake_and_load(path);
  EXPECT_TRUE(scene);
  auto ctx = HeadlessContext::create();
  EXPECT_TRUE(ctx.ok());
  auto r = Renderer::create(*scene);
  EXPECT_TRUE(r.ok()) << r.error().message;
  FrameParams f;
  f.camera = (*r)->default_camera();
  f.width = w;
  f.height = h;
  EXPECT_TRUE((*r)->render(f).ok());
  return Image{w, h, (*r)->read_hdr()};
}

TEST(Render, AnAlbedoTextureScalesEachTexelsLightByItsLinearAlbedo) {
  const std::string png = write_quadrant_png("quadrants");
  nlohmann::json j = top_down_scene();
  j["objects"] = {{{"name", "floor"},
                   {"mesh", std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/plane.obj"},
                   {"material", {{"albedo_texture", {{"file", png}, {"projection", "box"}, {"scale", 1.0 / 3.0}, {"offset", {0.5, 0.5}}}}}},
                   {"transform", {{"scale", {3, 1, 3}}}}}};
  expect_texture_ratios(render_file(test::write_scene(j, "textured_box"), 64, 64), false);

  // The same floor as a glTF quad with TEXCOORD_0 (0..1 over it, v = 0 at
  // z = -1.5) and the image embedded in a buffer view.
  test::GltfBuilder b;
  const int pos = b.positions({{-1.5f, 0, -1.5f}, {-1.5f, 0, 1.5f}, {1.5f, 0, 1.5f}, {1.5f, 0, -1.5f}});
  const int nrm = b.normals({{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}});
  const int uv = b.accessor(std::vector<float>{0, 0, 0, 1, 1, 1, 1, 0}, 5126, "VEC2", 4);
  const int idx = b.indices({0, 1, 2, 0, 2, 3});
  std::ifstream in(png, std::ios::binary);
  const std::vector<std::uint8_t> png_bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  b.doc["images"] = {{{"bufferView", b.view(png_bytes.data(), png_bytes.size())}, {"mimeType", "image/png"}}};
  b.doc["samplers"] = {{{"wrapS", 10497}, {"wrapT", 10497}}};
  b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
  b.use_extension("KHR_texture_transform", true);
  const nlohmann::json texture{{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0.0}}}}}}};
  const int mat = b.material({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"baseColorTexture", texture}}}});
  // The same without colour: a glTF dielectric's specular layer (F0 0.04)
  // does not take the base colour, so the texture scales what is left.
  const int black = b.material({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"baseColorFactor", {0, 0, 0, 1}}, {"baseColorTexture", texture}}}});
  const auto render_quad = [&](int material, const std::string& tag) {
    test::GltfBuilder q = b;
    const int mesh = q.mesh({{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}}}, {"indices", idx}, {"material", material}}});
    q.scene({q.node({{"name", "floor"}, {"mesh", mesh}})});
    const auto gltf = std::filesystem::temp_directory_path() / ("caustix_" + tag + ".gltf");
    q.write_embedded(gltf);
    nlohmann::json g = top_down_scene();
    g["gltf"] = gltf.string();
    return render_file(test::write_scene(g, tag), 64, 64);
  };
  Image diffuse = render_quad(mat, "textured_quad");
  const Image specular = render_quad(black, "black_quad");
  for (std::size_t k = 0; k < diffuse.rgba.size(); ++k) diffuse.rgba[k] -= specular.rgba[k];
  expect_texture_ratios(diffuse, true);
}

// The analytic sky (FrameParams::sky; Preetham, Shirley & Smits 1999): a
// camera at the floor looking straight up under a sun 45 degrees high
// towards +z. The zenith has the flat sky's luminance (what the model is
// scaled to), the circumsolar sky towards the sun is brighter than the
// sky 90 degrees away from it on the other side, and the zenith is bluer
// than it is red (a clear day).
TEST(Render, TheAnalyticSkyIsScaledToTheFlatSkyAtTheZenithAndBrightAboutTheSun) {
  nlohmann::json j{{"name", "sky"},
                   {"objects", {{{"name", "floor"}, {"mesh", std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/plane.obj"}}}},
                   {"lights", {{{"type", "directional"}, {"direction", {0, -1, -1}}, {"irradiance", 1.0}}}},
                   {"camera", {{"position", {0, 0.5, 0}}, {"target", {0, 1.5, 0}}, {"up", {0, 0, -1}}, {"fov_y_deg", 90}}}};
  auto scene = test::bake_and_load(test::write_scene(j, "analytic_sky"));
  ASSERT_TRUE(scene);
  auto ctx = HeadlessContext::create();
  ASSERT_TRUE(ctx.ok());
  auto r = Renderer::create(*scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  FrameParams f;
  f.camera = (*r)->default_camera();
  f.width = f.height = 64;
  f.sky = sample::SkyModel::kAnalytic;
  ASSERT_TRUE((*r)->render(f).ok());
  const Image img{64, 64, (*r)->read_hdr()};
  const auto luminance = [](const float* c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; };
  const double flat = luminance(sample::kSkyColor);
  // The four centre pixels straddle the zenith (0.7 degrees off it).
  double zenith = 0;
  for (int k = 0; k < 4; ++k) zenith += 0.25 * luminance(img.at(31 + k / 2, 31 + k % 2));
  EXPECT_NEAR(zenith, flat, 0.01 * flat);
  const float* towards_sun = img.at(60, 32);  // image bottom: +z
  const float* away = img.at(3, 32);
  EXPECT_GT(luminance(towards_sun), 2.0 * luminance(away));
  const float* z = img.at(31, 31);
  EXPECT_GT(z[2], z[0]);
  std::printf("[analytic sky] zenith luminance %.4f (flat sky %.4f), towards the sun %.3f, away %.3f\n", zenith, flat,
              luminance(towards_sun), luminance(away));
}

// Surfaces (glTF's metallic-roughness model, formats/scene.h Surface) on
// a 3 m floor seen straight down from 4.2 m under the flat sky, checked at
// the four centre pixels (the view within 0.5 degrees of the normal)
// against what the model gives there in closed form:
// - emission alone (a black metal: F0 = 0, no diffuse) is emissive times
//   the reference irradiance;
// - a smooth metal of base colour 1 reflects the sky overhead exactly
//   (F0 = 1; the split sum's A + B is 1 at roughness 0 and normal view);
// - a white rough dielectric under a sky of constant radiance S above the
//   horizon has diffuse irradiance / pi = S exactly (the harmonics of such
//   a step are exact along its axis), plus F0 = 0.04 of the sky times A
//   (0.452 at roughness 1, B 0);
// - the sun's specular on a metal at normal incidence (n = l = v = h) is
//   pi D Vis F E with D = 1 / (pi alpha^2), Vis = 1/4, F = F0: base E /
//   (4 alpha^2), measured as the difference with the sun off.
TEST(Render, SurfacesShadeAsTheMetallicRoughnessModelAtNormalIncidence) {
  const auto centre = [&](const nlohmann::json& material, const std::vector<double>& sun, double e0) {
    nlohmann::json j = top_down_scene();
    j["lights"] = {{{"type", "directional"}, {"direction", sun}, {"irradiance", e0}}};
    j["objects"] = {{{"name", "floor"},
                     {"mesh", std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/plane.obj"},
                     {"material", material},
                     {"transform", {{"scale", {3, 1, 3}}}}}};
    const Image img = render_file(test::write_scene(j, "surface"), 64, 64);
    glm::dvec3 c(0.0);
    for (int k = 0; k < 4; ++k) {
      const float* p = img.at(31 + k / 2, 31 + k % 2);
      c += 0.25 * glm::dvec3(p[0], p[1], p[2]);
    }
    return c;
  };
  const std::vector<double> up{0, 1, 0}, down{0, -1, 0};  // a sun travelling up lights nothing facing up
  const glm::dvec3 sky(sample::kSkyColor[0], sample::kSkyColor[1], sample::kSkyColor[2]);  // E0 = 1
  const auto expect_near = [](const glm::dvec3& got, const glm::dvec3& want, const char* what) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 0.01 * want[k] + 1e-4) << what << ", channel " << k;
    std::printf("[surfaces] %s: %.4f %.4f %.4f (model %.4f %.4f %.4f)\n", what, got.x, got.y, got.z, want.x, want.y, want.z);
  };
  expect_near(centre({{"albedo", 0.0}, {"metallic", 1.0}, {"emissive", {0.5, 0.25, 0.1}}}, up, 1.0), {0.5, 0.25, 0.1}, "emission");
  expect_near(centre({{"albedo", 1.0}, {"metallic", 1.0}, {"roughness", 0.0}}, up, 1.0), sky, "smooth metal");
  expect_near(centre({{"albedo", 1.0}, {"roughness", 1.0}}, up, 1.0), sky * (1.0 + 0.04 * 0.452), "white dielectric");
  const nlohmann::json metal{{"albedo", 0.5}, {"metallic", 1.0}, {"roughness", 0.5}};
  const double alpha = 0.25;
  expect_near(centre(metal, down, 1.0) - centre(metal, down, 0.0), glm::dvec3(0.5 / (4.0 * alpha * alpha)), "sun on metal");
}

// glTF's COLOR_0 multiplies the base colour (glTF 2.0 §3.9.2): a white
// rough dielectric quad whose vertices carry c = (0.5, 0.25, 1), as
// normalised unsigned bytes, under the flat sky seen straight down shows
// sky (c + 0.04 A), A = 0.452 (the specular layer does not take the
// colour), against sky (1 + 0.04 A) without the colours.
TEST(Render, VertexColoursMultiplyTheBaseColour) {
  test::GltfBuilder b;
  const int pos = b.positions({{-1.5f, 0, -1.5f}, {-1.5f, 0, 1.5f}, {1.5f, 0, 1.5f}, {1.5f, 0, -1.5f}});
  const int nrm = b.normals({{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}});
  std::vector<std::uint8_t> rgba;
  for (int v = 0; v < 4; ++v) rgba.insert(rgba.end(), {128, 64, 255, 255});
  const int col = b.accessor(rgba, 5121, "VEC4", 4, /*normalized=*/true);
  const int idx = b.indices({0, 1, 2, 0, 2, 3});
  const int mat = b.material({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}});
  const auto render = [&](bool colours, const std::string& tag) {
    test::GltfBuilder q = b;
    nlohmann::json attributes{{"POSITION", pos}, {"NORMAL", nrm}};
    if (colours) attributes["COLOR_0"] = col;
    q.scene({q.node({{"name", "floor"}, {"mesh", q.mesh({{{"attributes", attributes}, {"indices", idx}, {"material", mat}}})}})});
    const auto gltf = std::filesystem::temp_directory_path() / ("caustix_" + tag + ".gltf");
    q.write_embedded(gltf);
    nlohmann::json g = top_down_scene();
    g["lights"] = {{{"type", "directional"}, {"direction", {0, 1, 0}}, {"irradiance", 1.0}}};  // lights nothing facing up
    g["gltf"] = gltf.string();
    const Image img = render_file(test::write_scene(g, tag), 64, 64);
    const float* p = img.at(32, 32);
    return glm::dvec3(p[0], p[1], p[2]);
  };
  const glm::dvec3 sky(sample::kSkyColor[0], sample::kSkyColor[1], sample::kSkyColor[2]);
  const glm::dvec3 c(128.0 / 255.0, 64.0 / 255.0, 1.0);
  const glm::dvec3 plain = render(false, "uncoloured_quad"), coloured = render(true, "coloured_quad");
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(plain[k], sky[k] * (1.0 + 0.04 * 0.452), 0.005 * sky[k]) << k;
    EXPECT_NEAR(coloured[k], sky[k] * (c[k] + 0.04 * 0.452), 0.005 * sky[k]) << k;
  }
  std::printf("[vertex colours] %.4f %.4f %.4f (closed form %.4f %.4f %.4f)\n", coloured.x, coloured.y, coloured.z, sky.x * (c.x + 0.04 * 0.452),
              sky.y * (c.y + 0.04 * 0.452), sky.z * (c.z + 0.04 * 0.452));
}

// The maps and alpha of glTF's material (SurfaceMaps) against closed forms,
// each a floor seen from above at normal incidence (box-projected solid
// textures from scene.json, so that only the map's meaning is tested):
// - an emissive texture multiplies the emission by its linear colour;
// - an occlusion texture of R scales the ambient light by R;
// - a metallic-roughness texture of (G 1, B 0) on metallic 1 roughness 1
//   gives the white rough dielectric sky(1 + 0.04 A);
// - a normal map tilting the normal 45 degrees towards a sun 45 degrees
//   high turns the sun's part of the Lambertian floor, E0 cos 45, into E0
//   (and away from it, into 0), along the texture's s (T) and along N x T (the map's +y, up
//   the image): the glTF convention, measured in both axes;
// - a masked floor (alpha 0 on its left half) shows the emissive floor
//   below it there, a blended one (alpha 0.25) alpha of itself over the
//   rest.
TEST(Render, MapsAndAlphaShadeAsTheirClosedForms) {
  const auto solid = [](const std::string& tag, std::vector<std::uint8_t> texel, bool left_clear = false) {
    const int channels = static_cast<int>(texel.size());
    std::vector<std::uint8_t> px;
    for (int y = 0; y < 16; ++y) {
      for (int x = 0; x < 16; ++x) {
        for (int c = 0; c < channels; ++c) px.push_back(c == 3 && left_clear && x < 8 ? 0 : texel[static_cast<std::size_t>(c)]);
      }
    }
    const std::string path = (std::filesystem::temp_directory_path() / ("caustix_map_" + tag + ".png")).string();
    EXPECT_TRUE(sample::write_u8_image(path, 16, 16, channels, px).ok());
    return path;
  };
  const auto box = [](const std::string& file) { return nlohmann::json{{"file", file}, {"projection", "box"}, {"scale", 1.0 / 3.0}, {"offset", {0.5, 0.5}}}; };
  const std::string plane = std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/plane.obj";
  const auto render = [&](nlohmann::json material, const std::vector<double>& sun, nlohmann::json below = nullptr) {
    nlohmann::json j = top_down_scene();
    j["lights"] = {{{"type", "directional"}, {"direction", sun}, {"irradiance", 1.0}}};
    j["objects"] = {{{"name", "floor"}, {"mesh", plane}, {"material", material}, {"transform", {{"scale", {3, 1, 3}}}}}};
    if (!below.is_null()) {
      j["objects"].push_back({{"name", "below"}, {"mesh", plane}, {"material", below}, {"transform", {{"translate", {0, -0.5, 0}}, {"scale", {6, 1, 6}}}}});
    }
    return render_file(test::write_scene(j, "maps"), 64, 64);
  };
  const auto at = [](const Image& img, int row, int col) {
    glm::dvec3 c(0.0);
    for (int k = 0; k < 4; ++k) {
      const float* p = img.at(row + k / 2, col + k % 2);
      c += 0.25 * glm::dvec3(p[0], p[1], p[2]);
    }
    return c;
  };
  const auto centre = [&](const Image& img) { return at(img, 31, 31); };
  const auto expect_near = [](const glm::dvec3& got, const glm::dvec3& want, const char* what) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 0.01 * want[k] + 2e-3) << what << ", channel " << k;
    std::printf("[maps] %s: %.4f %.4f %.4f (closed form %.4f %.4f %.4f)\n", what, got.x, got.y, got.z, want.x, want.y, want.z);
  };
  const std::vector<double> up{0, 1, 0};
  const glm::dvec3 sky(sample::kSkyColor[0], sample::kSkyColor[1], sample::kSkyColor[2]);
  const nlohmann::json glowing{{"albedo", 0.0}, {"metallic", 1.0}, {"emissive", 1.0}};

  nlohmann::json emissive = glowing;
  emissive["emissive_texture"] = box(solid("emissive", {188, 128, 64}));
  expect_near(centre(render(emissive, up)), {srgb_to_linear(188), srgb_to_linear(128), srgb_to_linear(64)}, "emissive texture");

  const glm::dvec3 white_dielectric = sky * (1.0 + 0.04 * 0.452);
  expect_near(centre(render({{"albedo", 1.0}, {"roughness", 1.0}, {"occlusion_texture", box(solid("occlusion", {128, 255, 255}))}}, up)),
              white_dielectric * (128.0 / 255.0), "occlusion 128/255");
  expect_near(centre(render({{"albedo", 1.0}, {"metallic", 1.0}, {"roughness", 1.0}, {"metallic_roughness_texture", box(solid("mr", {0, 255, 0}))}}, up)),
              white_dielectric, "metallic-roughness (G 1, B 0) on a metal");

  // Tangent-space normals 45 degrees off the surface's, 8-bit encoded.
  const auto tilted = [&](const std::string& tag, std::uint8_t x, std::uint8_t y) {
    return nlohmann::json{{"albedo", 1.0}, {"normal_texture", box(solid(tag, {x, y, 218}))}};
  };
  const double s = std::sqrt(0.5), c45 = (218.0 / 255.0 * 2.0 - 1.0);
  const auto lambert = [&](double tx, double ty, const glm::dvec3& to_sun) {
    // N (0, 1, 0), T +x (box projection: s along world x), B = N x T = -z.
    const glm::dvec3 n = glm::normalize(glm::dvec3(tx, c45, -ty));
    return glm::dvec3(std::max(glm::dot(n, glm::normalize(to_sun)), 0.0));
  };
  const double plus = 218.0 / 255.0 * 2.0 - 1.0, minus = 37.0 / 255.0 * 2.0 - 1.0, zero = 128.0 / 255.0 * 2.0 - 1.0;
  const std::vector<double> from_plus_x{-s, -s, 0}, from_minus_z{0, -s, s};
  // The sun's part: the render less the same floor's ambient alone.
  const auto sunlit = [&](const nlohmann::json& material, const std::vector<double>& sun) {
    return centre(render(material, sun)) - centre(render(material, up));
  };
  expect_near(sunlit({{"albedo", 1.0}}, from_plus_x), glm::dvec3(s), "flat, sun 45 degrees high");
  expect_near(sunlit(tilted("nx", 218, 128), from_plus_x), lambert(plus, zero, {1, 1, 0}), "normal tilted along +T towards the sun");
  expect_near(sunlit(tilted("nx_away", 37, 128), from_plus_x), lambert(minus, zero, {1, 1, 0}), "normal tilted along -T, away");
  expect_near(sunlit(tilted("ny", 128, 218), from_minus_z), lambert(zero, plus, {0, 1, -1}), "normal tilted along +B (up the image) towards the sun");

  // Alpha: the floor below glows red, the floor on top blue.
  const nlohmann::json red{{"albedo", 0.0}, {"metallic", 1.0}, {"emissive", {1.0, 0.0, 0.0}}};
  nlohmann::json mask{{"albedo", 0.0}, {"metallic", 1.0}, {"emissive", {0.0, 0.0, 1.0}}, {"alpha_mode", "mask"},
                      {"albedo_texture", box(solid("alpha", {255, 255, 255, 255}, true))}};
  const Image masked = render(mask, up, red);
  expect_near(at(masked, 31, 12), {1.0, 0.0, 0.0}, "masked: the floor below through the clear half");
  expect_near(at(masked, 31, 50), {0.0, 0.0, 1.0}, "masked: the opaque half");
  nlohmann::json blend{{"albedo", 0.0}, {"metallic", 1.0}, {"emissive", {0.0, 0.0, 1.0}}, {"alpha_mode", "blend"}, {"alpha", 0.25}};
  expect_near(centre(render(blend, up, red)), {0.75, 0.0, 0.25}, "blended at alpha 0.25 over the floor below");
}

}  // namespace
}  // namespace caustix
