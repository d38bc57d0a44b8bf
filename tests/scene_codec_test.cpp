// Scene chunks: every field survives encode -> decode; malformed payloads are
// refused with the chunk named.

#include <gtest/gtest.h>

#include <functional>

#include <cmath>
#include <cstring>
#include <limits>

#include "caustix/formats/light_transport.h"
#include "caustix/formats/spectrum.h"
#include "caustix/formats/scene.h"
#include "cxb_test_util.h"

namespace caustix {
namespace {

SceneDesc full_scene() {
  SceneDesc s;
  s.name = "codec test";
  MeshInfo m;
  m.source = "meshes/thing.obj";
  m.vertex_count = 8;
  m.triangle_count = 12;
  m.position_bits = 14;
  m.normal_bits = 10;
  m.bounds_min = {-1, -2, -3};
  m.bounds_max = {1, 2, 3};
  s.meshes = {m};
  Object o;
  o.name = "glass";
  o.role = Role::kReceiver;
  o.material = Material{{0.1f, 0.2f, 0.3f}, true, 1.5f};
  o.transform = {2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 4, 0, 5, 6, 7, 1};  // non-uniform: fine for a receiver
  s.objects = {o};
  Light sun;
  sun.name = "sun";
  sun.direction = {0.6f, -0.8f, 0};
  sun.irradiance = 3.5f;
  sun.color = {1, 0.9f, 0.8f};
  Light bulb;
  bulb.type = LightType::kPoint;
  bulb.position = {1, 2, 3};
  bulb.intensity = 42;
  s.lights = {sun, bulb};
  Water w;
  w.level = 2;
  w.ior = 1.33f;
  w.absorption = {0.1f, 0.2f, 0.3f};
  w.cells = {64, 32};
  w.extent = {-1, -2, 3, 4};
  w.waves = {Wave{0.1f, 1.0f, {1, 0}, 0.5f, 0.25f}, Wave{0.05f, 0.3f, {0, 1}, 0.2f, 1.0f}};
  w.scattering = {{0.1f, 0.2f, 0.3f}, Phase::kSchlick, 0.5f};
  s.water = w;
  Medium fog;
  fog.extent = {-1, 0, -2, 1, 3, 2};
  fog.absorption = {0.01f, 0.02f, 0.03f};
  fog.scattering = {{0.4f, 0.5f, 0.6f}, Phase::kIsotropic, 0.0f};
  s.medium = fog;
  s.objects[0].material.scattering = {{2, 2, 2}, Phase::kSchlick, -0.25f};
  Camera c;
  c.position = {1, 2, 3};
  c.fov_y_deg = 60;
  s.camera = c;
  s.render = RenderDefaults{"fast", 256, 128, 3, 96, 48, 300, 200, 3, 5000, 384, 0};
  return s;
}

Result<DecodedScene> decode(const std::vector<std::uint8_t>& b) {
  auto c = cxb::read_container(b.data(), b.size());
  if (!c) return c.error();
  // decode_scene keeps spans into b, which outlives the result here.
  return decode_scene(*c);
}

TEST(SceneCodec, EveryFieldSurvives) {
  const SceneDesc s = full_scene();
  ASSERT_FALSE(validate_scene(s).has_value());
  const auto b = encode_scene(s, {{1, 2, 3, 4}});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  const SceneDesc& r = d->scene;
  EXPECT_EQ(r.name, s.name);
  ASSERT_EQ(r.meshes.size(), 1u);
  EXPECT_EQ(r.meshes[0].source, "meshes/thing.obj");
  EXPECT_EQ(r.meshes[0].triangle_count, 12u);
  EXPECT_EQ(r.meshes[0].bounds_max, s.meshes[0].bounds_max);
  ASSERT_EQ(r.objects.size(), 1u);
  EXPECT_EQ(r.objects[0].name, "glass");
  EXPECT_EQ(r.objects[0].role, Role::kReceiver);
  EXPECT_EQ(r.objects[0].material.albedo, s.objects[0].material.albedo);
  EXPECT_TRUE(r.objects[0].material.transparent);
  EXPECT_EQ(r.objects[0].material.ior, 1.5f);
  EXPECT_EQ(r.objects[0].transform, s.objects[0].transform);
  ASSERT_EQ(r.lights.size(), 2u);
  EXPECT_EQ(r.lights[0].direction, s.lights[0].direction);
  EXPECT_EQ(r.lights[0].irradiance, 3.5f);
  EXPECT_EQ(r.lights[0].color, s.lights[0].color);
  EXPECT_EQ(r.lights[1].type, LightType::kPoint);
  EXPECT_EQ(r.lights[1].position, s.lights[1].position);
  EXPECT_EQ(r.lights[1].intensity, 42.0f);
  ASSERT_TRUE(r.water.has_value());
  EXPECT_EQ(r.water->cells, s.water->cells);
  EXPECT_EQ(r.water->extent, s.water->extent);
  EXPECT_EQ(r.water->absorption, s.water->absorption);
  ASSERT_EQ(r.water->waves.size(), 2u);
  EXPECT_EQ(r.water->waves[1].wavelength, 0.3f);
  EXPECT_EQ(r.water->waves[1].phase, 1.0f);
  EXPECT_EQ(r.water->scattering.coefficient, s.water->scattering.coefficient);
  EXPECT_EQ(r.water->scattering.phase, Phase::kSchlick);
  EXPECT_EQ(r.water->scattering.anisotropy, 0.5f);
  ASSERT_TRUE(r.medium.has_value());
  EXPECT_EQ(r.medium->extent, s.medium->extent);
  EXPECT_EQ(r.medium->absorption, s.medium->absorption);
  EXPECT_EQ(r.medium->scattering.coefficient, s.medium->scattering.coefficient);
  EXPECT_EQ(r.objects[0].material.scattering.coefficient, s.objects[0].material.scattering.coefficient);
  EXPECT_EQ(r.objects[0].material.scattering.anisotropy, -0.25f);
  ASSERT_TRUE(r.camera.has_value());
  EXPECT_EQ(r.camera->fov_y_deg, 60.0f);
  ASSERT_TRUE(r.render.has_value());
  EXPECT_EQ(r.render->preset, "fast");
  EXPECT_EQ(r.render->caustics_map_size, 256u);
  EXPECT_EQ(r.render->glass_map_size, 128u);
  EXPECT_EQ(r.render->glass_planes, 3u);
  EXPECT_EQ(r.render->volume_photons, 96u);
  EXPECT_EQ(r.render->volume_grid, 48u);
  EXPECT_EQ(r.render->cmap_photons, 300u);
  EXPECT_EQ(r.render->cmap_map_size, 200u);
  EXPECT_EQ(r.render->cmap_adaptive_levels, 3u);
  EXPECT_EQ(r.render->water_texture, 384u);
  EXPECT_EQ(r.render->cmap_photon_budget, 5000u);
  EXPECT_EQ(r.render->glass_spectral_coarse, 0u);
  ASSERT_EQ(d->draco_meshes.size(), 1u);
  EXPECT_EQ(d->draco_meshes[0].size(), 4u);
}

TEST(SceneCodec, OptionalPartsAbsent) {
  SceneDesc s = full_scene();
  s.water.reset();
  s.camera.reset();
  s.render.reset();
  s.medium.reset();
  s.objects[0].material.scattering = {};
  const auto b = encode_scene(s, {{0}});
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  EXPECT_TRUE(c->find(cxb::kTagMedia).empty()) << "a scene without media pays nothing for them";
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_FALSE(d->scene.medium.has_value());
  EXPECT_FALSE(d->scene.water.has_value());
  EXPECT_FALSE(d->scene.camera.has_value());
  EXPECT_FALSE(d->scene.render.has_value());
}

TEST(SceneCodec, MeshChunkCountMustMatch) {
  const auto b = encode_scene(full_scene(), {});
  auto d = decode(b);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("'MESH'"), std::string::npos) << d.error().message;
}

TEST(SceneCodec, BadEnumAndNaNAreRefusedWithThePlace) {
  auto b = encode_scene(full_scene(), {{0}});
  // Find the OBJS payload; its role byte follows count, name and mesh index.
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  const std::size_t objs = c->find(cxb::kTagObjects).at(0);
  const std::size_t off = c->chunks()[objs].offset;
  const std::size_t role = off + 4 + 4 + 5 + 4;  // count, name length, "glass", mesh index
  auto bad = b;
  bad[role] = 9;
  test::reseal_payload(bad, objs);
  auto d = decode(bad);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("'OBJS'"), std::string::npos) << d.error().message;
  EXPECT_NE(d.error().message.find("role"), std::string::npos) << d.error().message;

