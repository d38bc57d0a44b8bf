// Light-transport tables at the format level (formats/light_transport.h):
// quantisation bounds, the LTTB payload round trip and its refusals, and
// the look-up's interpolation on synthetic tables with known answers. The
// physics of baked tables is in glass_test.cpp.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "caustix/formats/light_transport.h"
#include "caustix/formats/scene.h"

namespace caustix {
namespace {

constexpr double kPi = 3.14159265358979323846;

SceneDesc glass_scene() {
  SceneDesc s;
  s.meshes.resize(1);
  Object o;
  o.name = "glass";
  o.role = Role::kTransparent;
  o.material.transparent = true;
  o.material.ior = 1.5f;
  s.objects.push_back(o);
  return s;
}

LightTransportTable empty_table(std::uint32_t vertices, std::uint32_t resolution, std::uint32_t bits) {
  LightTransportTable t;
  t.resolution = resolution;
  t.max_bounces = 4;
  t.ior = 1.5f;
  t.exit_min = {-1, -1, -1};
  t.exit_max = {1, 1, 1};
  t.max_path = 10;
  t.vertex_count = vertices;
  t.precision_bits = bits;
  t.words.assign(std::size_t{vertices} * resolution * resolution * 4, 0);
  return t;
}

Dir3 unit(Dir3 d) {
  const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return {d[0] / l, d[1] / l, d[2] / l};
}

double angle(const Dir3& a, const Dir3& b) {
  return std::acos(std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0));
}

// A table whose entries are random leaving paths (and a few trapped or
// occluded ones), stored at `bits`.
LightTransportTable random_table(std::uint32_t bits, std::vector<TransportEntry>* truth = nullptr) {
  LightTransportTable t = empty_table(7, 6, bits);
  std::mt19937 rng(bits);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t i = 0; i < t.words.size() / 4; ++i) {
    TransportEntry e;
    if (i % 11 == 3) {
      e.status = i % 2 ? TransportStatus::kTrapped : TransportStatus::kOccluded;
    } else {
      e.status = TransportStatus::kLeaves;
      e.exit = {u(rng), u(rng), u(rng)};
      e.direction = unit({u(rng), u(rng), u(rng)});
      e.transmittance = 0.5 + 0.5 * u(rng);
      e.path = 5 + 5 * u(rng);
      e.bounces = static_cast<std::uint8_t>(i % 3);
    }
    t.store(i, e);
    if (truth) truth->push_back(e);
  }
  return t;
}

TEST(TransportQuantisation, StoredValuesStayWithinTheStatedBounds) {
  for (std::uint32_t bits : {8u, 12u, 16u}) {
    std::vector<TransportEntry> truth;
    const LightTransportTable t = random_table(bits, &truth);
    double worst_pos = 0, worst_dir = 0, worst_t = 0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
      const TransportEntry got = t.load(i);
      ASSERT_EQ(got.status, truth[i].status);
      if (got.status != TransportStatus::kLeaves) continue;
      EXPECT_EQ(got.bounces, truth[i].bounces);
      for (std::size_t k = 0; k < 3; ++k) worst_pos = std::max(worst_pos, std::fabs(got.exit[k] - truth[i].exit[k]));
      worst_dir = std::max(worst_dir, angle(got.direction, truth[i].direction));
      worst_t = std::max(worst_t, std::fabs(got.transmittance - truth[i].transmittance));
      // Every field keeps `bits` significant bits: a multiple of 2^(16 - bits) or the top value.
      const std::uint32_t step = 1u << (16 - bits);
      for (std::size_t w = 0; w < 3; ++w) {
        for (std::uint32_t v : {t.words[4 * i + w] & 0xFFFFu, t.words[4 * i + w] >> 16}) {
          EXPECT_TRUE(v % step == 0 || v == 0xFFFF) << v;
        }
      }
    }
    std::printf("[ltt %2u bits] exit error %.2e (bound %.2e), direction %.4f deg (bound %.4f), T %.2e\n", bits, worst_pos,
                t.position_error_bound(), worst_dir * 180 / kPi, t.direction_error_bound() * 180 / kPi, worst_t);
    EXPECT_LE(worst_pos, t.position_error_bound() * (1 + 1e-9));
    EXPECT_LE(worst_dir, t.direction_error_bound());
    EXPECT_LE(worst_t, 0.5 * (1u << (16 - bits)) / 65535.0 + 1e-12);
  }
  // 12 bits, the default: 0.059 deg and 1/8190 of the exit box.
  EXPECT_NEAR(empty_table(1, 2, 12).direction_error_bound() * 180 / kPi, 0.0594, 0.0001);
}

