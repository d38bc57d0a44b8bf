// A corpus of glTF files shaped like what artists export, each
// baked through bake_scene() as `caustix-bake file.glb` does: what must
// bake, with which warnings, and what must be refused, naming the glTF node
// or the extension. The files are written here (tests/gltf_fixture.h) the
// way exporters write them: seams split and recomputed (Blender's UV
// sphere), integer positions under tiny node scales (KHR_mesh_quantization),
// centimetre and kilometre units, deep hierarchies, Draco, strips and fans,
// materials shared by many nodes, required extensions.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "caustix/bake/bake.h"
#include "caustix/bake/mesh_compress.h"
#include "caustix/formats/scene.h"
#include "gltf_fixture.h"

namespace caustix {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfBuilder;
using test::SplitCube;

constexpr double kPi = 3.14159265358979323846;

// A UV sphere as Blender's exporter writes it: a ring of `seg` + 1 columns
// whose last column repeats the first (the UV seam) and poles repeated per
// column, every position computed in double from its own angle -- so the
// seam's copies differ in the last bits (sin 2 pi is -2.4e-16, not 0) --
// plus `jitter` (relative) as an exporter's float rounding adds.
struct SeamSphere {
  std::vector<std::array<float, 3>> positions, normals;
  std::vector<std::uint32_t> indices;
  SeamSphere(int seg, int rings, double radius, double jitter = 0) {
    for (int r = 0; r <= rings; ++r) {
      const double th = kPi * r / rings;
      for (int s = 0; s <= seg; ++s) {
        const double ph = 2 * kPi * s / seg;
        const std::array<double, 3> n{std::sin(th) * std::cos(ph), std::cos(th), -std::sin(th) * std::sin(ph)};
        const double wobble = 1 + jitter * (((r * 7 + s * 13) % 5) - 2) / 2.0;
        positions.push_back({static_cast<float>(radius * n[0] * wobble), static_cast<float>(radius * n[1] * wobble),
                             static_cast<float>(radius * n[2] * wobble)});
        normals.push_back({static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2])});
      }
    }
    const auto at = [&](int r, int s) { return static_cast<std::uint32_t>(r * (seg + 1) + s); };
    for (int r = 0; r < rings; ++r) {
      for (int s = 0; s < seg; ++s) {
        // Outward: counter-clockwise seen from outside.
        if (r > 0) indices.insert(indices.end(), {at(r, s), at(r + 1, s), at(r, s + 1)});
        if (r + 1 < rings) indices.insert(indices.end(), {at(r, s + 1), at(r + 1, s), at(r + 1, s + 1)});
      }
    }
  }
};

const json kGlass{{"name", "glass"},
                  {"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
                  {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}, {"KHR_materials_volume", {{"thicknessFactor", 0.1}}}}}};

// A floor, a sun and whatever the case adds: what a user's export holds.
GltfBuilder base_scene() {
  GltfBuilder g;
  g.use_extension("KHR_lights_punctual");
  const int floor_mat = g.material({{"name", "floor"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1.0}}, {"metallicFactor", 0.0}}}});
  const int quad = g.positions({{-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}});
  const int idx = g.indices({0, 2, 1, 0, 3, 2});
  const int mesh = g.mesh(json::array({{{"attributes", {{"POSITION", quad}}}, {"indices", idx}, {"material", floor_mat}}}), "floor");
  g.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "directional"}, {"name", "sun"}, {"intensity", 683.0}}});
  const double s = std::sqrt(0.5);
  g.scene({g.node({{"name", "Floor"}, {"mesh", mesh}}),
           g.node({{"name", "Sun"}, {"rotation", {-s, 0.0, 0.0, s}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}})});
  return g;
}

