// Index grids for media (Pfeuti "Voxelization", "Octree Construction"):
// the voxelised volume is the mesh's, the filter keeps it, the octree's
// nodes hold the index within epsilon, the bake is deterministic, and the
// chunk refuses what it must.

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <atomic>
#include <cmath>
#include <mutex>

#include "caustix/bake/bake.h"
#include "caustix/bake/index_grid.h"
#include "caustix/bake/mesh_import.h"
#include "caustix/formats/scene.h"
#include "scene_fixture.h"

namespace caustix::bake {
namespace {

TriangleMesh sphere() {
  auto m = import_mesh(std::string(CAUSTIX_SOURCE_DIR) + "/assets/meshes/sphere.obj");
  EXPECT_TRUE(m.ok()) << m.error().message;
  return m.ok() ? m->mesh : TriangleMesh{};
}

// The polyhedron's volume (divergence theorem).
double mesh_volume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) {
    const auto& a = m.positions[t[0]];
    const auto& b = m.positions[t[1]];
    const auto& c = m.positions[t[2]];
    v += (double{a[0]} * (double{b[1]} * c[2] - double{b[2]} * c[1]) - double{a[1]} * (double{b[0]} * c[2] - double{b[2]} * c[0]) +
          double{a[2]} * (double{b[0]} * c[1] - double{b[1]} * c[0])) / 6;
  }
  return v;
}

double grid_volume(const IndexGrid& g) {
  double sum = 0;
  for (std::uint16_t c : g.coverage) sum += c / 65535.0;
  return sum * double{g.voxel} * g.voxel * g.voxel;
}

TEST(IndexGrid, VoxelisedVolumeIsTheMeshsAndTheFilterKeepsIt) {
  const TriangleMesh m = sphere();
  const double exact = mesh_volume(m);
  IndexGridOptions sharp;
  sharp.blur = 0;
  const IndexGrid a = voxelize_index(0, m, 1.5f, 1.0f, sharp);
  const IndexGrid b = voxelize_index(0, m, 1.5f, 1.0f, IndexGridOptions{});
  // Exact along x, 4 x 4 rows per voxel in y and z: the volume within 0.1 %.
  EXPECT_NEAR(grid_volume(a), exact, 1e-3 * exact);
  // The normalised Gaussian moves coverage, it does not make or lose any
  // (the grid is padded past its tail); quantisation costs < 1e-5 a voxel.
  EXPECT_NEAR(grid_volume(b), grid_volume(a), 2e-4 * exact);
  // Inside, the glass's index; in the corners, the surrounding one; a
  // filtered surface voxel between.
  const std::uint32_t c = a.size[0] / 2;
  EXPECT_FLOAT_EQ(b.ior_at(b.index(c, c, c)), 1.5f);
  EXPECT_FLOAT_EQ(b.ior_at(0), 1.0f);
  int grey = 0;
  for (std::size_t v = 0; v < b.voxels(); ++v) grey += b.coverage[v] > 0 && b.coverage[v] < 65535;
  EXPECT_GT(grey, 0);
  ::testing::Test::RecordProperty("sphere_volume_error", std::to_string(grid_volume(a) / exact - 1));
}

