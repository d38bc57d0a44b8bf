// scene.json front end: every error names file, line and column.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "caustix/bake/bake.h"
#include "caustix/bake/scene_json.h"
#include "caustix/bake/texture_import.h"

namespace caustix::bake {
namespace {

const char* kMinimal = R"({
  "objects": [
    { "name": "floor", "mesh": "plane.obj" }
  ],
  "lights": [ { "type": "directional", "direction": [0, -1, 0] } ]
})";

std::string error_of(const std::string& text) {
  auto r = parse_scene_json(text, "scene.json");
  EXPECT_FALSE(r.ok()) << "accepted: " << text;
  return r.ok() ? "" : r.error().message;
}

TEST(SceneJson, MinimalSceneAndDefaults) {
  auto r = parse_scene_json(kMinimal, "dir/scene.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const SceneDesc& s = r->scene;
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].role, Role::kReceiver);
  EXPECT_EQ(r->mesh_paths, std::vector<std::string>{"dir/plane.obj"});
  EXPECT_EQ(s.meshes[0].source, "plane.obj");
  EXPECT_FALSE(s.water.has_value());
  EXPECT_TRUE(r->warnings.empty());
}

TEST(SceneJson, SharedMeshIsImportedOnce) {
  auto r = parse_scene_json(R"({"objects": [{"name": "a", "mesh": "m.obj"}, {"name": "b", "mesh": "./m.obj"},
                                            {"name": "c", "mesh": "n.obj"}]})", "s.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->mesh_paths.size(), 2u);
  EXPECT_EQ(r->scene.objects[1].mesh_index, 0u);
  EXPECT_EQ(r->scene.objects[2].mesh_index, 1u);
}

TEST(SceneJson, TransformAndDirectionNormalisation) {
  auto r = parse_scene_json(R"({"objects": [{"name": "a", "mesh": "m.obj",
      "transform": {"translate": [1, 2, 3], "rotate_deg": [0, 90, 0], "scale": 2}}],
      "lights": [{"type": "directional", "direction": [0, -2, 0]}],
      "water": {"level": 1, "waves": [{"amplitude": 0.1, "wavelength": 1, "direction": [3, 4]}]}})",
                            "s.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Mat4f& m = r->scene.objects[0].transform;
  // Ry(90) maps +x to -z; scale 2; then translate.
  EXPECT_NEAR(m[0], 0.0f, 1e-6f);
  EXPECT_NEAR(m[2], -2.0f, 1e-6f);
  EXPECT_NEAR(m[5], 2.0f, 1e-6f);
  EXPECT_EQ(m[12], 1.0f);
  EXPECT_EQ(m[14], 3.0f);
  EXPECT_NEAR(r->scene.lights[0].direction[1], -1.0f, 1e-6f);
  EXPECT_NEAR(r->scene.water->waves[0].direction[0], 0.6f, 1e-6f);
}

TEST(SceneJson, SyntaxErrorHasLineAndColumn) {
  const std::string msg = error_of("{\n  \"objects\": [\n    { \"name\": \"a\" \"mesh\": \"m.obj\" }\n  ]\n}");
  EXPECT_EQ(msg.rfind("scene.json:3:", 0), 0u) << msg;
}

TEST(SceneJson, WrongTypePointsAtTheKey) {
  const std::string msg = error_of(R"({
  "objects": [
    { "name": "floor", "mesh": "plane.obj",
      "material": { "albedo": "white" } }
  ]
})");
  EXPECT_EQ(msg.rfind("scene.json:4:21: /objects/0/material/albedo", 0), 0u) << msg;
  EXPECT_NE(msg.find("string"), std::string::npos) << msg;
}

TEST(SceneJson, MissingFieldPointsAtTheObject) {
  const std::string msg = error_of("{\n  \"objects\": [\n    { \"name\": \"floor\" }\n  ]\n}");
  EXPECT_EQ(msg.rfind("scene.json:3:5: /objects/0: missing required field \"mesh\"", 0), 0u) << msg;
}