void use_transmission(GltfBuilder& g) {
  g.use_extension("KHR_materials_transmission");
  g.use_extension("KHR_materials_volume");
}
int add_root(GltfBuilder& g, const json& node) {
  const int n = g.node(node);
  g.doc["scenes"][0]["nodes"].push_back(n);
  return n;
}
int mesh_of(GltfBuilder& g, const std::vector<std::array<float, 3>>& p, const std::vector<std::array<float, 3>>& n,
            const std::vector<std::uint32_t>& i, int material) {
  json attrs{{"POSITION", g.positions(p)}};
  if (!n.empty()) attrs["NORMAL"] = g.normals(n);
  json prim{{"attributes", attrs}, {"indices", g.indices(i)}};
  if (material >= 0) prim["material"] = material;
  return g.mesh(json::array({prim}));
}
int glass_cube(GltfBuilder& g, float half = 0.25f) {
  use_transmission(g);
  const SplitCube c(half);
  return mesh_of(g, c.positions, c.normals, c.indices, g.material(kGlass));
}

// The floor with TEXCOORD_0 and a base-colour texture: the default
// scene's 256 x 256 tile PNG embedded in a buffer view, or an external
// file that is not there.
void textured_floor(GltfBuilder& g, bool missing_file) {
  g.use_extension("KHR_texture_transform", true);
  json& prim = g.doc["meshes"][0]["primitives"][0];
  prim["attributes"]["TEXCOORD_0"] = g.accessor(std::vector<float>{0, 0, 1, 0, 1, 1, 0, 1}, 5126, "VEC2", 4);
  if (missing_file) {
    g.doc["images"] = json::array({{{"uri", "missing%20tiles.png"}}});
  } else {
    std::ifstream in(std::string(CAUSTIX_SOURCE_DIR) + "/assets/textures/pool_tiles.png", std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    g.doc["images"] = json::array({{{"bufferView", g.view(bytes.data(), bytes.size())}, {"mimeType", "image/png"}}});
  }
  g.doc["samplers"] = json::array({{{"wrapS", 33648}, {"wrapT", 33071}}});
  g.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
  g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {
      {"index", 0}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.25, 0.5}}, {"rotation", 1.5707963267948966}, {"scale", {4, 2}}}}}}};
}

struct Case {
  const char* name;
  std::function<void(GltfBuilder&)> build;
  std::vector<std::string> expect;  // substrings of the warnings, or of the error
  bool bakes = true;
  std::function<void(const bake::BakeResult&)> check = nullptr;
};