  bad = b;
  const float nan = std::nanf("");
  std::memcpy(bad.data() + role + 4 + 12, &nan, 4);  // ior
  test::reseal_payload(bad, objs);
  d = decode(bad);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/objects/0/material/ior"), std::string::npos) << d.error().message;
}

TEST(SceneCodec, TruncatedPayloadNamesTheField) {
  auto b = encode_scene(full_scene(), {{0}});
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  // Rebuild the container with the CAMR chunk cut short by 4 bytes.
  cxb::ContainerWriter w;
  for (std::size_t i = 0; i < c->chunks().size(); ++i) {
    auto p = c->payload(i);
    std::vector<std::uint8_t> bytes(p.begin(), p.end());
    if (c->chunks()[i].tag == cxb::kTagCamera) bytes.resize(bytes.size() - 4);
    w.add_chunk(c->chunks()[i].tag, c->chunks()[i].flags, bytes);
  }
  const auto cut = w.finish();
  auto d = decode(cut);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("chunk 'CAMR' payload offset 44: truncated while reading camera"),
            std::string::npos) << d.error().message;
}

TEST(SceneCodec, DuplicateSingletonChunk) {
  auto b = encode_scene(full_scene(), {{0}});
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  cxb::ContainerWriter w;
  for (std::size_t i = 0; i < c->chunks().size(); ++i) {
    auto p = c->payload(i);
    w.add_chunk(c->chunks()[i].tag, c->chunks()[i].flags, {p.begin(), p.end()});
    if (c->chunks()[i].tag == cxb::kTagLights) w.add_chunk(c->chunks()[i].tag, c->chunks()[i].flags, {p.begin(), p.end()});
  }
  const auto dup = w.finish();
  auto d = decode(dup);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("'LGHT' appears 2 times"), std::string::npos) << d.error().message;
}

TEST(SceneValidate, RulesNameTheField) {
  SceneDesc s = full_scene();
  s.water->cells = {1000000000u, 4};
  auto issue = validate_scene(s);
  ASSERT_TRUE(issue.has_value());
  EXPECT_EQ(issue->pointer, "/water/grid/cells");
  s = full_scene();
  s.lights[0].direction = {0, 0, 0};
  issue = validate_scene(s);
  ASSERT_TRUE(issue.has_value());
  EXPECT_EQ(issue->pointer, "/lights/0/direction");
  s = full_scene();
  s.objects.push_back(s.objects[0]);
  issue = validate_scene(s);
  ASSERT_TRUE(issue.has_value());
  EXPECT_EQ(issue->pointer, "/objects/1/name");
  s = full_scene();
  s.render->caustics_map_size = 0;
  issue = validate_scene(s);
  ASSERT_TRUE(issue.has_value());
  EXPECT_EQ(issue->pointer, "/render/caustics_map_size");
  s = full_scene();
  s.render->glass_planes = 17;
  issue = validate_scene(s);
  ASSERT_TRUE(issue.has_value());
  EXPECT_EQ(issue->pointer, "/render/glass_planes");
}