TEST(SceneJson, AbsurdValuesAreLocated) {
  std::string msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}],
 "water": {"level": 0, "grid": {"cells": [1000000000, 10]}}})");
  EXPECT_EQ(msg.rfind("scene.json:2:33: /water/grid/cells", 0), 0u) << msg;
  msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj", "transform": {"scale": 0}}]})");
  EXPECT_NE(msg.find("/objects/0/transform"), std::string::npos) << msg;
  EXPECT_NE(msg.find("degenerate"), std::string::npos) << msg;
  msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}], "water": {"level": 0, "ior": -1}})");
  EXPECT_NE(msg.find("scene.json:1:69: /water/ior"), std::string::npos) << msg;
  msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}], "water": {"level": 0, "grid": {"cells": [-4, 2]}}})");
  EXPECT_NE(msg.find("/water/grid/cells/0"), std::string::npos) << msg;
  // An empty water extent would make zero-area water triangles.
  msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}], "water": {"level": 0, "grid": {"extent": [1, -6, 1, 6]}}})");
  EXPECT_NE(msg.find("/water/grid/extent"), std::string::npos) << msg;
}

TEST(SceneJson, DuplicateKeysAndNamesAreErrors) {
  std::string msg = error_of("{\"objects\": [{\"name\": \"a\", \"name\": \"b\", \"mesh\": \"m.obj\"}]}");
  EXPECT_NE(msg.find("duplicate key \"name\""), std::string::npos) << msg;
  EXPECT_NE(msg.find("scene.json:1:"), std::string::npos) << msg;
  msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}, {"name": "a", "mesh": "m.obj"}]})");
  EXPECT_NE(msg.find("/objects/1/name"), std::string::npos) << msg;
}

TEST(SceneJson, UnknownFieldsWarnWithPlace) {
  auto r = parse_scene_json(R"({"objects": [{"name": "a", "mesh": "m.obj", "colour": [1, 0, 0]}],
    "lights": [{"type": "directional", "direction": [0, -1, 0]}]})", "s.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_EQ(r->warnings[0].rfind("s.json:1:45: /objects/0/colour: unknown field", 0), 0u) << r->warnings[0];
}

TEST(SceneJson, NotAnObjectAndEmpty) {
  EXPECT_NE(error_of("[1, 2]").find("expected an object"), std::string::npos);
  EXPECT_NE(error_of("").find("scene.json:1:1"), std::string::npos);
  EXPECT_NE(error_of("{}").find("missing required field \"objects\""), std::string::npos);
  EXPECT_NE(error_of(R"({"objects": []})").find("at least one object"), std::string::npos);
}

TEST(SceneJson, MissingFileIsAnInputError) {
  auto r = load_scene_json("/nonexistent/scene.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kInput);
  EXPECT_NE(r.error().message.find("/nonexistent/scene.json"), std::string::npos);
}

TEST(SceneJson, HugeNumbersAndLightTypes) {
  EXPECT_NE(error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}], "lights": [{"type": "directional", "direction": [1e300, 0, 0]}]})")
                .find("/lights/0/direction/0"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}], "lights": [{"type": "area"}]})")
                .find("/lights/0/type"),
            std::string::npos);
}

// Spot lights: a point light with KHR_lights_punctual's cone,
// half-angles in degrees (inner 0 and outer 45 unless given), pointing
// down unless given; bad cones are located.
TEST(SceneJson, SpotLights) {
  auto r = parse_scene_json(R"({"objects": [{"name": "a", "mesh": "m.obj"}], "lights": [
    {"type": "spot", "position": [0, 3, 0], "intensity": 5, "direction": [0, -2, 0], "inner_cone_deg": 10, "outer_cone_deg": 30},
    {"type": "spot", "position": [1, 3, 0]}]})", "scene.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Light& a = r->scene.lights[0];
  EXPECT_TRUE(a.spot);
  EXPECT_EQ(a.type, LightType::kPoint);
  EXPECT_FLOAT_EQ(a.direction[1], -1.0f);  // normalised
  EXPECT_NEAR(a.inner_cone, 10 * 3.14159265 / 180, 1e-6);
  EXPECT_NEAR(a.outer_cone, 30 * 3.14159265 / 180, 1e-6);
  const Light& b = r->scene.lights[1];
  EXPECT_TRUE(b.spot);
  EXPECT_FLOAT_EQ(b.inner_cone, 0.0f);
  EXPECT_NEAR(b.outer_cone, 3.14159265 / 4, 1e-6);
  EXPECT_FLOAT_EQ(b.direction[1], -1.0f);
  std::string msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}], "lights": [{"type": "spot", "position": [0, 3, 0], "outer_cone_deg": 100}]})");
  EXPECT_NE(msg.find("/lights/0/outer_cone_deg: must be in (0, 90] degrees"), std::string::npos) << msg;
  msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}], "lights": [{"type": "spot", "position": [0, 3, 0], "inner_cone_deg": 50, "outer_cone_deg": 40}]})");
  EXPECT_NE(msg.find("/lights/0/inner_cone_deg"), std::string::npos) << msg;
  msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj"}], "lights": [{"type": "spot", "position": [0, 3, 0], "direction": [0, 0, 0]}]})");
  EXPECT_NE(msg.find("/lights/0/direction"), std::string::npos) << msg;
}

