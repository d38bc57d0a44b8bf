// The view through glass (timofy 2009's nearby-geometry refraction,
// Shah, Konttinen & Pattanaik 2007, against Iwasaki et al. §3's table-traced view
// rays), with Snell's law as the oracle: a dark strip on the floor seen
// through a flat glass slab from an oblique camera appears where the exact
// trace of the camera's rays through the slab's two faces puts it, not
// where the straight view would. Nearby refraction is exact on planes (the
// exit and landing iterations converge onto the slab's back face and the
// floor), so the strip's edge lands within a pixel of the trace's. Extremes:
// one and 64 iterations stay finite; iterations out of 1..64 are refused by
// name. Dispersion: through a dispersive slab the nearby view
// puts the edge where Snell puts it at each wavelength's index, and the
// RGB image is the wavelengths' images times their weights. A tinted slab
// darkens the floor seen through it by tint^2; a thin-walled pane
// shows it straight through, scaled by its sheet's transmittance and tint;
// a glowing box inside an absorbing slab is seen through the entry alone,
// attenuated as Beer-Lambert says over the depth it lies at.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>

#include "bake_fixture.h"
#include "caustix/formats/spectrum.h"
#include "caustix/sample/renderer.h"
#include "gl_fixture.h"
#include "optics_oracle.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

constexpr double kIor = 1.5;
constexpr double kSlabTop = 0.5, kSlabBottom = 0.3;  // y; the slab spans |x|, |z| <= 1
constexpr double kStripTop = 0.004, kStripEdge = 0.2;  // the strip spans |z| <= 0.2; 4 mm (its unlit side, under half a pixel, counts half)
constexpr int kSize = 256;
const glm::vec3 kEye(0.0f, 1.5f, 1.5f);

// A closed box (8 shared corners, 12 triangles, outward winding) of the
// given extent, written as OBJ; the bake splits its crease edges.
std::string write_slab() {
  const auto path = std::filesystem::temp_directory_path() / "caustix_glass_view_slab.obj";
  std::ofstream f(path);
  for (int c = 0; c < 8; ++c) {
    f << "v " << (c & 1 ? 1 : -1) << ' ' << (c & 2 ? kSlabTop : kSlabBottom) << ' ' << (c & 4 ? 1 : -1) << '\n';
  }
  // Faces as corner quads (1-based), counter-clockwise seen from outside.
  const int quads[6][4] = {{1, 5, 7, 3}, {2, 4, 8, 6}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 3, 4, 2}, {5, 6, 8, 7}};
  for (const auto& q : quads) f << "f " << q[0] << ' ' << q[1] << ' ' << q[2] << "\nf " << q[0] << ' ' << q[2] << ' ' << q[3] << '\n';
  return path.string();
}