// Every voxel's octree node (the aligned cube of 2^level voxels around it,
// cells past the grid counting as outside) holds the index within epsilon,
// and no node could be doubled: checked by brute force on a coarse grid.
TEST(IndexGrid, OctreeNodesHoldTheIndexWithinEpsilon) {
  const TriangleMesh m = sphere();
  for (float eps : {0.0f, 0.01f, 0.1f}) {
    IndexGridOptions o;
    o.resolution = 24;
    o.epsilon = eps;
    const IndexGrid g = voxelize_index(0, m, 1.5f, 1.0f, o);
    auto range = [&](std::uint32_t i0, std::uint32_t j0, std::uint32_t k0, std::uint32_t w) {
      float lo = 1e9f, hi = -1e9f;
      for (std::uint32_t k = k0; k < k0 + w; ++k) {
        for (std::uint32_t j = j0; j < j0 + w; ++j) {
          for (std::uint32_t i = i0; i < i0 + w; ++i) {
            const bool in = i < g.size[0] && j < g.size[1] && k < g.size[2];
            const float n = in ? g.ior_at(g.index(i, j, k)) : g.ior_outside;
            lo = std::min(lo, n);
            hi = std::max(hi, n);
          }
        }
      }
      return hi - lo;
    };
    double steps = 0;
    for (std::uint32_t k = 0; k < g.size[2]; ++k) {
      for (std::uint32_t j = 0; j < g.size[1]; ++j) {
        for (std::uint32_t i = 0; i < g.size[0]; ++i) {
          const std::uint32_t lv = g.level[g.index(i, j, k)], w = 1u << lv;
          steps += w;
          if (lv > 0) {
            ASSERT_LE(range(i & ~(w - 1), j & ~(w - 1), k & ~(w - 1), w), eps + 1e-6f) << i << "," << j << "," << k;
          }
        }
      }
    }
    // Far outside the sphere the index is constant: the corner voxel sits
    // in a node wider than one voxel at any epsilon.
    EXPECT_GT(g.level[0], 0) << "eps " << eps;
    ::testing::Test::RecordProperty("mean_step_eps_" + std::to_string(eps), std::to_string(steps / double(g.voxels())));
  }
}

TEST(IndexGrid, LargerEpsilonNeverShrinksANode) {
  const TriangleMesh m = sphere();
  IndexGridOptions o;
  o.resolution = 32;
  o.epsilon = 0.001f;
  const IndexGrid fine = voxelize_index(0, m, 1.5f, 1.0f, o);
  o.epsilon = 0.1f;
  const IndexGrid coarse = voxelize_index(0, m, 1.5f, 1.0f, o);
  std::size_t wider = 0;
  for (std::size_t v = 0; v < fine.voxels(); ++v) {
    ASSERT_GE(coarse.level[v], fine.level[v]) << v;
    wider += coarse.level[v] > fine.level[v];
  }
  EXPECT_GT(wider, 0u);
}

TEST(IndexGrid, SameBytesWhateverTheThreadCount) {
  const TriangleMesh m = sphere();
  std::vector<std::uint8_t> one;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = encode_index_grid(voxelize_index(3, m, 1.5f, 1.33f, IndexGridOptions{}));
  }
  EXPECT_EQ(one, encode_index_grid(voxelize_index(3, m, 1.5f, 1.33f, IndexGridOptions{})));
}

// One object's grid reports its progress as it goes (a fine
// grid of one object takes seconds; the bar must move and the budgets
// must be able to stop it), and reporting changes nothing in it.
TEST(IndexGrid, ProgressWithinOneObjectAndAStop) {
  const TriangleMesh m = sphere();
  IndexGridOptions o;
  o.resolution = 96;
  std::mutex mutex;
  std::vector<double> said;
  const IndexGrid g = voxelize_index(0, m, 1.5f, 1.0f, o, [&](double f) {
    const std::lock_guard<std::mutex> lock(mutex);
    said.push_back(f);
    return true;
  });
  EXPECT_EQ(encode_index_grid(g), encode_index_grid(voxelize_index(0, m, 1.5f, 1.0f, o)));
  ASSERT_FALSE(said.empty());
  std::size_t rows = 0, blur = 0, octree = 0;
  for (const double f : said) {
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
    (f <= 0.22 ? rows : f <= 0.72 ? blur : octree) += 1;
  }
  EXPECT_GE(rows, 50u) << "about every 1 % of the voxel rows";
  EXPECT_EQ(blur, 3u) << "after each blur pass";
  EXPECT_GE(octree, 3u) << "after each octree level";
  // A stop in the rows leaves them undone: the coverage is short of the volume.
  std::atomic<int> calls{0};
  const IndexGrid cut = voxelize_index(0, m, 1.5f, 1.0f, o, [&](double) { return ++calls < 5; });
  EXPECT_LT(grid_volume(cut), 0.5 * grid_volume(g));
  EXPECT_LT(calls.load(), 30) << "no more progress after the stop, but for rows already under way";
}