// Albedo textures: a file name (mesh UVs), or the object form
// with box projection and KHR_texture_transform's parts; one image per
// distinct file; the albedo defaults to 1 under a texture and tints it
// when given; bad values are located; a texture on glass is refused.
TEST(SceneJson, AlbedoTextures) {
  auto r = parse_scene_json(R"({"objects": [
      {"name": "a", "mesh": "m.obj", "material": {"albedo_texture": "tex/tiles.png"}},
      {"name": "b", "mesh": "n.obj", "material": {"albedo": [1, 0.5, 0.5],
        "albedo_texture": {"file": "./tex/tiles.png", "projection": "box", "scale": [2, 4], "offset": [0.5, 0], "rotation_deg": 90, "wrap": "mirror"}}},
      {"name": "c", "mesh": "n.obj", "material": {"albedo_texture": {"file": "stone.jpg"}}}]})", "dir/scene.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->images.size(), 2u);
  EXPECT_EQ(r->images[0].path, "dir/tex/tiles.png");
  EXPECT_NE(r->images[0].where.find("dir/scene.json:2:"), std::string::npos) << r->images[0].where;
  EXPECT_EQ(r->images[1].path, "dir/stone.jpg");
  const auto& a = r->scene.objects[0].material;
  ASSERT_TRUE(a.albedo_texture);
  EXPECT_EQ(a.albedo, (Vec3f{1, 1, 1}));
  EXPECT_EQ(a.albedo_texture->projection, TextureProjection::kUv);
  EXPECT_EQ(a.albedo_texture->transform, (std::array<float, 6>{1, 0, 0, 0, 1, 0}));
  const auto& b = r->scene.objects[1].material;
  ASSERT_TRUE(b.albedo_texture);
  EXPECT_EQ(b.albedo_texture->image, 0u);
  EXPECT_EQ(b.albedo, (Vec3f{1, 0.5f, 0.5f}));
  EXPECT_EQ(b.albedo_texture->projection, TextureProjection::kBox);
  EXPECT_EQ(b.albedo_texture->wrap_s, TextureWrap::kMirror);
  EXPECT_EQ(b.albedo_texture->wrap_t, TextureWrap::kMirror);
  // rotation 90 deg: rows (c sx, s sy, ox) = (0, 4, 0.5) and (-s sx, c sy, oy) = (-2, 0, 0).
  const std::array<float, 6> want{0, 4, 0.5f, -2, 0, 0};
  for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(b.albedo_texture->transform[k], want[k], 1e-6f) << k;
  EXPECT_EQ(r->scene.objects[2].material.albedo_texture->image, 1u);

  std::string msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj",
      "material": {"albedo_texture": {"file": "t.png", "projection": "sphere"}}}]})");
  EXPECT_NE(msg.find("scene.json:2:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("/objects/0/material/albedo_texture/projection: expected \"uv\" or \"box\""), std::string::npos) << msg;
  msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj", "material": {"albedo_texture": {"scale": 2}}}]})");
  EXPECT_NE(msg.find("/objects/0/material/albedo_texture: missing required field \"file\""), std::string::npos) << msg;
  msg = error_of(R"({"objects": [{"name": "g", "mesh": "m.obj", "role": "transparent",
      "material": {"transparent": true, "albedo_texture": "t.png"}}]})");
  EXPECT_NE(msg.find("/objects/0/material/albedo_texture: only a receiver takes an albedo texture"), std::string::npos) << msg;
}