nlohmann::json slab_scene(double dispersion = 0.0, std::array<double, 3> tint = {1, 1, 1}) {
  const std::string meshes = test::kScenes + "../meshes/";
  return {{"name", "glass_view_slab"},
          {"objects",
           {{{"name", "floor"}, {"mesh", meshes + "plane.obj"}, {"material", {{"albedo", 0.9}}}, {"transform", {{"scale", {6, 1, 6}}}}},
            {{"name", "strip"},
             {"mesh", meshes + "box.obj"},
             {"material", {{"albedo", 0.05}}},
             {"transform", {{"translate", {0, kStripTop / 2, 0}}, {"scale", {3.0, kStripTop, 2 * kStripEdge}}}}},
            {{"name", "slab"},
             {"mesh", write_slab()},
             {"role", "transparent"},
             {"material", {{"transparent", true}, {"ior", kIor}, {"dispersion", dispersion}, {"tint", tint}}}}}},
          {"lights", {{{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", 1.0}}}},
          {"camera", {{"position", {kEye.x, kEye.y, kEye.z}}, {"target", {0, 0, 0}}, {"fov_y_deg", 45}}}};
}

// The image row (from the bottom, fractional pixel centres) where the
// world point p projects under the test's camera.
double image_row(const glm::vec3& p) {
  const glm::mat4 vp = glm::perspective(glm::radians(45.0f), 1.0f, 0.05f, 100.0f) *
                       glm::lookAt(kEye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
  const glm::vec4 c = vp * glm::vec4(p, 1.0f);
  return (c.y / c.w * 0.5 + 0.5) * kSize - 0.5;
}

// The exact trace (in the x = 0 plane): the point on the slab's top face
// whose camera ray, refracted through both faces (leaving parallel to how
// it came), lands on the strip's edge (halfway up its side).
glm::vec3 apparent_edge(double ior = kIor) {
  double lo = -1, hi = 1;
  for (int k = 0; k < 100; ++k) {
    const double ze = 0.5 * (lo + hi);
    const double dy = kSlabTop - kEye.y, dz = ze - kEye.z;
    const double s = std::fabs(dz) / std::hypot(dy, dz), st = s / ior;
    const double tan_i = s / std::sqrt(1 - s * s), tan_t = st / std::sqrt(1 - st * st);
    const double land = ze - (kSlabTop - kSlabBottom) * tan_t - (kSlabBottom - kStripTop / 2) * tan_i;
    (land > kStripEdge ? hi : lo) = ze;
  }
  return {0.0f, static_cast<float>(kSlabTop), static_cast<float>(0.5 * (lo + hi))};
}

class GlassView : public test::GlTest {
 protected:
  void SetUp() override {
    test::GlTest::SetUp();
    renderer_ = slab(0.0, "glass_view_test");
    ASSERT_TRUE(renderer_);
  }
  static std::unique_ptr<sample::Renderer> slab(double dispersion, const char* tag) {
    auto scene = test::bake_and_load(test::write_scene(slab_scene(dispersion), tag));
    if (!scene) return nullptr;
    auto r = sample::Renderer::create(*scene);
    EXPECT_TRUE(r.ok()) << r.error().message;
    return r.ok() ? std::move(*r) : nullptr;
  }
  static sample::FrameParams frame(const runtime::GlassViewOptions& o) {
    sample::FrameParams f;
    f.camera.position = {kEye.x, kEye.y, kEye.z};
    f.camera.target = {0, 0, 0};
    f.camera.fov_y_deg = 45;
    f.width = f.height = kSize;
    f.glass_view = o;
    return f;
  }
  Status render(const runtime::GlassViewOptions& o) { return renderer_->render(frame(o)); }
  // The strip's near edge along the image's centre column, searched within
  // [near - 20, near + 40] pixels: the row where the luminance crosses
  // halfway between the floor and the strip.
  double edge_row(const runtime::GlassViewOptions& o, double near) {
    const Status st = render(o);
    EXPECT_TRUE(st.ok()) << st.error().message;
    return edge_row(renderer_->read_hdr(), near);
  }
  static double edge_row(const std::vector<float>& hdr, double near) {
    std::vector<double> column(kSize);
    for (int row = 0; row < kSize; ++row) {  // from the bottom; read_hdr() gives the top row first
      const std::size_t i = (static_cast<std::size_t>(kSize - 1 - row) * kSize + kSize / 2) * 4;
      for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(hdr[i + c]));
      column[row] = (hdr[i] + hdr[i + 1] + hdr[i + 2]) / 3;
    }
    // Below the edge lies the floor in front of the strip; the strip is the
    // darkest stretch above it.
    const auto lo = column.begin() + std::max(0, static_cast<int>(near) - 20);
    const auto dark = std::min_element(lo, column.begin() + std::min(kSize, static_cast<int>(near) + 40));
    const double half = 0.5 * (*dark + *std::max_element(lo, dark + 1));
    for (int row = static_cast<int>(dark - column.begin()); row > lo - column.begin(); --row) {
      if (column[row - 1] >= half) return row - 1 + (column[row - 1] - half) / (column[row - 1] - column[row]);
    }
    ADD_FAILURE() << "no edge in the column";
    return 0;
  }
  std::unique_ptr<sample::Renderer> renderer_;
};

TEST_F(GlassView, NearbyRefractionPutsTheStripWhereSnellSays) {
  const double straight = image_row({0.0f, static_cast<float>(kStripTop / 2), static_cast<float>(kStripEdge)});
  const double exact = image_row(apparent_edge());
  runtime::GlassViewOptions o;
  o.method = runtime::GlassView::kNearby;
  const double nearby = edge_row(o, exact);
  o.method = runtime::GlassView::kTable;
  const double table = edge_row(o, exact);
  std::printf("[slab] strip edge at row %.2f exact (%.2f seen straight); nearby %.2f (%+.2f px), table %.2f (%+.2f px)\n", exact,
              straight, nearby, nearby - exact, table, table - exact);
  ASSERT_GT(std::fabs(exact - straight), 4.0) << "the slab must shift the edge for the test to mean anything";
  EXPECT_NEAR(nearby, exact, 1.0);

}

TEST_F(GlassView, IterationExtremesStayFiniteAndAbsurdOnesAreRefused) {
  runtime::GlassViewOptions o;
  o.method = runtime::GlassView::kNearby;
  for (std::uint32_t n : {1u, 64u}) {
    o.iterations = o.exit_iterations = n;
    edge_row(o, image_row(apparent_edge()));  // asserts every pixel of the column finite
  }
  for (auto field : {&runtime::GlassViewOptions::iterations, &runtime::GlassViewOptions::exit_iterations}) {
    for (std::uint32_t bad : {0u, 65u}) {
      runtime::GlassViewOptions b;
      b.method = runtime::GlassView::kNearby;
      b.*field = bad;
      const Status st = render(b);
      ASSERT_FALSE(st.ok());
      EXPECT_EQ(st.error().code, ErrorCode::kUsage);
      EXPECT_NE(st.error().message.find("iterations"), std::string::npos) << st.error().message;
    }
  }
}

// A dispersive slab (n_d 1.5, dispersion 10: V_d 2, n 1.94 at 400 nm and
// 1.39 at 700 nm) through the nearby view. Each monochromatic image puts
// the strip's edge where the exact trace at that wavelength's index does,
// within a pixel as at n_d, and 400 and 700 nm lie more than 3 pixels
// apart. With the caustics off the opaque scene behind the glass is the
// same at every wavelength, so the RGB image of 4 wavelengths is their
// images times the bins' weights to float rounding, and its red and blue
// edges part; one wavelength is the slab without dispersion, bit for bit.
TEST_F(GlassView, NearbyViewRefractsEachWavelengthAtItsIndex) {
  constexpr float kDispersion = 10.0f;
  auto dispersive = slab(kDispersion, "glass_view_dispersive");
  ASSERT_TRUE(dispersive);
  runtime::GlassViewOptions o;
  o.method = runtime::GlassView::kNearby;
  sample::FrameParams f = frame(o);
  f.caustics.method = runtime::CausticsMethod::kNone;
  auto image = [](sample::Renderer& r, const sample::FrameParams& fp) {
    const Status st = r.render(fp);
    EXPECT_TRUE(st.ok()) << st.error().message;
    return r.read_hdr();
  };
  std::vector<double> rows;
  for (const float nm : {400.0f, 700.0f}) {
    f.caustics.wavelength_nm = nm;
    const double ior = index_at(static_cast<float>(kIor), kDispersion, nm);
    const double exact = image_row(apparent_edge(ior));
    const double got = edge_row(image(*dispersive, f), exact);
    std::printf("[dispersive slab] %.0f nm, n %.4f: strip edge at row %.2f, exact %.2f (%+.2f px)\n", nm, ior, got, exact, got - exact);
    EXPECT_NEAR(got, exact, 1.0) << nm << " nm";
    rows.push_back(got);
  }
  EXPECT_GT(std::fabs(rows[0] - rows[1]), 3.0) << "the wavelengths must part for the test to mean anything";

  f.caustics.wavelength_nm.reset();
  f.caustics.wavelengths = 4;
  const std::vector<float> rgb = image(*dispersive, f);
  std::vector<double> sum(rgb.size(), 0.0);
  for (const WavelengthSample& w : wavelength_samples(4)) {
    f.caustics.wavelength_nm = w.nm;
    const std::vector<float> mono = image(*dispersive, f);
    for (std::size_t i = 0; i < rgb.size(); ++i) {
      if (i % 4 < 3) sum[i] += w.rgb[i % 4] * mono[i];
    }
  }
  double peak = 0, worst = 0;
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    if (i % 4 == 3) continue;
    peak = std::max(peak, std::fabs(sum[i]));
    worst = std::max(worst, std::fabs(rgb[i] - sum[i]));
  }
  std::printf("[dispersive slab] RGB of 4 wavelengths vs their weighted images: largest difference %.2e of the peak\n", worst / peak);
  EXPECT_LT(worst, 1e-5 * peak);
  auto channel = [&rgb](int c) {
    std::vector<float> one(rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i) one[i] = rgb[i - i % 4 + static_cast<std::size_t>(c)];
    return one;
  };
  const double red = edge_row(channel(0), rows[1]), blue = edge_row(channel(2), rows[0]);
  std::printf("[dispersive slab] RGB: red edge at row %.2f, blue at %.2f\n", red, blue);
  EXPECT_GT(std::fabs(red - blue), 1.0);

  f.caustics.wavelength_nm.reset();
  f.caustics.wavelengths = 1;
  EXPECT_TRUE(image(*dispersive, f) == image(*renderer_, f)) << "one wavelength must be the slab without dispersion";
}

// An object inside the glass (MosquitoInAmber's insect turned
// the whole amber black in the table view). The table view maps the
// glass's front straight to its exit; its exit ray starts behind anything
// inside, so a surface nearer than the exit point is not what it meets.
// glass_ball with a 6 cm opaque cube at the ball's centre against the same
// view without it: the ball's pixels keep their light (the cube, seen from
// the exit side, covers a few of them); the march that took the cube for a
// hit wherever it covered an exit point's pixel left 6 % of their light.
TEST_F(GlassView, AnObjectInsideTheGlassDoesNotBlackenTheTableView) {
  nlohmann::json j = test::canonical_scene("glass_ball");
  const auto ball_mean = [&](const nlohmann::json& scene, const char* tag) {
    bake::BakeOptions opt;
    opt.transport.resolution = 8;  // the view's exit points, not the caustic, are under test
    auto loaded = test::bake_and_load(test::write_scene(scene, tag), opt);
    EXPECT_TRUE(loaded);
    auto r = sample::Renderer::create(*loaded);
    EXPECT_TRUE(r.ok());
    sample::FrameParams f;
    f.camera = (*r)->default_camera();
    f.width = f.height = 128;
    EXPECT_TRUE((*r)->render(f).ok());
    const std::vector<float> hdr = (*r)->read_hdr();
    // The ball's disc on screen: the pixels whose ray passes within 0.45 m
    // of its centre (0, 0.75, 0).
    const glm::vec3 eye(f.camera.position[0], f.camera.position[1], f.camera.position[2]);
    const glm::mat4 inv = glm::inverse(glm::perspective(glm::radians(f.camera.fov_y_deg), 1.0f, f.camera.near_plane, f.camera.far_plane) *
                                       glm::lookAt(eye, glm::vec3(f.camera.target[0], f.camera.target[1], f.camera.target[2]), glm::vec3(0, 1, 0)));
    double sum = 0;
    int n = 0;
    for (int row = 0; row < 128; ++row) {
      for (int col = 0; col < 128; ++col) {
        const glm::vec4 far = inv * glm::vec4((col + 0.5f) / 64.0f - 1.0f, 1.0f - (row + 0.5f) / 64.0f, 1.0f, 1.0f);
        const glm::vec3 d = glm::normalize(glm::vec3(far) / far.w - eye), c = glm::vec3(0, 0.75f, 0) - eye;
        if (glm::length(c - glm::dot(c, d) * d) > 0.45f) continue;
        const std::size_t i = (static_cast<std::size_t>(row) * 128 + col) * 4;
        sum += hdr[i] + hdr[i + 1] + hdr[i + 2];
        ++n;
      }
    }
    EXPECT_GT(n, 500);
    return sum / std::max(n, 1);
  };
  const double clear = ball_mean(j, "glass_view_clear");
  j["objects"].push_back({{"name", "insect"},
                          {"mesh", test::kScenes + "../meshes/box.obj"},
                          {"material", {{"albedo", 0.5}}},
                          {"transform", {{"translate", {0, 0.75, 0}}, {"scale", 0.06}}}});
  const double inside = ball_mean(j, "glass_view_insect");
  std::printf("[glass view] ball's mean radiance with an object inside / without: %.3f\n", inside / clear);
  EXPECT_GT(inside / clear, 0.9);
}

// What is inside the glass, seen through either view with Beer-Lambert as
// the oracle: a glowing box inside the slab (its top 5 cm below the
// slab's), seen straight down through glass absorbing sigma = (0, 4, 8)
// per metre. The box's own radiance is the image with it glowing less the
// image with it black, and through the slab it is the entry's Fresnel
// transmittance at normal incidence, 1 - ((n - 1)/(n + 1))^2, times
// e^(-sigma 0.05) per channel.
TEST_F(GlassView, BothViewsSeeWhatIsInsideThroughBeerLambert) {
  const double depth = kSlabTop - 0.45;
  const auto centre = [&](double glow, runtime::GlassView view) {
    nlohmann::json j{{"name", "inside"},
                     {"objects", {{{"name", "floor"}, {"mesh", test::kScenes + "../meshes/plane.obj"}, {"material", {{"albedo", 0.5}}},
                                   {"transform", {{"scale", {4, 1, 4}}}}},
                                  {{"name", "slab"}, {"mesh", write_slab()}, {"role", "transparent"},
                                   {"material", {{"transparent", true}, {"ior", kIor}, {"absorption", {0.0, 4.0, 8.0}}}}},
                                  {{"name", "insect"}, {"mesh", test::kScenes + "../meshes/box.obj"},
                                   {"material", {{"albedo", 0.0}, {"metallic", 1.0}, {"emissive", glow}}},
                                   {"transform", {{"translate", {0, 0.4, 0}}, {"scale", 0.1}}}}}},
                     {"lights", {{{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", 1.0}}}},
                     {"camera", {{"position", {0, 3, 0}}, {"target", {0, 0, 0}}, {"up", {0, 0, -1}}, {"fov_y_deg", 20}}}};
    bake::BakeOptions opt;
    opt.transport.resolution = 8;
    auto loaded = test::bake_and_load(test::write_scene(j, glow > 0 ? "inside_glowing" : "inside_black"), opt);
    EXPECT_TRUE(loaded);
    auto r = sample::Renderer::create(*loaded);
    EXPECT_TRUE(r.ok());
    sample::FrameParams f;
    f.camera = (*r)->default_camera();
    f.width = f.height = 65;  // the middle pixel's centre on the axis
    f.glass_view.method = view;
    EXPECT_TRUE((*r)->render(f).ok());
    const std::vector<float> hdr = (*r)->read_hdr();
    const std::size_t i = (32u * 65u + 32u) * 4u;
    return glm::dvec3(hdr[i], hdr[i + 1], hdr[i + 2]);
  };
  const double t = 1.0 - std::pow((kIor - 1.0) / (kIor + 1.0), 2.0);
  const glm::dvec3 want(t, t * std::exp(-4.0 * depth), t * std::exp(-8.0 * depth));
  for (const auto view : {runtime::GlassView::kTable, runtime::GlassView::kNearby}) {
    const glm::dvec3 seen = centre(1.0, view) - centre(0.0, view);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(seen[k], want[k], 0.01 * want[k]) << "channel " << k << ", view " << static_cast<int>(view);
    std::printf("[glass view] inside the slab, 5 cm deep, %s view: %.4f %.4f %.4f (Beer-Lambert %.4f %.4f %.4f)\n",
                view == runtime::GlassView::kTable ? "table" : "nearby", seen.x, seen.y, seen.z, want.x, want.y, want.z);
  }
}

// The floor seen through a tinted slab. A low sun (10 degrees,
// travelling along -x) reaches the floor under the slab at x = 0.4 beneath
// the slab (the light through the slab lands at -0.35 < x < 0), so the
// floor there is lit as brightly whatever the tint, and the view ray
// crossing the slab's two faces takes tint^2. What the slab adds by itself
// -- its Fresnel reflection of the sky -- is the image with a black tint
// (0), so per channel (P(tint) - P(0)) / (P(1) - P(0)) = tint^2, in both
// views.
TEST_F(GlassView, ATintedSlabDarkensTheFloorSeenThroughItByTintSquared) {
  const std::array<double, 3> tint{0.5, 0.8, 0.9};
  const double row0 = image_row(apparent_edge()) - 14;  // the floor in front of the strip, seen through the slab, 70 columns right of the middle
  double mean[3][2][3] = {};  // [black, tinted, clear][table, nearby][channel]
  const std::array<double, 3> tints[3] = {{0, 0, 0}, tint, {1, 1, 1}};
  // Baked once, tinted (the tint through the .cxb); black and clear by
  // editing the loaded scene's material.
  nlohmann::json j = slab_scene(0.0, tint);
  const double sun = 10 * std::acos(-1.0) / 180;
  j["lights"][0]["direction"] = {-std::cos(sun), -std::sin(sun), 0};
  bake::BakeOptions opt;
  opt.transport.resolution = 8;  // the view, not the slab's caustic, is under test
  const auto baked = test::bake_and_load(test::write_scene(j, "glass_view_tint"), opt);
  ASSERT_TRUE(baked);
  ASSERT_EQ(baked->desc.objects[2].material.tint, (Vec3f{0.5f, 0.8f, 0.9f}));
  for (int k = 0; k < 3; ++k) {
    runtime::RuntimeScene scene = *baked;
    for (std::size_t c = 0; c < 3; ++c) scene.desc.objects[2].material.tint[c] = static_cast<float>(tints[k][c]);
    auto r = sample::Renderer::create(scene);
    ASSERT_TRUE(r.ok()) << r.error().message;
    for (int v = 0; v < 2; ++v) {
      runtime::GlassViewOptions o;
      o.method = v == 0 ? runtime::GlassView::kTable : runtime::GlassView::kNearby;
      sample::FrameParams f = frame(o);
      ASSERT_TRUE((*r)->render(f).ok());
      const std::vector<float> hdr = (*r)->read_hdr();
      for (int row = static_cast<int>(row0) - 4; row <= static_cast<int>(row0) + 4; ++row) {
        for (int col = kSize / 2 + 66; col <= kSize / 2 + 74; ++col) {
          const std::size_t i = (static_cast<std::size_t>(kSize - 1 - row) * kSize + col) * 4;
          for (int c = 0; c < 3; ++c) mean[k][v][c] += hdr[i + c] / 81.0;
        }
      }
    }
  }
  for (int v = 0; v < 2; ++v) {
    for (int c = 0; c < 3; ++c) {
      const double seen = (mean[1][v][c] - mean[0][v][c]) / (mean[2][v][c] - mean[0][v][c]), want = tint[c] * tint[c];
      std::printf("[tinted slab, %s view] channel %d: floor behind it %.4f of the clear slab's (reflection %.4f of %.4f); tint^2 %.4f\n",
                  v == 0 ? "table" : "nearby", c, seen, mean[0][v][c], mean[2][v][c], want);
      EXPECT_GT(mean[2][v][c] - mean[0][v][c], 4 * mean[0][v][c]) << "the floor, not the reflection, must dominate";
      EXPECT_NEAR(seen, want, 0.002 * want);  // measured within 0.01 %
    }
  }
}

// A thin-walled pane in the view: an open vertical quad at
// z = 1 between the camera and the floor (baked thin-walled), the sun
// behind it (its shadow falls towards the camera, off the floor seen
// through it). Through a sheet the floor is seen where it is, scaled by
// tint (1 - r) / (1 + r) (r Fresnel's reflectance at the view ray's angle
// to the pane; optics_oracle's Fresnel), plus the sky the sheet reflects.
// Per pixel: P(tint) = R_sheet sky + T_sheet tint F, so (P(tint) - P(0)) /
// (P(1) - P(0)) = tint, and (P(1) - P(0)) / F = T_sheet, F the floor with
// the pane at index 1 (which neither reflects nor dims). In both views.
TEST_F(GlassView, AThinPaneShowsWhatIsBehindItStraightThroughScaledByItsSheet) {
  const std::array<double, 3> tint{0.5, 0.8, 0.9};
  nlohmann::json j = slab_scene();
  const auto pane = std::filesystem::temp_directory_path() / "caustix_glass_view_pane.obj";
  std::ofstream(pane) << "v -1 0 1\nv 1 0 1\nv 1 1.4 1\nv -1 1.4 1\nf 1 2 3\nf 1 3 4\n";
  j["objects"][2]["mesh"] = pane.string();
  j["objects"][2]["material"] = {{"transparent", true}, {"ior", kIor}, {"tint", tint}};
  j["lights"][0]["direction"] = {0, -0.9, 0.44};
  const auto baked = test::bake_and_load(test::write_scene(j, "glass_view_thin"));
  ASSERT_TRUE(baked);
  ASSERT_EQ(baked->desc.objects[2].role, Role::kThin);
  // [black, tinted, clear, index 1][table, nearby][channel], over 9 x 9
  // pixels around the image's centre (the floor at the origin, seen
  // through the pane at y = 1); and the sheet's T per pixel.
  double mean[4][2][3] = {};
  double sheet = 0;
  const glm::mat4 vp = glm::perspective(glm::radians(45.0f), 1.0f, 0.05f, 100.0f) * glm::lookAt(kEye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
  for (int row = kSize / 2 - 4; row <= kSize / 2 + 4; ++row) {
    for (int col = kSize / 2 - 4; col <= kSize / 2 + 4; ++col) {
      const glm::vec4 ndc(2.0f * (static_cast<float>(col) + 0.5f) / kSize - 1, 2.0f * (static_cast<float>(row) + 0.5f) / kSize - 1, 1, 1);
      glm::vec4 far = glm::inverse(vp) * ndc;
      const glm::vec3 d = glm::normalize(glm::vec3(far) / far.w - kEye);
      const double r = 1 - test::fresnel_t(std::fabs(d.z), kIor);
      sheet += (1 - r) / (1 + r) / 81.0;
    }
  }
  for (int k = 0; k < 4; ++k) {
    runtime::RuntimeScene scene = *baked;
    Material& m = scene.desc.objects[2].material;
    for (std::size_t c = 0; c < 3; ++c) m.tint[c] = k == 0 ? 0.0f : k == 1 ? static_cast<float>(tint[c]) : 1.0f;
    if (k == 3) m.ior = 1.0f;
    auto r = sample::Renderer::create(scene);
    ASSERT_TRUE(r.ok()) << r.error().message;
    for (int v = 0; v < 2; ++v) {
      runtime::GlassViewOptions o;
      o.method = v == 0 ? runtime::GlassView::kTable : runtime::GlassView::kNearby;
      ASSERT_TRUE((*r)->render(frame(o)).ok());
      const std::vector<float> hdr = (*r)->read_hdr();
      for (int row = kSize / 2 - 4; row <= kSize / 2 + 4; ++row) {
        for (int col = kSize / 2 - 4; col <= kSize / 2 + 4; ++col) {
          const std::size_t i = (static_cast<std::size_t>(kSize - 1 - row) * kSize + col) * 4;
          for (int c = 0; c < 3; ++c) mean[k][v][c] += hdr[i + c] / 81.0;
        }
      }
    }
  }
  for (int v = 0; v < 2; ++v) {
    for (int c = 0; c < 3; ++c) {
      const double seen = (mean[1][v][c] - mean[0][v][c]) / (mean[2][v][c] - mean[0][v][c]);
      const double through = (mean[2][v][c] - mean[0][v][c]) / mean[3][v][c];
      std::printf("[thin pane, %s view] channel %d: floor through it / through the clear pane %.4f (tint %.4f); clear pane / no pane %.4f "
                  "(T_sheet %.4f, %+.2f %%); its reflection %.4f of %.4f\n",
                  v == 0 ? "table" : "nearby", c, seen, tint[c], through, sheet, 100 * (through / sheet - 1), mean[0][v][c], mean[2][v][c]);
      EXPECT_GT(mean[0][v][c], 0.0) << "the sheet reflects the sky";
      EXPECT_NEAR(seen, tint[c], 0.002 * tint[c]);
      EXPECT_NEAR(through, sheet, 0.002 * sheet);
    }
  }
}

// The caller's environment (GlassViewOptions::environment): a black pane
// (tint 0: nothing through it) shows only what it reflects, the sheet's
// 2r / (1 + r) = 1 - T_sheet of the environment in the reflected
// direction; a uniform cube map of colour C gives exactly that times C
// (the flat sky instead is brighter upward). A texture that is not a cube
// map is refused, naming it.
TEST_F(GlassView, APaneReflectsTheCallersEnvironment) {
  nlohmann::json j = slab_scene();
  const auto pane = std::filesystem::temp_directory_path() / "caustix_glass_view_pane.obj";
  std::ofstream(pane) << "v -1 0 1\nv 1 0 1\nv 1 1.4 1\nv -1 1.4 1\nf 1 2 3\nf 1 3 4\n";
  j["objects"][2]["mesh"] = pane.string();
  j["objects"][2]["material"] = {{"transparent", true}, {"ior", kIor}, {"tint", 0.0}};
  const auto baked = test::bake_and_load(test::write_scene(j, "glass_view_environment"));
  ASSERT_TRUE(baked);
  auto r = sample::Renderer::create(*baked);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const float colour[4] = {0.3f, 0.7f, 1.9f, 1.0f};
  GLuint cube = 0, flat = 0;
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &cube);
  glTextureStorage2D(cube, 1, GL_RGBA32F, 1, 1);
  for (int face = 0; face < 6; ++face) glTextureSubImage3D(cube, 0, 0, 0, face, 1, 1, 1, GL_RGBA, GL_FLOAT, colour);
  glCreateTextures(GL_TEXTURE_2D, 1, &flat);
  glTextureStorage2D(flat, 1, GL_RGBA32F, 1, 1);
  runtime::GlassViewOptions o;
  const glm::mat4 vp = glm::perspective(glm::radians(45.0f), 1.0f, 0.05f, 100.0f) * glm::lookAt(kEye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
  for (const auto method : {runtime::GlassView::kTable, runtime::GlassView::kNearby}) {
    o.method = method;
    o.environment = cube;
    ASSERT_TRUE((*r)->render(frame(o)).ok());
    const std::vector<float> hdr = (*r)->read_hdr();
    double seen[3] = {}, reflected = 0;
    for (int row = kSize / 2 - 4; row <= kSize / 2 + 4; ++row) {
      for (int col = kSize / 2 - 4; col <= kSize / 2 + 4; ++col) {
        const glm::vec4 ndc(2.0f * (static_cast<float>(col) + 0.5f) / kSize - 1, 2.0f * (static_cast<float>(row) + 0.5f) / kSize - 1, 1, 1);
        const glm::vec4 far = glm::inverse(vp) * ndc;
        const glm::vec3 d = glm::normalize(glm::vec3(far) / far.w - kEye);
        const double rf = 1 - test::fresnel_t(std::fabs(d.z), kIor);
        reflected += 2 * rf / (1 + rf) / 81.0;
        const std::size_t i = (static_cast<std::size_t>(kSize - 1 - row) * kSize + col) * 4;
        for (int c = 0; c < 3; ++c) seen[c] += hdr[i + c] / 81.0;
      }
    }
    for (int c = 0; c < 3; ++c) {
      std::printf("[environment, %s view] channel %d: %.5f (2r/(1+r) C = %.5f)\n", method == runtime::GlassView::kTable ? "table" : "nearby",
                  c, seen[c], reflected * colour[c]);
      EXPECT_NEAR(seen[c], reflected * colour[c], 0.005 * reflected * colour[c]);
    }
    o.environment = flat;
    const Status refused = (*r)->render(frame(o));
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::kUsage);
    EXPECT_NE(refused.error().message.find("environment " + std::to_string(flat) + " is not a cube-map texture"), std::string::npos)
        << refused.error().message;
  }
  glDeleteTextures(1, &cube);
  glDeleteTextures(1, &flat);
}

}  // namespace
}  // namespace caustix
