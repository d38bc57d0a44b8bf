// LMAP / OBBS payloads: round trip, and hostile payloads refused cleanly
// (every prefix, every byte flip, inconsistent fields). Runs under ASan.

#include <gtest/gtest.h>

#include <cmath>

#include "caustix/formats/level_map.h"
#include "caustix/formats/scene.h"

namespace caustix {
namespace {

SceneDesc two_object_scene() {
  SceneDesc s;
  s.meshes.resize(1);
  s.objects.resize(2);
  s.objects[0].name = "floor";
  s.objects[1].name = "glass";
  s.objects[1].role = Role::kTransparent;
  s.objects[1].material.transparent = true;
  s.lights.resize(1);
  return s;
}

LevelMap small_map() {
  LevelMap m;
  m.object = 0;
  m.light = 0;
  m.frame.origin = {1e4, -2, 3};
  m.frame.half = {1, 0.5, 2};
  m.map_size = 4;
  m.depth = {0, 100, 200, kEmptyDepth, 300, 65534, kEmptyDepth, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  m.diffuse.assign(16 * 3, 200);
  m.histogram = {10, 0, 4};  // 14 covered texels
  m.sub_boxes = {{0, 0}, {2, 2}};
  m.uniform_planes = {{0.5f, 0.25f}, {0.0f, 0.25f}, {-0.5f, 0.25f}};
  m.smart_planes = {{0.4f, 0.1f}, {-0.4f, 0.1f}};
  m.epsilon = 0.25f;
  m.planes_requested = 2;
  return m;
}

TEST(LevelMapCodec, RoundTrip) {
  const SceneDesc scene = two_object_scene();
  const LevelMap m = small_map();
  const auto bytes = encode_level_map(m);
  auto d = decode_level_map(bytes, scene);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->depth, m.depth);
  EXPECT_EQ(d->diffuse, m.diffuse);
  EXPECT_EQ(d->histogram, m.histogram);
  EXPECT_EQ(d->frame.origin, m.frame.origin);
  EXPECT_EQ(d->smart_planes.size(), 2u);
  EXPECT_EQ(d->sub_boxes.size(), 2u);
  EXPECT_EQ(encode_level_map(*d), bytes);
}

TEST(LevelMapCodec, EveryPrefixAndFlipIsSafe) {
  const SceneDesc scene = two_object_scene();
  const auto bytes = encode_level_map(small_map());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
    auto d = decode_level_map(cut, scene);
    ASSERT_FALSE(d.ok()) << "prefix " << n;
    EXPECT_NE(d.error().message.find("'LMAP'"), std::string::npos);
  }
  // Flips: either refused or decoded into something self-consistent.
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    auto t = bytes;
    t[i] ^= 0x5A;
    auto d = decode_level_map(t, scene);
    if (d.ok()) {
      EXPECT_EQ(d->depth.size(), std::size_t{d->map_size} * d->map_size);
      EXPECT_LT(d->object, scene.objects.size());
    }
  }
}

TEST(LevelMapCodec, InconsistentFieldsAreRefused) {
  const SceneDesc scene = two_object_scene();
  LevelMap m = small_map();
  m.object = 1;  // a transparent object, not a receiver
  EXPECT_FALSE(decode_level_map(encode_level_map(m), scene).ok());
  m = small_map();
  m.light = 3;
  EXPECT_FALSE(decode_level_map(encode_level_map(m), scene).ok());
  m = small_map();
  m.histogram = {10, 0, 5};  // claims 15 covered texels, the map has 14
  auto d = decode_level_map(encode_level_map(m), scene);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("histogram"), std::string::npos) << d.error().message;
  m = small_map();
  m.sub_boxes = {{2, 2}, {0, 0}};  // out of order
  EXPECT_FALSE(decode_level_map(encode_level_map(m), scene).ok());
  m = small_map();
  m.frame.v = {0, 0.9f, 0};  // not unit
  EXPECT_FALSE(decode_level_map(encode_level_map(m), scene).ok());
  m = small_map();
  m.smart_planes[0].epsilon = std::nanf("");
  EXPECT_FALSE(decode_level_map(encode_level_map(m), scene).ok());
  m = small_map();
  m.depth[0] = 65535 - 0;  // empty is fine...
  m.depth[1] = 65535;      // ...but now the histogram is wrong
  EXPECT_FALSE(decode_level_map(encode_level_map(m), scene).ok());
}

TEST(LevelMapCodec, ObjectBoxes) {
  const SceneDesc scene = two_object_scene();
  ObjectBox b;
  b.object = 1;
  b.center = {1, 2, 3};
  b.axes = {Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, 0, -1}};  // left-handed is accepted
  b.half = {1, 2, 3};
  auto d = decode_object_boxes(encode_object_boxes({b}), scene);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->at(0).center, b.center);
  b.object = 7;
  EXPECT_FALSE(decode_object_boxes(encode_object_boxes({b}), scene).ok());
  b.object = 0;
  b.axes[1] = {1, 0, 0};
  EXPECT_FALSE(decode_object_boxes(encode_object_boxes({b}), scene).ok());
}

}  // namespace
}  // namespace caustix