// glTF's maps and alpha in scene.json (formats/scene.h SurfaceMaps): each
// texture key as "albedo_texture"'s; one file read as colour and as data
// is two images; a masking base colour keeps its alpha; a bad mode is
// named with its place.
TEST(SceneJson, MapsAndAlpha) {
  auto r = parse_scene_json(R"({"objects": [
      {"name": "a", "mesh": "m.obj", "material": {"albedo_texture": "t.png", "normal_texture": {"file": "n.png", "projection": "box"},
        "metallic_roughness_texture": "orm.png", "occlusion_texture": "orm.png", "emissive_texture": "t.png",
        "normal_scale": 0.5, "occlusion_strength": 0.25, "alpha_mode": "mask", "alpha_cutoff": 0.4, "alpha": 0.9}},
      {"name": "b", "mesh": "m.obj", "material": {"alpha_mode": "blend"}}]})", "scene.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Material& a = r->scene.objects[0].material;
  ASSERT_TRUE(a.maps && a.albedo_texture && a.maps->normal && a.maps->metallic_roughness && a.maps->occlusion && a.maps->emissive);
  EXPECT_EQ(a.maps->normal->projection, TextureProjection::kBox);
  EXPECT_EQ(a.maps->metallic_roughness->image, a.maps->occlusion->image);
  EXPECT_EQ(a.albedo_texture->image, a.maps->emissive->image);
  ASSERT_EQ(r->images.size(), 3u);  // t.png (colour), n.png and orm.png (data)
  EXPECT_TRUE(r->images[a.albedo_texture->image].keep_alpha);
  EXPECT_FALSE(r->images[a.albedo_texture->image].data);
  EXPECT_TRUE(r->images[a.maps->normal->image].data);
  EXPECT_EQ(a.maps->normal_scale, 0.5f);
  EXPECT_EQ(a.maps->occlusion_strength, 0.25f);
  EXPECT_EQ(a.maps->alpha_mode, AlphaMode::kMask);
  EXPECT_EQ(a.maps->alpha_cutoff, 0.4f);
  EXPECT_EQ(a.maps->alpha, 0.9f);
  ASSERT_TRUE(r->scene.objects[1].material.maps);
  EXPECT_EQ(r->scene.objects[1].material.maps->alpha_mode, AlphaMode::kBlend);
  EXPECT_FALSE(r->scene.objects[1].material.maps->any_map());

  std::string msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj", "material": {"alpha_mode": "glass"}}]})");
  EXPECT_NE(msg.find("/objects/0/material/alpha_mode: expected \"opaque\", \"mask\" or \"blend\""), std::string::npos) << msg;
  msg = error_of(R"({"objects": [{"name": "a", "mesh": "m.obj", "material": {"occlusion_strength": 3}}]})");
  EXPECT_NE(msg.find("/objects/0/material/occlusion_strength: must be in [0, 1]"), std::string::npos) << msg;
}

// What the baker says of a texture it cannot use: a file that is not there
// (named with the scene's line and column, nothing written), and a mesh
// without texture coordinates under "uv" (the fix named).
TEST(SceneJson, TextureErrorsAtBakeNameThePlace) {
  const auto dir = std::filesystem::temp_directory_path() / "caustix_texture_errors";
  std::filesystem::create_directories(dir);
  const std::string plane = std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/plane.obj";
  const auto write = [&](const std::string& material) {
    const auto path = dir / "scene.json";
    std::ofstream(path) << R"({"objects": [{"name": "floor", "mesh": ")" << plane << R"(",
  "material": )" << material << "}]}";
    return path.string();
  };
  auto baked = bake_scene(write(R"({"albedo_texture": "nowhere.png"})"), BakeOptions{});
  ASSERT_FALSE(baked.ok());
  EXPECT_EQ(baked.error().code, ErrorCode::kInput);
  EXPECT_NE(baked.error().message.find("scene.json:2:16: /objects/0/material/albedo_texture: image '"), std::string::npos) << baked.error().message;
  EXPECT_NE(baked.error().message.find("nowhere.png': cannot be read"), std::string::npos) << baked.error().message;
  baked = bake_scene(write(R"({"albedo_texture": ")" + std::string(CAUSTIX_SOURCE_DIR) + R"(/assets/textures/pool_tiles.png"})"), BakeOptions{});
  ASSERT_FALSE(baked.ok());
  EXPECT_NE(baked.error().message.find("plane.obj: the mesh has no texture coordinates for its textures; give the textures \"projection\": \"box\""),
            std::string::npos) << baked.error().message;
  std::filesystem::remove_all(dir);
}