class GltfCorpus : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("caustix_gltf_corpus_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

const Object* named(const SceneDesc& s, const std::string& name) {
  for (const Object& o : s.objects) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

TEST_F(GltfCorpus, ExportsBakeOrAreRefusedByNode) {
  const std::vector<Case> cases{
      {"seam_sphere_glass",  // Blender's UV sphere: refused as open (286 boundary edges) before snapping; baked thin-walled if not welded
       [](GltfBuilder& g) {
         use_transmission(g);
         const SeamSphere s(24, 12, 0.3);
         add_root(g, {{"name", "Ball"}, {"mesh", mesh_of(g, s.positions, s.normals, s.indices, g.material(kGlass))}, {"translation", {0.0, 1.0, 0.0}}});
       },
       {}, true,
       [](const bake::BakeResult& r) {
         ASSERT_TRUE(named(r.scene, "Ball"));
         EXPECT_EQ(named(r.scene, "Ball")->role, Role::kTransparent);
         ASSERT_EQ(r.transport.size(), 1u);
       }},
      {"seam_sphere_float_noise",  // seam copies 3e-7 apart (relative), as float exports round them
       [](GltfBuilder& g) {
         use_transmission(g);
         SeamSphere s(16, 8, 0.3);
         for (int r = 0; r <= 8; ++r) s.positions[static_cast<std::size_t>(r * 17 + 16)][0] *= 1.0000003f;
         add_root(g, {{"name", "Ball"}, {"mesh", mesh_of(g, s.positions, s.normals, s.indices, g.material(kGlass))}, {"translation", {0.0, 1.0, 0.0}}});
       },
       {}},
      {"seam_sphere_receiver",
       [](GltfBuilder& g) {
         const SeamSphere s(16, 8, 0.3);
         add_root(g, {{"name", "Ball"}, {"mesh", mesh_of(g, s.positions, s.normals, s.indices, -1)}, {"translation", {0.0, 0.3, 0.0}}});
       },
       {}},
      {"hard_edged_glass_cube",
       [](GltfBuilder& g) { add_root(g, {{"name", "Block"}, {"mesh", glass_cube(g)}, {"translation", {0.0, 0.5, 0.0}}}); },
       {}},
      {"quantized_under_tiny_scale",  // Khronos's quantized Avocado: integer positions, node scale 3.8e-6
       [](GltfBuilder& g) {
         g.use_extension("KHR_mesh_quantization", true);
         const SplitCube c;
         std::vector<std::uint16_t> pos;
         for (const auto& p : c.positions) {
           for (float v : p) pos.push_back(static_cast<std::uint16_t>(std::lround((v + 0.5f) * 16000)));
           pos.push_back(0);
         }
         const int pv = g.view(pos.data(), pos.size() * 2);
         g.doc["bufferViews"][pv]["byteStride"] = 8;
         g.doc["accessors"].push_back({{"bufferView", pv}, {"componentType", 5123}, {"count", 24}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {16000, 16000, 16000}}});
         const int pa = static_cast<int>(g.doc["accessors"].size()) - 1;
         const int mesh = g.mesh(json::array({{{"attributes", {{"POSITION", pa}}}, {"indices", g.indices(c.indices)}}}));
         add_root(g, {{"name", "Avocado"}, {"mesh", mesh}, {"scale", {3.8e-6, 3.8e-6, 3.8e-6}}});
       },
       {}, true,
       [](const bake::BakeResult& r) {
         // The Draco error bound in metres in the world (sub-millimetre),
         // not in the file's integer units.
         ASSERT_EQ(r.meshes.size(), 2u);
         EXPECT_GT(r.meshes[1].max_position_error, 0.05);
         EXPECT_LT(r.meshes[1].max_world_error, 1e-5);
       }},
      {"centimetre_units_nested",  // ToyCar: a 0.01 scale above a 0.01 scale
       [](GltfBuilder& g) {
         const SplitCube c(50.0f);
         const int child = g.node({{"name", "Body"}, {"mesh", mesh_of(g, c.positions, c.normals, c.indices, -1)}, {"scale", {0.01, 0.01, 0.01}}});
         add_root(g, {{"name", "Car"}, {"children", {child}}, {"scale", {0.01, 0.01, 0.01}}, {"translation", {0.0, 0.005, 0.0}}});
       },
       {}},
      {"kilometre_scale",
       [](GltfBuilder& g) {
         const SplitCube c(0.0005f);
         add_root(g, {{"name", "Hill"}, {"mesh", mesh_of(g, c.positions, c.normals, c.indices, -1)}, {"scale", {1000.0, 1000.0, 1000.0}}});
       },
       {}},
      {"deep_hierarchy",
       [](GltfBuilder& g) {
         const SplitCube c(0.2f);
         int n = g.node({{"name", "Leaf"}, {"mesh", mesh_of(g, c.positions, c.normals, c.indices, -1)}, {"translation", {0.5, 0.0, 0.0}}});
         for (int d = 0; d < 6; ++d) {
           n = g.node({{"name", "Group" + std::to_string(d)}, {"children", {n}}, {"rotation", {0.0, std::sin(0.1), 0.0, std::cos(0.1)}}, {"translation", {0.0, 0.05, 0.0}}});
         }
         add_root(g, {{"name", "Root"}, {"children", {n}}});
       },
       {}, true,
       [](const bake::BakeResult& r) {
         const Object* leaf = named(r.scene, "Leaf");
         ASSERT_TRUE(leaf);
         // Six turns of 0.2 rad about y, six lifts of 5 cm: the leaf's origin.
         double x = 0.5, z = 0;
         for (int d = 0; d < 6; ++d) {
           const double nx = std::cos(0.2) * x + std::sin(0.2) * z, nz = -std::sin(0.2) * x + std::cos(0.2) * z;
           x = nx, z = nz;
         }
         EXPECT_NEAR(leaf->transform[12], x, 1e-5);
         EXPECT_NEAR(leaf->transform[13], 0.3, 1e-5);
         EXPECT_NEAR(leaf->transform[14], z, 1e-5);
       }},
      {"draco_glass",
       [](GltfBuilder& g) {
         use_transmission(g);
         g.use_extension("KHR_draco_mesh_compression", true);
         const SplitCube c(0.25f);
         bake::DracoOptions opt;
         opt.position_bits = 14;
         const auto stream = bake::encode_draco(c.triangle_mesh(), opt);
         const int mesh = g.mesh(json::array({g.draco_primitive(*stream, 24, 12, 0.25f, g.material(kGlass))}));
         add_root(g, {{"name", "Gem"}, {"mesh", mesh}, {"translation", {0.0, 0.6, 0.0}}});
       },
       {}},
      {"strips_and_fans",
       [](GltfBuilder& g) {
         const int p = g.positions({{0, 0.1f, 0}, {1, 0.1f, 0}, {0, 0.1f, 1}, {1, 0.1f, 1}, {0.5f, 0.1f, 1.5f}});
         const int strip = g.indices({0, 2, 1, 3});
         const int fan = g.indices({2, 4, 3});
         const int mesh = g.mesh(json::array({{{"attributes", {{"POSITION", p}}}, {"indices", strip}, {"mode", 5}}, {{"attributes", {{"POSITION", p}}}, {"indices", fan}, {"mode", 6}}}));
         add_root(g, {{"name", "Tarp"}, {"mesh", mesh}});
       },
       {}, true, [](const bake::BakeResult& r) { EXPECT_TRUE(named(r.scene, "Tarp/0") && named(r.scene, "Tarp/1")); }},
      {"mirrored_receiver",  // a negative scale, as mirrored duplicates carry
       [](GltfBuilder& g) {
         const SplitCube c(0.2f);
         add_root(g, {{"name", "Left"}, {"mesh", mesh_of(g, c.positions, c.normals, c.indices, -1)}, {"scale", {-1.0, 1.0, 1.0}}, {"translation", {0.5, 0.2, 0.0}}});
       },
       {}},
      {"object_inside_glass",  // MosquitoInAmber's shape: a receiver inside a glass block
       [](GltfBuilder& g) {
         const SplitCube inner(0.05f);
         add_root(g, {{"name", "Amber"}, {"mesh", glass_cube(g, 0.3f)}, {"translation", {0.0, 0.5, 0.0}}});
         add_root(g, {{"name", "Insect"}, {"mesh", mesh_of(g, inner.positions, inner.normals, inner.indices, -1)}, {"translation", {0.0, 0.5, 0.0}}});
       },
       {"receiver 'Insect' lies inside transparent object 'Amber' (its bounding box): the light-transport tables never reach it, so the runtime lights that glass by caustic maps"}},
      {"texture_without_texcoords",  // a baseColorTexture but no TEXCOORD_0 on the primitive: the base colour is used
       [](GltfBuilder& g) {
         g.use_extension("KHR_texture_transform", true);
         g.doc["images"] = json::array({{{"uri", "tiles.png"}}});
         g.doc["textures"] = json::array({{{"source", 0}}});
         g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {4, 4}}}}}}};
       },
       {"no TEXCOORD_0 for its material's textures; drawn with its factors alone"}, true,
       [](const bake::BakeResult& r) { EXPECT_FALSE(named(r.scene, "Floor")->material.albedo_texture); }},
      {"textured_floor_embedded_png",  // a GLB's image in a buffer view, a repeating sampler, KHR_texture_transform required
       [](GltfBuilder& g) { textured_floor(g, false); },
       {}, true,
       [](const bake::BakeResult& r) {
         const Object* floor = named(r.scene, "Floor");
         ASSERT_TRUE(floor && floor->material.albedo_texture);
         const AlbedoTexture& t = *floor->material.albedo_texture;
         EXPECT_EQ(t.projection, TextureProjection::kUv);
         EXPECT_EQ(t.wrap_s, TextureWrap::kMirror);
         EXPECT_EQ(t.wrap_t, TextureWrap::kClamp);
         // offset (0.25, 0.5), rotation pi/2, scale (4, 2): rows (c sx, s sy, ox), (-s sx, c sy, oy).
         const std::array<float, 6> want{0, 2, 0.25f, -4, 0, 0.5f};
         for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(t.transform[k], want[k], 1e-6f) << k;
         ASSERT_EQ(r.scene.images.size(), 1u);
         EXPECT_EQ(r.scene.images[0].width, 256u);
         EXPECT_EQ(r.scene.images[0].rgb.size(), 256u * 256u * 3u);
         EXPECT_EQ(floor->material.albedo, (Vec3f{0.8f, 0.8f, 0.8f}));  // the factor still multiplies
       }},
      {"texture_file_missing",  // an external image that is not there: warned, the base colour is used
       [](GltfBuilder& g) { textured_floor(g, true); },
       {"cannot be read", "drawn with their base colour factor"}, true,
       [](const bake::BakeResult& r) {
         EXPECT_FALSE(named(r.scene, "Floor")->material.albedo_texture);
         EXPECT_TRUE(r.scene.images.empty());
       }},
      {"tinted_glass",  // KHR_materials_transmission: the base colour tints the transmitted light
       [](GltfBuilder& g) {
         json m = kGlass;
         m["pbrMetallicRoughness"]["baseColorFactor"] = {0.5, 0.8, 1.0, 1.0};
         use_transmission(g);
         const SplitCube c(0.2f);
         add_root(g, {{"name", "Bottle"}, {"mesh", mesh_of(g, c.positions, c.normals, c.indices, g.material(m))}, {"translation", {0.0, 0.5, 0.0}}});
       },
       {}, true,
       [](const bake::BakeResult& r) {
         const Object* bottle = named(r.scene, "Bottle");
         ASSERT_TRUE(bottle);
         EXPECT_EQ(bottle->role, Role::kTransparent);
         EXPECT_EQ(bottle->material.tint, (Vec3f{0.5f, 0.8f, 1.0f}));
         for (const auto& w : r.warnings) EXPECT_EQ(w.find("tint"), std::string::npos) << w;
       }},
      {"meshopt_required",
       [](GltfBuilder& g) { g.use_extension("EXT_meshopt_compression", true); },
       {"/extensionsRequired/0: the file requires extension EXT_meshopt_compression"}, false},
      {"metallic_transmission_is_metal",  // glTF: metallic blends the transmission away
       [](GltfBuilder& g) {
         json m = kGlass;
         m["pbrMetallicRoughness"]["metallicFactor"] = 1.0;
         use_transmission(g);
         const SplitCube c(0.2f);
         add_root(g, {{"name", "Chrome"}, {"mesh", mesh_of(g, c.positions, c.normals, c.indices, g.material(m))}, {"translation", {0.0, 0.5, 0.0}}});
       },
       {"is metallic (1.000000) and transmissive"}, true,
       [](const bake::BakeResult& r) { EXPECT_EQ(named(r.scene, "Chrome")->role, Role::kMirror); }},
      {"rough_transmission_named",  // TransmissionRoughnessTest
       [](GltfBuilder& g) {
         json m = kGlass;
         m["pbrMetallicRoughness"]["roughnessFactor"] = 0.5;
         use_transmission(g);
         const SplitCube c(0.2f);
         add_root(g, {{"name", "Frosted"}, {"mesh", mesh_of(g, c.positions, c.normals, c.indices, g.material(m))}, {"translation", {0.0, 0.5, 0.0}}});
       },
       {"roughnessFactor 0.500000 on a transmissive material is ignored"}},
      {"shared_material_warned_once",
       [](GltfBuilder& g) {
         g.doc["textures"] = json::array({{{"sampler", 0}}});
         g.doc["samplers"] = json::array({json::object()});
         g.doc["materials"][0]["occlusionTexture"] = {{"index", 0}};
         g.doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
         const SplitCube c(0.1f);
         const int mesh = mesh_of(g, c.positions, c.normals, c.indices, 0);
         for (int k = 0; k < 4; ++k) add_root(g, {{"name", "Post" + std::to_string(k)}, {"mesh", mesh}, {"translation", {k * 0.5, 0.1, 1.0}}});
       },
       {"metallicRoughnessTexture", "occlusionTexture"}, true,
       [](const bake::BakeResult& r) {
         std::size_t n = 0;
         for (const auto& w : r.warnings) n += w.find("occlusionTexture") != std::string::npos;
         EXPECT_EQ(n, 1u) << "one warning for the material, not one per node";
       }},
      {"two_scenes",
       [](GltfBuilder& g) {
         g.doc["scenes"].push_back({{"name", "Alternate"}, {"nodes", json::array({0})}});
         g.doc["scenes"][0]["name"] = "Main";
       },
       {"the file has 2 scenes; imported /scenes/0 ('Main') (the default scene)"}},
      {"spot_light_turned_down",  // a spot's cone about its node's -z, the node turned to face the floor
       [](GltfBuilder& g) {
         g.doc["extensions"]["KHR_lights_punctual"]["lights"].push_back(
             {{"type", "spot"}, {"name", "Lamp"}, {"intensity", 50.0}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}});
         const double s = std::sqrt(0.5);
         add_root(g, {{"name", "LampNode"}, {"translation", {0.0, 3.0, 0.0}}, {"rotation", {-s, 0.0, 0.0, s}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
       },
       {}, true,
       [](const bake::BakeResult& r) {
         ASSERT_EQ(r.scene.lights.size(), 2u);
         const Light& l = r.scene.lights[1];
         EXPECT_TRUE(l.spot);
         EXPECT_EQ(l.type, LightType::kPoint);
         EXPECT_NEAR(l.direction[1], -1.0, 1e-6);
         EXPECT_FLOAT_EQ(l.inner_cone, 0.2f);
         EXPECT_FLOAT_EQ(l.outer_cone, 0.5f);
       }},
      {"spot_cone_out_of_range",
       [](GltfBuilder& g) {
         g.doc["extensions"]["KHR_lights_punctual"]["lights"].push_back({{"type", "spot"}, {"spot", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.5}}}});
         add_root(g, {{"name", "Bad"}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
       },
       {"/extensions/KHR_lights_punctual/lights/1/spot/innerConeAngle: must be in [0, outerConeAngle)"}, false},
      {"no_lights",
       [](GltfBuilder& g) {
         g.doc["extensions"].erase("KHR_lights_punctual");
         g.doc["extensionsUsed"] = json::array();
         g.doc["nodes"][1].erase("extensions");
       },
       {"the file has no lights; lit by the default rig, a sun 55 degrees high over the camera's right shoulder"}},
      {"zero_scale_node",
       [](GltfBuilder& g) {
         const SplitCube c(0.2f);
         add_root(g, {{"name", "Flat"}, {"mesh", mesh_of(g, c.positions, c.normals, c.indices, -1)}, {"scale", {1.0, 0.0, 1.0}}});
       },
       {"/nodes/2 ('Flat')/transform: is degenerate"}, false},
      {"thin_walled_pane",  // GlassBrokenWindow: one quad, transmission without a volume: glTF's thin-walled glass
       [](GltfBuilder& g) {
         use_transmission(g);
         json m = kGlass;
         m["extensions"].erase("KHR_materials_volume");
         m["pbrMetallicRoughness"]["baseColorFactor"] = {0.6, 0.9, 0.7, 1.0};
         const int mesh = mesh_of(g, {{-0.5f, 0, 0}, {0.5f, 0, 0}, {0.5f, 1, 0}, {-0.5f, 1, 0}}, {}, {0, 1, 2, 0, 2, 3}, g.material(m));
         add_root(g, {{"name", "Pane"}, {"mesh", mesh}, {"translation", {0.0, 0.2, 0.0}}});
       },
       {}, true,
       [](const bake::BakeResult& r) {
         ASSERT_TRUE(named(r.scene, "Pane"));
         EXPECT_EQ(named(r.scene, "Pane")->role, Role::kThin);
         EXPECT_EQ(named(r.scene, "Pane")->material.tint, (Vec3f{0.6f, 0.9f, 0.7f}));
         EXPECT_TRUE(r.transport.empty()) << "thin-walled glass has no light-transport table";
         EXPECT_TRUE(named(r.scene, "Floor"));
       }},
      {"thin_walled_bulb",  // a closed sphere without KHR_materials_volume: a bulb's thin glass, not a ball lens
       [](GltfBuilder& g) {
         use_transmission(g);
         json m = kGlass;
         m["extensions"].erase("KHR_materials_volume");
         m["extensions"]["KHR_materials_dispersion"] = {{"dispersion", 1.0}};
         const SeamSphere s(24, 12, 0.3);
         add_root(g, {{"name", "Bulb"}, {"mesh", mesh_of(g, s.positions, s.normals, s.indices, g.material(m))}, {"translation", {0.0, 1.0, 0.0}}});
       },
       {"ignored KHR_materials_dispersion (a thin-walled material does not disperse",
        "transparent object 'Bulb' is a closed solid but thin-walled, so it does not bend or focus light; to make it solid "
        "glass give its glTF material KHR_materials_volume"},
       true,
       [](const bake::BakeResult& r) {
         ASSERT_TRUE(named(r.scene, "Bulb"));
         EXPECT_EQ(named(r.scene, "Bulb")->role, Role::kThin);
         EXPECT_EQ(named(r.scene, "Bulb")->material.dispersion, 0.0f);
         EXPECT_TRUE(r.transport.empty());
       }},
      {"inside_out_ball",  // a solid exported with reversed winding (outward normals): turned, not refused
       [](GltfBuilder& g) {
         use_transmission(g);
         g.doc["nodes"][0].erase("mesh");
         SeamSphere s(24, 12, 0.3);
         for (std::size_t t = 0; t + 2 < s.indices.size(); t += 3) std::swap(s.indices[t + 1], s.indices[t + 2]);
         add_root(g, {{"name", "Ball"}, {"mesh", mesh_of(g, s.positions, s.normals, s.indices, g.material(kGlass))}, {"translation", {0.0, 1.0, 0.0}}});
       },
       {"transparent object 'Ball' is wound inside out (signed volume -", "baked turned outside out (its triangles reversed)"},
       true,
       [](const bake::BakeResult& r) {
         ASSERT_TRUE(named(r.scene, "Ball"));
         EXPECT_EQ(named(r.scene, "Ball")->role, Role::kTransparent);
         EXPECT_FALSE(r.transport.empty()) << "a solid has its light-transport table";
       }},
      {"open_volume_shard",  // an open surface marked as a volume: baked thin-walled, naming it, not refused
       [](GltfBuilder& g) {
         use_transmission(g);
         g.doc["nodes"][0].erase("mesh");
         const int mesh = mesh_of(g, {{-0.5f, 0, 0}, {0.5f, 0, 0}, {0.5f, 1, 0}}, {}, {0, 1, 2}, g.material(kGlass));
         add_root(g, {{"name", "Shard"}, {"mesh", mesh}});
       },
       {"transparent object 'Shard' is not a closed, consistently wound mesh: it has 3 boundary edge(s) of holes",
        "it bounds no solid, so it is baked thin-walled"},
       true,
       [](const bake::BakeResult& r) {
         ASSERT_TRUE(named(r.scene, "Shard"));
         EXPECT_EQ(named(r.scene, "Shard")->role, Role::kThin);
       }},
  };
  ASSERT_GE(cases.size(), 20u);
  bake::BakeOptions opt;
  opt.transport.resolution = 6;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    GltfBuilder g = base_scene();
    c.build(g);
    const fs::path p = dir_ / (std::string(c.name) + ".glb");
    g.write_glb(p);
    auto baked = bake::bake_scene(p.string(), opt);
    std::string said;
    if (baked.ok()) {
      for (const auto& w : baked->warnings) said += w + "\n";
    } else {
      said = baked.error().message;
      EXPECT_EQ(baked.error().code, ErrorCode::kInput);
      EXPECT_NE(said.find(p.string()), std::string::npos) << said;
    }
    ASSERT_EQ(baked.ok(), c.bakes) << said;
    for (const auto& e : c.expect) EXPECT_NE(said.find(e), std::string::npos) << "'" << e << "' not in:\n" << said;
    if (baked.ok() && c.check) c.check(*baked);
  }
}

}  // namespace
}  // namespace caustix