TEST(TransportCodec, RoundTripIsExactAndFewerBitsStoreSmaller) {
  const SceneDesc scene = glass_scene();
  std::size_t previous = 0;
  for (std::uint32_t bits : {16u, 12u, 8u}) {
    const LightTransportTable t = random_table(bits);
    const std::vector<std::uint8_t> bytes = encode_transport_table(t);
    auto back = decode_transport_table(bytes, scene);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->words, t.words);
    EXPECT_EQ(back->resolution, t.resolution);
    EXPECT_EQ(back->vertex_count, t.vertex_count);
    if (previous) EXPECT_LT(bytes.size(), previous) << bits << " bits";
    previous = bytes.size();
  }
}

TEST(TransportCodec, RefusesEntriesAndHeadersOutOfRange) {
  const SceneDesc scene = glass_scene();
  const LightTransportTable good = random_table(12);
  auto refused = [&](LightTransportTable t, const char* what) {
    auto r = decode_transport_table(encode_transport_table(t), scene);
    ASSERT_FALSE(r.ok()) << what;
    EXPECT_EQ(r.error().code, ErrorCode::kContainer) << what;
    EXPECT_NE(r.error().message.find("LTTB"), std::string::npos) << r.error().message;
  };
  LightTransportTable t = good;
  t.words[3 * 4 + 3] = 3u << 16;  // status 3
  refused(t, "status");
  t = good;
  t.words[0 * 4 + 3] = 5u << 24;  // 5 bounces, table says at most 4
  refused(t, "bounces");
  t = good;
  t.words[3 * 4 + 0] = 7;  // a trapped entry that carries data
  refused(t, "non-empty trapped entry");
  t = good;
  t.resolution = 1;
  refused(t, "resolution");
  t = good;
  t.ior = 1.33f;
  refused(t, "IOR not the object's");
  // Truncation anywhere in the payload.
  const std::vector<std::uint8_t> bytes = encode_transport_table(good);
  for (std::size_t cut : {std::size_t{0}, std::size_t{10}, std::size_t{60}, bytes.size() - 1}) {
    auto r = decode_transport_table(std::span(bytes.data(), cut), scene);
    EXPECT_FALSE(r.ok()) << "cut at " << cut;
  }
}

// One vertex, normal +z, a field given per grid point (s, t) in [-1, 1]^2.
template <typename F>
LightTransportTable field_table(std::uint32_t r, F&& entry_at) {
  LightTransportTable t = empty_table(1, r, 16);
  for (std::uint32_t row = 0; row < r; ++row) {
    for (std::uint32_t col = 0; col < r; ++col) {
      const double s = -1.0 + 2.0 * col / (r - 1), tt = -1.0 + 2.0 * row / (r - 1);
      t.store(t.entry_index(0, row, col), entry_at(s, tt));
    }
  }
  return t;
}

TransportEntry leaving(double x, double y, double z, double transmittance) {
  TransportEntry e;
  e.status = TransportStatus::kLeaves;
  e.exit = {x, y, z};
  e.direction = {0, 0, -1};
  e.transmittance = transmittance;
  e.path = 1;
  return e;
}

// The query direction at hemi-octahedral coordinates (s, t) around +z.
Dir3 query(double s, double t) { return hemi_oct_decode(s, t); }