// The texture reader (bake/texture_import.h): a file and the same bytes
// embedded give the same texels; an image over max_size is filtered down
// to fit, keeping its mean colour (a box-like filter: within 1 %); bytes
// that are not an image and a MIME type glTF does not allow are refused
// naming the image and where it was named.
TEST(TextureImport, FilesBytesFittingAndRefusals) {
  const std::string path = std::string(CAUSTIX_SOURCE_DIR) + "/assets/textures/pool_tiles.png";
  ImageSource file;
  file.name = file.path = path;
  auto a = read_texture(file);
  ASSERT_TRUE(a.ok()) << a.error().message;
  EXPECT_EQ(a->width, 256u);
  EXPECT_EQ(a->height, 256u);
  ImageSource embedded;
  embedded.name = "/images/0";
  embedded.mime_type = "image/png";
  std::ifstream in(path, std::ios::binary);
  embedded.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  auto b = read_texture(embedded);
  ASSERT_TRUE(b.ok()) << b.error().message;
  EXPECT_EQ(b->rgb, a->rgb);

  auto small = read_texture(file, 64);
  ASSERT_TRUE(small.ok()) << small.error().message;
  EXPECT_EQ(small->width, 64u);
  EXPECT_EQ(small->height, 64u);
  const auto mean = [](const TextureImage& t, std::size_t k) {
    double m = 0;
    for (std::size_t i = k; i < t.rgb.size(); i += 3) m += t.rgb[i];
    return m / (t.rgb.size() / 3);
  };
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(mean(*small, k), mean(*a, k), 0.01 * mean(*a, k)) << k;

  ImageSource junk;
  junk.name = "/images/1";
  junk.mime_type = "image/png";
  junk.where = "lamp.glb: /images/1";
  junk.bytes = {'n', 'o', 't', ' ', 'a', ' ', 'p', 'n', 'g'};
  auto c = read_texture(junk);
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().code, ErrorCode::kInput);
  EXPECT_NE(c.error().message.find("lamp.glb: /images/1: image '/images/1': cannot be read"), std::string::npos) << c.error().message;
  junk.mime_type = "image/gif";
  c = read_texture(junk);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("glTF allows image/png and image/jpeg"), std::string::npos) << c.error().message;
}

// A glass's tint: a number or [r, g, b]; on an opaque
// material a warning and no effect; out of range, located.
TEST(SceneJson, GlassTint) {
  auto r = parse_scene_json(R"({"objects": [
      {"name": "g", "mesh": "m.obj", "role": "transparent", "material": {"transparent": true, "tint": [0.5, 0.8, 1]}},
      {"name": "h", "mesh": "n.obj", "material": {"tint": 0.5}}],
      "lights": [{"type": "directional", "direction": [0, -1, 0]}]})", "scene.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->scene.objects[0].material.tint, (Vec3f{0.5f, 0.8f, 1.0f}));
  EXPECT_EQ(r->scene.objects[1].material.tint, (Vec3f{1, 1, 1}));
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_NE(r->warnings[0].find("/objects/1/material/tint: \"tint\" has no effect on an opaque material"), std::string::npos) << r->warnings[0];
  const std::string msg = error_of(R"({"objects": [{"name": "g", "mesh": "m.obj", "role": "transparent",
      "material": {"transparent": true, "tint": [0.5, 2, 1]}}]})");
  EXPECT_NE(msg.find("/objects/0/material/tint"), std::string::npos) << msg;
}

// Thin-walled glass: "thin": true on a transparent material
// makes the object a thin wall; on an opaque one it warns; on a receiver it
// is refused, as are absorption and dispersion, which need an inside.
TEST(SceneJson, ThinWalledGlass) {
  auto r = parse_scene_json(R"({"objects": [
      {"name": "pane", "mesh": "m.obj", "role": "transparent", "material": {"transparent": true, "thin": true, "tint": [0.5, 0.8, 1]}},
      {"name": "ball", "mesh": "n.obj", "role": "transparent", "material": {"transparent": true}},
      {"name": "wall", "mesh": "w.obj", "material": {"thin": true}}],
      "lights": [{"type": "directional", "direction": [0, -1, 0]}]})", "scene.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->scene.objects[0].role, Role::kThin);
  EXPECT_EQ(r->scene.objects[1].role, Role::kTransparent);
  EXPECT_EQ(r->scene.objects[2].role, Role::kReceiver);
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_NE(r->warnings[0].find("/objects/2/material/thin: \"thin\" has no effect on an opaque material"), std::string::npos) << r->warnings[0];
  std::string msg = error_of(R"({"objects": [{"name": "g", "mesh": "m.obj", "role": "both",
      "material": {"transparent": true, "thin": true}}]})");
  EXPECT_NE(msg.find("/objects/0/material/thin: a thin-walled material needs \"role\": \"transparent\""), std::string::npos) << msg;
  msg = error_of(R"({"objects": [{"name": "g", "mesh": "m.obj", "role": "transparent",
      "material": {"transparent": true, "thin": true, "absorption": 0.5}}]})");
  EXPECT_NE(msg.find("/objects/0/material/absorption: a thin-walled object has no inside to absorb in; use tint"), std::string::npos) << msg;
}