// The bake writes grids only for scenes that scatter, and refuses a grid
// over the memory limit with the object, the size and what to lower.
TEST(IndexGrid, BakedOnlyWhereSomethingScattersAndBounded) {
  auto baked = bake_scene(test::kScenes + "fog_ball.json", BakeOptions{});
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  auto c = cxb::read_container(baked->cxb.data(), baked->cxb.size());
  ASSERT_TRUE(c.ok());
  ASSERT_EQ(c->find(cxb::kTagIndexGrid).size(), 1u);
  auto d = decode_scene(*c);
  ASSERT_TRUE(d.ok()) << d.error().message;
  ASSERT_EQ(d->index_grids.size(), 1u);
  EXPECT_EQ(d->index_grids[0].object, 1u);
  EXPECT_EQ(d->index_grids[0].ior_inside, 1.5f);
  EXPECT_EQ(d->index_grids[0].ior_outside, 1.0f);
  ASSERT_EQ(baked->index_grids.size(), 1u);
  EXPECT_GT(baked->index_grids[0].mean_step, 1.0);

  auto plain = bake_scene(test::kScenes + "glass_ball.json", BakeOptions{});
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  auto pc = cxb::read_container(plain->cxb.data(), plain->cxb.size());
  ASSERT_TRUE(pc.ok());
  EXPECT_TRUE(pc->find(cxb::kTagIndexGrid).empty());
  EXPECT_TRUE(pc->find(cxb::kTagMedia).empty());

  BakeOptions huge;
  huge.index_grid.resolution = 1024;
  auto refused = bake_scene(test::kScenes + "fog_ball.json", huge);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, ErrorCode::kInput);
  EXPECT_NE(refused.error().message.find("'ball': its index grid would hold"), std::string::npos) << refused.error().message;
  EXPECT_NE(refused.error().message.find("lower --volume-res"), std::string::npos) << refused.error().message;
}

TEST(IndexGrid, ChunkRefusesWhatItMust) {
  auto baked = bake_scene(test::kScenes + "fog_ball.json", BakeOptions{});
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  const SceneDesc& s = baked->scene;
  IndexGrid g;
  g.object = 1;
  g.size = {4, 4, 4};
  g.voxel = 0.1f;
  g.coverage.assign(64, 1000);
  g.level.assign(64, 0);
  ASSERT_TRUE(decode_index_grid(encode_index_grid(g), s).ok());
  auto bad = g;
  bad.level[5] = 16;
  auto r = decode_index_grid(encode_index_grid(bad), s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("voxel 5 has octree level 16"), std::string::npos) << r.error().message;
  bad = g;
  bad.object = 0;  // the floor
  r = decode_index_grid(encode_index_grid(bad), s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("not a transparent object"), std::string::npos) << r.error().message;
  bad = g;
  bad.ior_inside = 1.4f;
  EXPECT_FALSE(decode_index_grid(encode_index_grid(bad), s).ok());
  // A header claiming 2^30 voxels is refused before anything is allocated.
  auto bytes = encode_index_grid(g);
  const std::uint32_t big = 1024;
  for (int k = 0; k < 3; ++k) std::memcpy(bytes.data() + 4 + 4 * k, &big, 4);
  r = decode_index_grid(bytes, s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("above the limit"), std::string::npos) << r.error().message;
  // Truncated: the chunk and the field are named.
  bytes = encode_index_grid(g);
  bytes.resize(20);
  r = decode_index_grid(bytes, s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("chunk 'IGRD'"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace caustix::bake