// A hostile RNDR payload: an out-of-range value is refused, naming the field.
TEST(SceneCodec, RenderDefaultsAreValidated) {
  SceneDesc s = full_scene();
  s.render->glass_map_size = 9000;  // encode does not validate; decode must
  auto d = decode(encode_scene(s, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/render/glass_map_size"), std::string::npos) << d.error().message;
  s = full_scene();
  s.render->volume_grid = 1;
  d = decode(encode_scene(s, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/render/volume_grid"), std::string::npos) << d.error().message;
  s = full_scene();
  s.render->cmap_adaptive_levels = 9;
  d = decode(encode_scene(s, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/render/cmap_adaptive_levels"), std::string::npos) << d.error().message;

  s = full_scene();
  s.render->water_texture = 8;  // neither 0 nor 16..8192
  d = decode(encode_scene(s, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/render/water_texture"), std::string::npos) << d.error().message;
  s = full_scene();
  s.render->glass_spectral_coarse = 2;
  d = decode(encode_scene(s, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/render/glass_spectral_coarse"), std::string::npos) << d.error().message;

  // A chunk written by an older baker ends after the glass planes (or
  // after the media's pair, the caustic maps' four or the water textures'
  // limit, as the fields were added):
  // what follows keeps its defaults. Any other length is refused.
  for (const std::size_t cut : {32u, 24u, 8u, 4u, 12u, 2u}) {
    const auto full = encode_scene(full_scene(), {{0}});
    auto c = cxb::read_container(full.data(), full.size());
    ASSERT_TRUE(c.ok());
    cxb::ContainerWriter w;
    for (std::size_t i = 0; i < c->chunks().size(); ++i) {
      const auto p = c->payload(i);
      std::vector<std::uint8_t> payload(p.begin(), p.end());
      if (c->chunks()[i].tag == cxb::kTagRender) payload.resize(payload.size() - cut);
      w.add_chunk(c->chunks()[i].tag, c->chunks()[i].flags, std::move(payload));
    }
    auto old = decode(w.finish());
    if (cut == 32 || cut == 24 || cut == 8 || cut == 4) {
      ASSERT_TRUE(old.ok()) << old.error().message;
      EXPECT_EQ(old->scene.render->volume_photons, cut == 32 ? RenderDefaults{}.volume_photons : 96u);
      EXPECT_EQ(old->scene.render->volume_grid, cut == 32 ? RenderDefaults{}.volume_grid : 48u);
      EXPECT_EQ(old->scene.render->cmap_photons, cut <= 8 ? 300u : RenderDefaults{}.cmap_photons);
      EXPECT_EQ(old->scene.render->cmap_photon_budget, cut <= 8 ? 5000u : RenderDefaults{}.cmap_photon_budget);
      EXPECT_EQ(old->scene.render->water_texture, cut == 4 ? 384u : RenderDefaults{}.water_texture);
      EXPECT_EQ(old->scene.render->glass_spectral_coarse, RenderDefaults{}.glass_spectral_coarse);
      EXPECT_EQ(old->scene.render->glass_planes, 3u);
    } else {
      EXPECT_FALSE(old.ok()) << cut;
    }
  }
}

// A hostile MDIA payload: a phase that is not 1..2 and an anisotropy of 1
// are refused by name; an object index out of order is refused.
TEST(SceneCodec, MediaAreValidated) {
  SceneDesc s = full_scene();
  s.medium->scattering.phase = static_cast<Phase>(7);
  auto d = decode(encode_scene(s, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/medium/phase"), std::string::npos) << d.error().message;
  s = full_scene();
  s.objects[0].material.scattering.anisotropy = 1.0f;
  d = decode(encode_scene(s, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/objects/0/material/anisotropy"), std::string::npos) << d.error().message;

  // The object record's index (after flags, box record and water record)
  // pointed past the objects.
  auto b = encode_scene(full_scene(), {{0}});
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  const std::size_t mdia = c->find(cxb::kTagMedia).at(0);
  EXPECT_TRUE(c->chunks()[mdia].flags & cxb::kChunkRequired);
  const std::size_t index_at = c->chunks()[mdia].offset + 4 + (24 + 12 + 20) + 20 + 4;
  std::uint32_t one = 1;
  std::memcpy(b.data() + index_at, &one, 4);
  test::reseal_payload(b, mdia);
  d = decode(b);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("'MDIA'"), std::string::npos) << d.error().message;
  EXPECT_NE(d.error().message.find("scattering object index 1"), std::string::npos) << d.error().message;
}

// Mirrors: role 4 and the MIRR chunk survive; a reflectance out
// of [0, 1] is refused by name; a mirror whose record is missing (the
// count says none) is refused with the chunk named; a scene without
// mirrors has no MIRR chunk.
TEST(SceneCodec, MirrorsAreStoredAndValidated) {
  SceneDesc s = full_scene();
  Object m = s.objects[0];
  m.name = "ring";
  m.role = Role::kMirror;
  m.material = Material{};
  m.material.reflectance = {0.9f, 0.5f, 0.25f};
  s.objects.push_back(m);
  auto b = encode_scene(s, {{0}});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->scene.objects[1].role, Role::kMirror);
  EXPECT_EQ(d->scene.objects[1].material.reflectance, m.material.reflectance);

  SceneDesc bad = s;
  bad.objects[1].material.reflectance[1] = 1.5f;
  d = decode(encode_scene(bad, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/objects/1/material/reflectance"), std::string::npos) << d.error().message;

  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  const std::size_t mirr = c->find(cxb::kTagMirrors).at(0);
  EXPECT_TRUE(c->chunks()[mirr].flags & cxb::kChunkRequired);
  const std::uint32_t zero = 0;
  std::memcpy(b.data() + c->chunks()[mirr].offset, &zero, 4);
  test::reseal_payload(b, mirr);
  d = decode(b);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("'MIRR'"), std::string::npos) << d.error().message;

  auto plain = encode_scene(full_scene(), {{0}});
  auto pc = cxb::read_container(plain.data(), plain.size());
  ASSERT_TRUE(pc.ok());
  EXPECT_TRUE(pc->find(cxb::kTagMirrors).empty());
}

// Spot lights: the cone survives in the SPOT chunk (required: a
// reader that ignored it would light the whole scene); bad angles are
// refused by name; a record for a directional light is refused with the
// chunk named; a scene without spots has no SPOT chunk, so its bytes are
// unchanged.
TEST(SceneCodec, SpotConesAreStoredAndValidated) {
  SceneDesc s = full_scene();
  s.lights[1].spot = true;
  s.lights[1].direction = {0, -1, 0};
  s.lights[1].inner_cone = 0.2f;
  s.lights[1].outer_cone = 0.5f;
  auto b = encode_scene(s, {{0}});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_TRUE(d->scene.lights[1].spot);
  EXPECT_FALSE(d->scene.lights[0].spot);
  EXPECT_EQ(d->scene.lights[1].inner_cone, 0.2f);
  EXPECT_EQ(d->scene.lights[1].outer_cone, 0.5f);

  SceneDesc bad = s;
  bad.lights[1].inner_cone = 0.6f;
  d = decode(encode_scene(bad, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/lights/1/inner_cone_deg"), std::string::npos) << d.error().message;

  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  const std::size_t spot = c->find(cxb::kTagSpots).at(0);
  EXPECT_TRUE(c->chunks()[spot].flags & cxb::kChunkRequired);
  const std::uint32_t directional = 0;  // light 0 is the sun
  std::memcpy(b.data() + c->chunks()[spot].offset + 4, &directional, 4);
  test::reseal_payload(b, spot);
  d = decode(b);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("'SPOT'"), std::string::npos) << d.error().message;
  EXPECT_NE(d.error().message.find("not a point light"), std::string::npos) << d.error().message;

  auto plain = encode_scene(full_scene(), {{0}});
  auto pc = cxb::read_container(plain.data(), plain.size());
  ASSERT_TRUE(pc.ok());
  EXPECT_TRUE(pc->find(cxb::kTagSpots).empty());
}

// Albedo textures: the image and the receiver's mapping survive
// in the optional TEXR chunk; a scene without textures has none; a
// texture on a non-receiver, an image index out of range, a wrong texel
// count in the frame and a bad projection are refused by name.
TEST(SceneCodec, AlbedoTexturesAreStoredAndValidated) {
  SceneDesc s = full_scene();
  TextureImage im;
  im.source = "tiles.png";
  im.width = 3;
  im.height = 2;
  for (std::uint8_t i = 0; i < 18; ++i) im.rgb.push_back(static_cast<std::uint8_t>(i * 13));
  s.images = {im};
  AlbedoTexture t;
  t.projection = TextureProjection::kBox;
  t.wrap_s = TextureWrap::kMirror;
  t.wrap_t = TextureWrap::kClamp;
  t.transform = texture_transform({0.25f, 0.5f}, 0.3f, {2.0f, 3.0f});
  s.objects[0].material.albedo_texture = t;
  auto b = encode_scene(s, {{0}});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  ASSERT_EQ(d->scene.images.size(), 1u);
  EXPECT_EQ(d->scene.images[0].source, "tiles.png");
  EXPECT_EQ(d->scene.images[0].width, 3u);
  EXPECT_EQ(d->scene.images[0].rgb, im.rgb);
  ASSERT_TRUE(d->scene.objects[0].material.albedo_texture);
  const AlbedoTexture& r = *d->scene.objects[0].material.albedo_texture;
  EXPECT_EQ(r.projection, TextureProjection::kBox);
  EXPECT_EQ(r.wrap_s, TextureWrap::kMirror);
  EXPECT_EQ(r.wrap_t, TextureWrap::kClamp);
  EXPECT_EQ(r.transform, t.transform);

  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  const std::size_t texr = c->find(cxb::kTagTextures).at(0);
  EXPECT_FALSE(c->chunks()[texr].flags & cxb::kChunkRequired);  // a reader without it draws untextured

  SceneDesc glass = s;
  glass.objects[0].role = Role::kBoth;
  d = decode(encode_scene(glass, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/objects/0/material/albedo_texture: only a receiver"), std::string::npos) << d.error().message;

  SceneDesc out_of_range = s;
  out_of_range.objects[0].material.albedo_texture->image = 1;
  d = decode(encode_scene(out_of_range, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("image 1 is out of range"), std::string::npos) << d.error().message;

  // The frame must hold width x height x 3 bytes: say 4 x 2.
  std::vector<std::uint8_t> wide = b;
  auto wc = cxb::read_container(wide.data(), wide.size());
  const std::size_t at = wc->chunks()[texr].offset + 4 + 4 + im.source.size();  // count, string length, string
  const std::uint32_t four = 4;
  std::memcpy(wide.data() + at, &four, 4);
  test::reseal_payload(wide, texr);
  d = decode(wide);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("'TEXR'"), std::string::npos) << d.error().message;
  EXPECT_NE(d.error().message.find("image data does not hold 8 RGB texels"), std::string::npos) << d.error().message;

  SceneDesc bad = s;
  bad.objects[0].material.albedo_texture->projection = static_cast<TextureProjection>(7);
  d = decode(encode_scene(bad, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("albedo_texture/projection"), std::string::npos) << d.error().message;

  auto plain = encode_scene(full_scene(), {{0}});
  auto pc = cxb::read_container(plain.data(), plain.size());
  ASSERT_TRUE(pc.ok());
  EXPECT_TRUE(pc->find(cxb::kTagTextures).empty());
}

// Dispersion: the water's and a transparent object's survive in
// the DISP chunk (required: a reader that ignored it would render no
// colour fringes); out-of-range values are refused by name; a record for
// an object that is not transparent is refused with the chunk named; a
// scene without dispersion has no DISP chunk, so its bytes are unchanged.
// full_scene() with a dispersive lens (object 1, dispersion 0.9) and
// dispersive water, without media (a scene that scatters would need index
// grids too); `table` the smallest n_d table decode accepts for the lens
// (the codec does not look into it).
SceneDesc dispersive_scene(LightTransportTable& table) {
  SceneDesc s = full_scene();
  Object lens = s.objects[0];
  lens.name = "lens";
  lens.role = Role::kTransparent;
  lens.transform = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1};
  lens.material.dispersion = 0.9f;
  s.objects.push_back(lens);
  s.medium.reset();
  s.water->scattering = {};
  s.objects[0].material.scattering = {};
  s.objects[1].material.scattering = {};
  s.water->dispersion = 0.36f;
  table = LightTransportTable{};
  table.object = 1;
  table.ior = lens.material.ior;
  table.resolution = kMinTransportResolution;
  table.max_bounces = 1;
  table.vertex_count = 3;
  table.words.assign(std::size_t{3} * table.resolution * table.resolution * 4, 0);
  return s;
}

TEST(SceneCodec, DispersionIsStoredAndValidated) {
  LightTransportTable table;
  const SceneDesc s = dispersive_scene(table);
  const std::vector<LightTransportTable> tables{table};
  auto b = encode_scene(s, {{0}}, {}, {}, tables);
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->scene.objects[1].material.dispersion, 0.9f);
  EXPECT_EQ(d->scene.objects[0].material.dispersion, 0.0f);
  EXPECT_EQ(d->scene.water->dispersion, 0.36f);

  SceneDesc bad = s;
  bad.objects[1].material.dispersion = 25.0f;
  d = decode(encode_scene(bad, {{0}}, {}, {}, tables));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/objects/1/material/dispersion"), std::string::npos) << d.error().message;
  bad = s;
  bad.water->dispersion = std::numeric_limits<float>::quiet_NaN();
  d = decode(encode_scene(bad, {{0}}, {}, {}, tables));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/water/dispersion"), std::string::npos) << d.error().message;

  // The record's object index (after the water's f32 and the count) turned
  // to object 0, a receiver.
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  const std::size_t disp = c->find(cxb::kTagDispersion).at(0);
  EXPECT_TRUE(c->chunks()[disp].flags & cxb::kChunkRequired);
  const std::uint32_t zero = 0;
  std::memcpy(b.data() + c->chunks()[disp].offset + 8, &zero, 4);
  test::reseal_payload(b, disp);
  d = decode(b);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("'DISP'"), std::string::npos) << d.error().message;
  EXPECT_NE(d.error().message.find("not transparent"), std::string::npos) << d.error().message;

  auto plain = encode_scene(full_scene(), {{0}});
  auto pc = cxb::read_container(plain.data(), plain.size());
  ASSERT_TRUE(pc.ok());
  EXPECT_TRUE(pc->find(cxb::kTagDispersion).empty());
}

// A dispersive lens's tables at other wavelengths (LTTS): stored
// after its LTTB, required, each at the lens's index at its wavelength;
// refused out of order, at another index, for an object that does not
// disperse, outside 380..780 nm, or unlike the object's LTTB.
// Tints of transparent objects: stored in the required TINT
// chunk (a reader that skipped it would render tinted glass clear); a tint
// on an object that is not transparent and a component outside [0, 1] are
// refused by name; a scene without tints has no TINT chunk.
TEST(SceneCodec, TintsAreStoredAndValidated) {
  LightTransportTable table;
  SceneDesc s = dispersive_scene(table);
  s.objects[1].material.tint = {0.5f, 0.8f, 1.0f};
  auto b = encode_scene(s, {{0}}, {}, {}, {table});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->scene.objects[1].material.tint, (Vec3f{0.5f, 0.8f, 1.0f}));
  EXPECT_EQ(d->scene.objects[0].material.tint, (Vec3f{1, 1, 1}));
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  EXPECT_TRUE(c->chunks()[c->find(cxb::kTagTint).at(0)].flags & cxb::kChunkRequired);

  SceneDesc bad = s;
  bad.objects[1].material.tint[2] = 1.5f;
  d = decode(encode_scene(bad, {{0}}, {}, {}, {table}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/objects/1/material/tint"), std::string::npos) << d.error().message;
  bad = s;
  bad.objects[0].material.tint = {0.5f, 0.5f, 0.5f};  // object 0 is a receiver
  d = decode(encode_scene(bad, {{0}}, {}, {}, {table}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("not transparent"), std::string::npos) << d.error().message;

  LightTransportTable plain_table;
  auto plain = encode_scene(dispersive_scene(plain_table), {{0}}, {}, {}, {plain_table});
  auto pc = cxb::read_container(plain.data(), plain.size());
  ASSERT_TRUE(pc.ok());
  EXPECT_TRUE(pc->find(cxb::kTagTint).empty());
}

// Receivers' surfaces (glTF's metallic-roughness model): stored in the
// optional SURF chunk (shading only), every field surviving; a surface on
// an object that is not a receiver, or a value out of range or NaN, is
// refused by name; a scene without surfaces has no SURF chunk.
TEST(SceneCodec, SurfacesAreStoredAndValidated) {
  LightTransportTable table;
  SceneDesc s = dispersive_scene(table);
  ASSERT_EQ(s.objects[0].role, Role::kReceiver);
  s.objects[0].material.surface = Surface{0.25f, 0.75f, {2.0f, 0.5f, 0.0f}};
  auto b = encode_scene(s, {{0}}, {}, {}, {table});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->scene.objects[0].material.surface, (Surface{0.25f, 0.75f, {2.0f, 0.5f, 0.0f}}));
  EXPECT_FALSE(d->scene.objects[1].material.surface);
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  ASSERT_EQ(c->find(cxb::kTagSurfaces).size(), 1u);
  EXPECT_FALSE(c->chunks()[c->find(cxb::kTagSurfaces).at(0)].flags & cxb::kChunkRequired);

  for (const auto& [change, says] : std::vector<std::pair<std::function<void(Surface&)>, std::string>>{
           {[](Surface& f) { f.metallic = 1.5f; }, "/objects/0/material/metallic"},
           {[](Surface& f) { f.roughness = std::nanf(""); }, "/objects/0/material/roughness"},
           {[](Surface& f) { f.emissive[1] = -1.0f; }, "/objects/0/material/emissive"}}) {
    SceneDesc bad = s;
    change(*bad.objects[0].material.surface);
    d = decode(encode_scene(bad, {{0}}, {}, {}, {table}));
    ASSERT_FALSE(d.ok()) << says;
    EXPECT_NE(d.error().message.find(says), std::string::npos) << d.error().message;
  }
  SceneDesc bad = s;
  bad.objects[1].material.surface = Surface{};  // object 1 is glass
  d = decode(encode_scene(bad, {{0}}, {}, {}, {table}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("not a receiver"), std::string::npos) << d.error().message;

  LightTransportTable plain_table;
  auto plain = encode_scene(dispersive_scene(plain_table), {{0}}, {}, {}, {plain_table});
  auto pc = cxb::read_container(plain.data(), plain.size());
  ASSERT_TRUE(pc.ok());
  EXPECT_TRUE(pc->find(cxb::kTagSurfaces).empty());
}

// A receiver's maps and alpha (TEXM, optional): every field survives, the
// base colour's alpha plane too; maps on glass, a bad mode or factor, an
// image out of range and an alpha plane of the wrong size are refused by
// the field's name; a scene without maps has no TEXM.
TEST(SceneCodec, SurfaceMapsAreStoredAndValidated) {
  SceneDesc s = full_scene();
  TextureImage im;
  im.source = "leaf.png";
  im.width = 2;
  im.height = 2;
  im.rgb.assign(12, 200);
  im.alpha = {0, 255, 128, 7};
  TextureImage data = im;
  data.source = "orm.png";
  data.alpha.clear();
  s.images = {im, data};
  Material& m = s.objects[0].material;
  m.albedo_texture = AlbedoTexture{};
  SurfaceMaps& maps = m.maps.emplace();
  maps.metallic_roughness = MapTexture{1, TextureProjection::kUv, TextureWrap::kClamp, TextureWrap::kRepeat, texture_transform({0.5f, 0.0f}, 0.0f, {4.0f, 4.0f})};
  maps.occlusion = MapTexture{1, TextureProjection::kUv};
  maps.emissive = MapTexture{0, TextureProjection::kBox};
  maps.normal_scale = -0.5f;
  maps.occlusion_strength = 0.75f;
  maps.alpha_mode = AlphaMode::kMask;
  maps.alpha = 0.8f;
  maps.alpha_cutoff = 0.3f;
  auto b = encode_scene(s, {{0}});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->scene.images[0].alpha, im.alpha);
  EXPECT_TRUE(d->scene.images[1].alpha.empty());
  ASSERT_TRUE(d->scene.objects[0].material.maps);
  const SurfaceMaps& r = *d->scene.objects[0].material.maps;
  ASSERT_TRUE(r.metallic_roughness && r.occlusion && r.emissive);
  EXPECT_FALSE(r.normal);
  EXPECT_EQ(r.metallic_roughness->image, 1u);
  EXPECT_EQ(r.metallic_roughness->wrap_s, TextureWrap::kClamp);
  EXPECT_EQ(r.metallic_roughness->transform, maps.metallic_roughness->transform);
  EXPECT_EQ(r.emissive->projection, TextureProjection::kBox);
  EXPECT_EQ(r.normal_scale, -0.5f);
  EXPECT_EQ(r.occlusion_strength, 0.75f);
  EXPECT_EQ(r.alpha_mode, AlphaMode::kMask);
  EXPECT_EQ(r.alpha, 0.8f);
  EXPECT_EQ(r.alpha_cutoff, 0.3f);
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  ASSERT_EQ(c->find(cxb::kTagSurfaceMaps).size(), 1u);
  EXPECT_FALSE(c->chunks()[c->find(cxb::kTagSurfaceMaps).at(0)].flags & cxb::kChunkRequired);  // a reader without it draws opaque and unmapped

  for (const auto& [change, says] : std::vector<std::pair<std::function<void(SceneDesc&)>, std::string>>{
           {[](SceneDesc& x) { x.objects[0].material.maps->alpha_mode = static_cast<AlphaMode>(3); }, "alpha mode 3"},
           {[](SceneDesc& x) { x.objects[0].material.maps->alpha = 1.5f; }, "/objects/0/material/alpha"},
           {[](SceneDesc& x) { x.objects[0].material.maps->alpha_cutoff = std::nanf(""); }, "/objects/0/material/alpha_cutoff"},
           {[](SceneDesc& x) { x.objects[0].material.maps->occlusion_strength = 2.0f; }, "/objects/0/material/occlusion_strength"},
           {[](SceneDesc& x) { x.objects[0].material.maps->normal_scale = 1e9f; }, "/objects/0/material/normal_scale"},
           {[](SceneDesc& x) { x.objects[0].material.maps->occlusion->image = 2; }, "/objects/0/material/occlusion_texture: image 2 is out of range"},
           {[](SceneDesc& x) { x.objects[0].role = Role::kBoth; }, "not a receiver"}}) {
    SceneDesc bad = s;
    change(bad);
    d = decode(encode_scene(bad, {{0}}));
    ASSERT_FALSE(d.ok()) << says;
    EXPECT_NE(d.error().message.find(says), std::string::npos) << d.error().message;
  }
  // An alpha plane must hold width x height bytes.
  SceneDesc short_alpha = s;
  short_alpha.images[0].alpha.pop_back();
  d = decode(encode_scene(short_alpha, {{0}}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("'TEXM'"), std::string::npos) << d.error().message;
  EXPECT_NE(d.error().message.find("4 alpha texels"), std::string::npos) << d.error().message;

  auto plain = encode_scene(full_scene(), {{0}});
  auto pc = cxb::read_container(plain.data(), plain.size());
  ASSERT_TRUE(pc.ok());
  EXPECT_TRUE(pc->find(cxb::kTagSurfaceMaps).empty());
}

// Thin-walled glass: role 5 in OBJS, no light-transport table,
// tinted through TINT; a bad tint, or a table for it, is refused.
TEST(SceneCodec, ThinWalledObjectsAreStoredAndValidated) {
  LightTransportTable table;
  SceneDesc s = dispersive_scene(table);
  Object pane = s.objects[1];
  pane.name = "pane";
  pane.role = Role::kThin;
  pane.material.dispersion = 0;
  pane.material.absorption = {0, 0, 0};
  pane.material.tint = {0.6f, 0.9f, 0.7f};
  s.objects.push_back(pane);
  auto d = decode(encode_scene(s, {{0}}, {}, {}, {table}));
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->scene.objects[2].role, Role::kThin);
  EXPECT_EQ(d->scene.objects[2].material.tint, (Vec3f{0.6f, 0.9f, 0.7f}));
  EXPECT_EQ(d->transport_tables.size(), 1u) << "the solid lens's only";

  SceneDesc bad = s;
  bad.objects[2].material.tint[1] = 1.5f;
  d = decode(encode_scene(bad, {{0}}, {}, {}, {table}));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("/objects/2/material/tint"), std::string::npos) << d.error().message;
  LightTransportTable for_pane = table;
  for_pane.object = 2;
  d = decode(encode_scene(s, {{0}}, {}, {}, {table, for_pane}));
  ASSERT_FALSE(d.ok()) << "a table for thin-walled glass";
  std::printf("[thin-walled] a table for it: %s\n", d.error().message.c_str());
}

TEST(SceneCodec, SpectralTablesAreStoredAndValidated) {
  LightTransportTable base;
  const SceneDesc s = dispersive_scene(base);
  auto at = [&](float nm) {
    LightTransportTable t = base;
    t.wavelength_nm = nm;
    t.ior = index_at(s.objects[1].material.ior, s.objects[1].material.dispersion, nm);
    return t;
  };
  auto b = encode_scene(s, {{0}}, {}, {}, {base, at(380), at(780)});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  ASSERT_EQ(d->spectral_tables.size(), 2u);
  EXPECT_EQ(d->spectral_tables[0].wavelength_nm, 380.0f);
  EXPECT_EQ(d->spectral_tables[1].ior, at(780).ior);
  EXPECT_EQ(d->transport_tables.size(), 1u);
  EXPECT_EQ(d->scene.objects[1].material.spectral_tables, 2u);
  EXPECT_EQ(d->scene.objects[0].material.spectral_tables, 0u);
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  ASSERT_EQ(c->find(cxb::kTagSpectralTransport).size(), 2u);
  EXPECT_TRUE(c->chunks()[c->find(cxb::kTagSpectralTransport)[0]].flags & cxb::kChunkRequired);

  auto refused = [&](const SceneDesc& scene, const std::vector<LightTransportTable>& tables, const char* what) {
    auto r = decode(encode_scene(scene, {{0}}, {}, {}, tables));
    ASSERT_FALSE(r.ok()) << "not refused: " << what;
    EXPECT_EQ(r.error().code, ErrorCode::kContainer) << what;
    EXPECT_NE(r.error().message.find("LTTS"), std::string::npos) << what << ": " << r.error().message;
  };
  refused(s, {base, at(780), at(380)}, "descending wavelengths");
  refused(s, {base, at(380), at(380)}, "the same wavelength twice");
  LightTransportTable t = at(480);
  t.ior = base.ior;
  refused(s, {base, t}, "the n_d index at 480 nm");
  t = at(480);
  t.resolution = 3;
  t.words.assign(std::size_t{3} * 9 * 4, 0);
  refused(s, {base, t}, "another resolution than the LTTB's");
  t = at(480);
  t.wavelength_nm = 300;
  refused(s, {base, t}, "300 nm");
  SceneDesc plain = s;
  plain.objects[1].material.dispersion = 0;
  t = at(480);
  t.ior = base.ior;  // what index_at() gives without dispersion
  refused(plain, {base, t}, "an object without dispersion");
  // Truncated anywhere in the payload (the wavelength, the header, the data).
  const std::vector<std::uint8_t> bytes = encode_transport_table(at(480));
  for (std::size_t cut : {std::size_t{0}, std::size_t{3}, std::size_t{20}, bytes.size() - 1}) {
    auto r = decode_transport_table(std::span(bytes.data(), cut), s, true);
    EXPECT_FALSE(r.ok()) << "cut at " << cut;
  }
}

// Where a table's path class switches (LTTW): optional, one per
// table, naming it by object and wavelength; the bytes survive. Refused: a
// second for one table, one for no table, another size; truncated
// anywhere. A file without it loads with no switches (what a reader that
// predates it sees, as it skips the optional chunk).
TEST(SceneCodec, TableSwitchesAreStoredAndValidated) {
  LightTransportTable base;
  const SceneDesc s = dispersive_scene(base);
  const std::size_t entries = std::size_t{base.vertex_count} * base.resolution * base.resolution;
  LightTransportTable spectral = base;
  spectral.wavelength_nm = 380;
  spectral.ior = index_at(s.objects[1].material.ior, s.objects[1].material.dispersion, 380);
  base.switches.assign(2 * entries, 0);
  base.switches[1] = 200;
  base.switches[2 * entries - 2] = 1;
  auto b = encode_scene(s, {{0}}, {}, {}, {base, spectral});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->transport_tables.at(0).switches, base.switches);
  EXPECT_TRUE(d->spectral_tables.at(0).switches.empty());
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  ASSERT_EQ(c->find(cxb::kTagTransportSwitches).size(), 1u);
  EXPECT_FALSE(c->chunks()[c->find(cxb::kTagTransportSwitches)[0]].flags & cxb::kChunkRequired);

  const auto with = [&](const std::vector<std::vector<std::uint8_t>>& payloads) {
    std::vector<LightTransportTable*> tables;
    auto r = decode(encode_scene(s, {{0}}, {}, {}, {base, spectral}));
    if (!r.ok()) return Status(r.error());
    LightTransportTable a = r->transport_tables.at(0), b2 = r->spectral_tables.at(0);
    a.switches.clear();
    for (const auto& p : payloads) {
      const Status st = decode_transport_switches(p, {&a, &b2});
      if (!st) return st;
    }
    return Status::success();
  };
  const std::vector<std::uint8_t> good = encode_transport_switches(base);
  EXPECT_TRUE(with({good}).ok());
  EXPECT_FALSE(with({good, good}).ok()) << "two for one table";
  LightTransportTable other = base;
  other.object = 0;
  EXPECT_FALSE(with({encode_transport_switches(other)}).ok()) << "object 0 has no table";
  other = base;
  other.wavelength_nm = 780;
  EXPECT_FALSE(with({encode_transport_switches(other)}).ok()) << "no table at 780 nm";
  other = base;
  other.vertex_count += 1;
  other.switches.assign(other.switches.size() + 2 * base.resolution * base.resolution, 0);
  const Status st = with({encode_transport_switches(other)});
  ASSERT_FALSE(st.ok()) << "another vertex count";
  EXPECT_NE(st.error().message.find("LTTW"), std::string::npos) << st.error().message;
  for (std::size_t cut : {std::size_t{0}, std::size_t{6}, std::size_t{19}, good.size() - 1}) {
    EXPECT_FALSE(with({std::vector<std::uint8_t>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut))}).ok()) << "cut at " << cut;
  }
  // A large table with one switch: zeros compress far past the tables'
  // 4096:1 bound, and still decode (the table's size bounds the data).
  LightTransportTable sparse = base;
  sparse.vertex_count = 4000;
  sparse.resolution = 20;
  sparse.switches.assign(std::size_t{4000} * 400 * 2, 0);
  sparse.switches[12345] = 77;
  const std::vector<std::uint8_t> packed = encode_transport_switches(sparse);
  LightTransportTable target = sparse;
  target.switches.clear();
  const Status sparse_ok = decode_transport_switches(packed, {&target});
  ASSERT_TRUE(sparse_ok.ok()) << sparse_ok.error().message;
  EXPECT_GT(sparse.switches.size(), 4096 * packed.size());
  EXPECT_EQ(target.switches, sparse.switches);
  // Without the chunk: no switches.
  base.switches.clear();
  d = decode(encode_scene(s, {{0}}, {}, {}, {base, spectral}));
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_TRUE(d->transport_tables.at(0).switches.empty());
}

// Objects sharing one set of tables: the required LTTR chunk
// names, per object in order, the earlier object whose LTTB and LTTS it
// uses; the sharer gets that object's absorption and spectral tables. Refused:
// a sharer with a table of its own (LTTB or LTTS), one naming a later
// object, a receiver, a sharer, or glass of another index or dispersion,
// an empty or truncated LTTR. A scene that shares nothing has no LTTR.
TEST(SceneCodec, SharedTablesAreStoredAndValidated) {
  LightTransportTable base;
  SceneDesc s = dispersive_scene(base);
  s.objects[1].material.absorption = base.absorption = {0.5f, 0.25f, 0.125f};
  for (const char* name : {"lens2", "lens3"}) {
    Object copy = s.objects[1];
    copy.name = name;
    copy.transform = {0, 0, -2, 0, 0, 2, 0, 0, 2, 0, 0, 0, 3, 1, 0, 1};  // turned, scaled, moved
    copy.tables_from = 1;
    s.objects.push_back(copy);
  }
  LightTransportTable at380 = base;
  at380.wavelength_nm = 380;
  at380.ior = index_at(s.objects[1].material.ior, s.objects[1].material.dispersion, 380);
  auto b = encode_scene(s, {{0}}, {}, {}, {base, at380});
  auto d = decode(b);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->transport_tables.size(), 1u);
  EXPECT_EQ(d->spectral_tables.size(), 1u);
  for (std::size_t i : {2u, 3u}) {
    const Object& o = d->scene.objects[i];
    EXPECT_EQ(o.tables_from, std::optional<std::uint32_t>{1});
    EXPECT_EQ(o.material.absorption, base.absorption) << "the tables' absorption";
    EXPECT_EQ(o.material.spectral_tables, 1u);
    EXPECT_EQ(o.transform, s.objects[i].transform);
  }
  EXPECT_FALSE(d->scene.objects[1].tables_from.has_value());
  auto c = cxb::read_container(b.data(), b.size());
  ASSERT_TRUE(c.ok());
  ASSERT_EQ(c->find(cxb::kTagTransportShared).size(), 1u);
  EXPECT_TRUE(c->chunks()[c->find(cxb::kTagTransportShared)[0]].flags & cxb::kChunkRequired);
  LightTransportTable plain_table;
  auto plain = encode_scene(dispersive_scene(plain_table), {{0}}, {}, {}, {plain_table});
  auto pc = cxb::read_container(plain.data(), plain.size());
  ASSERT_TRUE(pc.ok());
  EXPECT_TRUE(pc->find(cxb::kTagTransportShared).empty()) << "nothing shared, no LTTR: the bytes of before";

  auto refused = [&](const SceneDesc& scene, const std::vector<LightTransportTable>& tables, const char* what, const char* says) {
    auto r = decode(encode_scene(scene, {{0}}, {}, {}, tables));
    ASSERT_FALSE(r.ok()) << "not refused: " << what;
    EXPECT_EQ(r.error().code, ErrorCode::kContainer) << what;
    EXPECT_NE(r.error().message.find(says), std::string::npos) << what << ": " << r.error().message;
    std::printf("[shared tables] %s: %s\n", what, r.error().message.c_str());
  };
  LightTransportTable own = base;
  own.object = 2;
  refused(s, {base, own, at380}, "a sharer with its own LTTB", "may not have its own");
  LightTransportTable own380 = at380;
  own380.object = 3;
  refused(s, {base, at380, own380}, "a sharer with its own LTTS", "may not have its own");
  SceneDesc bad = s;
  bad.objects[2].tables_from = 3;
  refused(bad, {base, at380}, "a later object's tables", "/objects/2/tables_from");
  bad = s;
  bad.objects[2].tables_from = 0;
  refused(bad, {base, at380}, "a receiver's tables", "/objects/2/tables_from");
  bad = s;
  bad.objects[3].tables_from = 2;
  refused(bad, {base, at380}, "a sharer's tables", "/objects/3/tables_from");
  bad = s;
  bad.objects[2].material.ior = 1.6f;
  refused(bad, {base, at380}, "glass of another index", "/objects/2/tables_from");
  bad = s;
  bad.objects[3].material.dispersion = 2.0f;
  refused(bad, {base, at380}, "glass of another dispersion", "/objects/3/tables_from");

  // The payload itself: empty, truncated, or with bytes left over (the
  // file rebuilt around it, so that the container's checks pass).
  const std::size_t k = c->find(cxb::kTagTransportShared)[0];
  const auto payload = c->payload(k);
  const std::vector<std::uint8_t> whole(payload.begin(), payload.end());
  for (const auto& [what, count, size] : {std::tuple{"no object listed", 0u, std::size_t{4}}, std::tuple{"truncated", 2u, std::size_t{15}},
                                          std::tuple{"bytes left over", 1u, std::size_t{20}}}) {
    std::vector<std::uint8_t> p(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(size));
    test::put_u32(p, 0, count);
    cxb::ContainerWriter w;
    for (std::size_t i = 0; i < c->chunks().size(); ++i) {
      const auto& e = c->chunks()[i];
      const auto q = c->payload(i);
      w.add_chunk(e.tag, e.flags, i == k ? p : std::vector<std::uint8_t>(q.begin(), q.end()));
    }
    const std::vector<std::uint8_t> t = w.finish();
    auto r = decode(t);
    ASSERT_FALSE(r.ok()) << what;
    EXPECT_NE(r.error().message.find("LTTR"), std::string::npos) << what << ": " << r.error().message;
  }
}

}  // namespace
}  // namespace caustix