// Media: the medium box, scattering water and milky glass, with
// their phase functions; bad values are located.
TEST(SceneJson, MediaAndScattering) {
  auto r = parse_scene_json(R"({"objects": [{"name": "g", "mesh": "m.obj", "role": "transparent",
      "material": {"transparent": true, "scattering": 0.5, "phase": "schlick", "anisotropy": 0.3}}],
      "lights": [{"type": "directional", "direction": [0, -1, 0]}],
      "water": {"level": 1, "scattering": [0.1, 0.2, 0.3]},
      "medium": {"extent": [-1, 0, -1, 1, 2, 1], "scattering": 0.4, "absorption": 0.1}})",
                            "s.json");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const SceneDesc& s = r->scene;
  ASSERT_TRUE(s.medium.has_value());
  EXPECT_EQ(s.medium->extent[4], 2.0f);
  EXPECT_EQ(s.medium->scattering.coefficient, (Vec3f{0.4f, 0.4f, 0.4f}));
  EXPECT_EQ(s.medium->absorption, (Vec3f{0.1f, 0.1f, 0.1f}));
  EXPECT_EQ(s.medium->scattering.phase, Phase::kIsotropic);
  EXPECT_EQ(s.water->scattering.coefficient, (Vec3f{0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(s.objects[0].material.scattering.phase, Phase::kSchlick);
  EXPECT_EQ(s.objects[0].material.scattering.anisotropy, 0.3f);
  EXPECT_TRUE(scene_scatters(s));
  EXPECT_TRUE(r->warnings.empty());

  auto plain = parse_scene_json(kMinimal, "s.json");
  ASSERT_TRUE(plain.ok());
  EXPECT_FALSE(scene_scatters(plain->scene));

  const std::string obj = R"({"objects": [{"name": "a", "mesh": "m.obj"}], )";
  EXPECT_NE(error_of(obj + R"("medium": {"scattering": 1}})").find("/medium: missing required field \"extent\""),
            std::string::npos);
  EXPECT_NE(error_of(obj + R"("medium": {"extent": [0, 0, 0, 1, 0, 1]}})").find("/medium/extent: must be finite"),
            std::string::npos);
  EXPECT_NE(error_of(obj + R"("medium": {"extent": [0, 0, 0, 1, 1, 1], "scattering": -1}})")
                .find("/medium/scattering: each component must be in [0, 10^6]"),
            std::string::npos);
  EXPECT_NE(error_of(obj + R"("medium": {"extent": [0, 0, 0, 1, 1, 1], "scattering": 1, "phase": "mie"}})")
                .find("/medium/phase: expected \"isotropic\" or \"schlick\""),
            std::string::npos);
  EXPECT_NE(error_of(obj + R"("medium": {"extent": [0, 0, 0, 1, 1, 1], "scattering": 1, "phase": "schlick", "anisotropy": 1}})")
                .find("/medium/anisotropy: must be in (-1, 1)"),
            std::string::npos);
  EXPECT_NE(error_of(obj + R"("medium": {"extent": [0, 0, 0, 1, 1, 1], "scattering": 1, "anisotropy": 0.5}})")
                .find("/medium/anisotropy: needs \"phase\": \"schlick\""),
            std::string::npos);
  EXPECT_NE(error_of(R"({"objects": [{"name": "a", "mesh": "m.obj", "material": {"scattering": 1}}]})")
                .find("/objects/0/material/scattering: only a transparent material scatters inside"),
            std::string::npos);
  auto warn = parse_scene_json(obj + R"("medium": {"extent": [0, 0, 0, 1, 1, 1], "phase": "schlick"}})", "s.json");
  ASSERT_TRUE(warn.ok()) << warn.error().message;
  ASSERT_EQ(warn->warnings.size(), 2u);  // and "no lights"
  EXPECT_NE(warn->warnings[0].find("/medium: \"phase\" and \"anisotropy\" have no effect without \"scattering\""),
            std::string::npos) << warn->warnings[0];
}

}  // namespace
}  // namespace caustix::bake