TEST(TransportLookup, BicubicIsExactForQuadraticsInsideAndLinearFieldsEverywhere) {
  const std::uint32_t r = 9;
  const auto quad = [](double s, double t) { return 0.3 * s * s - 0.2 * s * t + 0.25 * t * t + 0.1 * s; };
  const LightTransportTable t = field_table(r, [&](double s, double tt) {
    return leaving(quad(s, tt), 0.4 * s - 0.3 * tt, 0.0, 0.5 + 0.2 * s + 0.1 * tt);
  });
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  double worst_quad_inside = 0, worst_linear = 0, worst_quad_bilinear = 0;
  const double cell = 2.0 / (r - 1);
  for (int k = 0; k < 2000; ++k) {
    const double s = u(rng), tt = u(rng);
    const TransportEntry c = lookup(t, 0, {0, 0, 1}, query(s, tt), Interpolation::kBicubic);
    const TransportEntry b = lookup(t, 0, {0, 0, 1}, query(s, tt), Interpolation::kBilinear);
    ASSERT_EQ(c.status, TransportStatus::kLeaves);
    // Exact hemi-oct round trip is float-close; away from the outer cells
    // the 4 x 4 stencil is complete and the Catmull-Rom weights reproduce
    // quadratics.
    if (std::fabs(s) < 1 - cell && std::fabs(tt) < 1 - cell) {
      worst_quad_inside = std::max(worst_quad_inside, std::fabs(c.exit[0] - quad(s, tt)));
      worst_quad_bilinear = std::max(worst_quad_bilinear, std::fabs(b.exit[0] - quad(s, tt)));
    }
    worst_linear = std::max({worst_linear, std::fabs(c.exit[1] - (0.4 * s - 0.3 * tt)),
                             std::fabs(c.transmittance - (0.5 + 0.2 * s + 0.1 * tt))});
  }
  std::printf("[lookup] quadratic inside: bicubic %.2e, bilinear %.2e; linear everywhere: %.2e\n", worst_quad_inside,
              worst_quad_bilinear, worst_linear);
  const double quantum = 2.0 / 65535;  // one 16-bit step of the exit box [-1, 1]
  EXPECT_LT(worst_quad_inside, quantum);
  EXPECT_LT(worst_linear, quantum);
  EXPECT_GT(worst_quad_bilinear, 20 * quantum);  // so the check above can fail
}

TEST(TransportLookup, BicubicFallsBackToBilinearAtADiscontinuity) {
  const std::uint32_t r = 8;
  // Entries with s > 0.3 leave after one internal reflection: a jump.
  const LightTransportTable t = field_table(r, [](double s, double tt) {
    TransportEntry e = leaving(s > 0.3 ? 1.0 : 0.0, tt, 0, 0.8);
    e.bounces = s > 0.3 ? 1 : 0;
    return e;
  });
  // Inside the cell that straddles the jump both modes give the same
  // bilinear fall-back; one cell away the cubic does not ring across it (the
  // outer column is extrapolated instead): the value stays 0.
  const double s_jump = -1.0 + 2.0 * 4.5 / (r - 1);  // the middle of cell 4..5
  for (double tt : {-0.5, 0.1, 0.6}) {
    const TransportEntry c = lookup(t, 0, {0, 0, 1}, query(s_jump, tt), Interpolation::kBicubic);
    const TransportEntry b = lookup(t, 0, {0, 0, 1}, query(s_jump, tt), Interpolation::kBilinear);
    EXPECT_NEAR(c.exit[0], b.exit[0], 1e-12);
    const double s_before = -1.0 + 2.0 * 3.5 / (r - 1);
    const TransportEntry near = lookup(t, 0, {0, 0, 1}, query(s_before, tt), Interpolation::kBicubic);
    // (0 is stored as the nearest 16-bit step; a cubic through the jump
    // would undershoot by 0.0625 here.)
    EXPECT_NEAR(near.exit[0], 0.0, 2.0 / 65535) << "cubic rang across the jump";
  }
  // In the straddling cell the exit lies on one side of the jump (the
  // nearer grid direction's), never blended between the two paths.
  for (double frac : {0.3, 0.45, 0.55, 0.7}) {
    const double s = -1.0 + 2.0 * (4 + frac) / (r - 1);
    const TransportEntry c = lookup(t, 0, {0, 0, 1}, query(s, 0.1), Interpolation::kBicubic);
    EXPECT_NEAR(c.exit[0], frac < 0.5 ? 0.0 : 1.0, 2.0 / 65535) << "blended across the jump at " << frac;
    EXPECT_EQ(c.bounces, frac < 0.5 ? 0 : 1);
    EXPECT_NEAR(c.transmittance, 0.8, 1e-4);
  }
  // A stencil whose inner entry is trapped still interpolates the others.
  LightTransportTable holes = t;
  TransportEntry trapped;
  holes.store(holes.entry_index(0, 3, 2), trapped);
  const TransportEntry got = lookup(holes, 0, {0, 0, 1}, query(-1.0 + 2.0 * 2.5 / (r - 1), -1.0 + 2.0 * 2.5 / (r - 1)));
  EXPECT_EQ(got.status, TransportStatus::kLeaves);
  EXPECT_NEAR(got.transmittance, 0.8 * 0.75, 1e-4);  // the trapped quarter passes nothing
}

}  // namespace
}  // namespace caustix
