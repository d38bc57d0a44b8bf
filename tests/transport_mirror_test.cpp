// The light-transport look-up exists twice: caustix::lookup() in C++
// (formats/src/light_transport.cpp, what the baker's checks and the tests
// use) and ltt_lookup() in GLSL (runtime/shaders/transport.glsl, what the
// glass passes run). This test runs the GLSL one in a compute shader over
// the same baked tables and queries and asks the two to agree on every
// branch: bicubic cells, mixed cells fitted per path class, cells cut at a
// stored switch (LTTW), totally reflected classes, trapped directions and
// directions below the horizon.

#include <gtest/gtest.h>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bake_fixture.h"
#include "caustix/formats/light_transport.h"
#include "gl_objects.h"
#include "caustix_shaders.h"
#include "gl_fixture.h"
#include "scene_fixture.h"

namespace caustix {
namespace {

namespace gl = runtime::gl;

// Queries: (n.xyz, vertex as bits), (to_light.xyz, 0); results: (exit,
// transmittance), (dir, path), (leaves, bounces, 0, 0).
constexpr const char* kMain = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 2) readonly buffer Queries { vec4 queries[]; };
layout(std430, binding = 3) writeonly buffer Results { vec4 results[]; };
uniform uint u_count;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  vec4 a = queries[2u * i], b = queries[2u * i + 1u];
  Transport t = ltt_lookup(floatBitsToUint(a.w), a.xyz, b.xyz);
  results[3u * i] = vec4(t.exit, t.transmittance);
  results[3u * i + 1u] = vec4(t.dir, t.path);
  results[3u * i + 2u] = vec4(t.leaves ? 1.0 : 0.0, float(t.bounces), 0.0, 0.0);
}
)";

struct Query {
  std::uint32_t vertex;
  std::array<float, 3> n, to_light;
};

struct Got {
  std::array<double, 3> exit, dir;
  double transmittance, path;
  bool leaves;
  std::uint32_t bounces;
};

// Which of lookup()'s branches a query takes, read from the table's
// entries around it (the same grid mapping as lookup()).
enum Branch { kBicubic, kMixed, kMixedWithSwitch, kNoneLeaves, kBranches };
const char* const kBranchNames[] = {"bicubic", "mixed cell", "mixed cell with a stored switch", "no corner leaves"};

Branch branch_of(const LightTransportTable& t, const Query& q) {
  const Dir3 n{q.n[0], q.n[1], q.n[2]}, l{q.to_light[0], q.to_light[1], q.to_light[2]};
  Dir3 tb, bb;
  tangent_frame(n, tb, bb);
  auto dot = [](const Dir3& a, const Dir3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  const auto st = hemi_oct_encode({dot(l, tb), dot(l, bb), std::max(dot(l, n), 0.0)});
  const double r1 = t.resolution - 1;
  const auto x0 = static_cast<std::uint32_t>(std::min(std::floor(std::clamp((st[0] + 1) * 0.5 * r1, 0.0, r1)), r1 - 1));
  const auto y0 = static_cast<std::uint32_t>(std::min(std::floor(std::clamp((st[1] + 1) * 0.5 * r1, 0.0, r1)), r1 - 1));
  std::array<TransportEntry, 4> c;
  bool any = false, alike = true;
  for (std::uint32_t k = 0; k < 4; ++k) {
    c[k] = t.load(t.entry_index(q.vertex, y0 + (k >> 1), x0 + (k & 1)));
    any = any || c[k].status == TransportStatus::kLeaves;
    alike = alike && leave_alike(c[0], c[k]);
  }
  if (!any) return kNoneLeaves;
  if (alike) return kBicubic;
  if (t.switches.empty()) return kMixed;
  // The cell's four edges: from (x0, y0) and (x0, y0 + 1) along the
  // columns, from (x0, y0) and (x0 + 1, y0) along the rows.
  const std::size_t e00 = t.entry_index(q.vertex, y0, x0), e01 = t.entry_index(q.vertex, y0 + 1, x0),
                    e10 = t.entry_index(q.vertex, y0, x0 + 1);
  const bool stored = t.switches[2 * e00] || t.switches[2 * e01] || t.switches[2 * e00 + 1] || t.switches[2 * e10 + 1];
  return stored ? kMixedWithSwitch : kMixed;
}

std::vector<Got> run_on_gpu(const gl::Program& program, const LightTransportTable& t, const std::vector<Query>& queries) {
  // The table as the glass passes upload it: the entries, then the switch
  // bytes padded to a word (their first word is u_ltt_switch_base).
  std::vector<std::uint32_t> words = t.words;
  std::uint32_t switch_base = 0;
  if (!t.switches.empty()) {
    switch_base = static_cast<std::uint32_t>(words.size());
    words.resize(words.size() + (t.switches.size() + 3) / 4, 0);
    std::memcpy(words.data() + switch_base, t.switches.data(), t.switches.size());
  }
  std::vector<float> in;
  for (const Query& q : queries) {
    float bits = 0;
    std::memcpy(&bits, &q.vertex, 4);
    in.insert(in.end(), {q.n[0], q.n[1], q.n[2], bits, q.to_light[0], q.to_light[1], q.to_light[2], 0.0f});
  }
  gl::Buffer table = gl::make_buffer(), qbuf = gl::make_buffer(), rbuf = gl::make_buffer();
  glNamedBufferStorage(table.get(), static_cast<GLsizeiptr>(words.size() * 4), words.data(), 0);
  glNamedBufferStorage(qbuf.get(), static_cast<GLsizeiptr>(in.size() * 4), in.data(), 0);
  glNamedBufferStorage(rbuf.get(), static_cast<GLsizeiptr>(queries.size() * 48), nullptr, 0);
  program.use();
  program.set("u_ltt_resolution", static_cast<int>(t.resolution));
  program.set("u_ltt_exit_min", glm::vec3(t.exit_min[0], t.exit_min[1], t.exit_min[2]));
  program.set("u_ltt_exit_max", glm::vec3(t.exit_max[0], t.exit_max[1], t.exit_max[2]));
  program.set("u_ltt_max_path", t.max_path);
  program.set("u_ltt_switch_base", switch_base);
  program.set("u_count", static_cast<unsigned>(queries.size()));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, table.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, qbuf.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, rbuf.get());
  glDispatchCompute(static_cast<GLuint>((queries.size() + 63) / 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<float> out(queries.size() * 12);
  glGetNamedBufferSubData(rbuf.get(), 0, static_cast<GLsizeiptr>(out.size() * 4), out.data());
  glUseProgram(0);
  std::vector<Got> got(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const float* r = &out[12 * i];
    got[i] = Got{{r[0], r[1], r[2]}, {r[4], r[5], r[6]}, r[3], r[7], r[8] > 0.5f, static_cast<std::uint32_t>(r[9])};
  }
  return got;
}

// Whether the GPU's answer `g` is the C++ one's `e`, within what float
// arithmetic moves: the direction by 1e-4 rad, the transmittance by 1e-4,
// the exit and the path by 2e-4 of their quantisation ranges (the table's
// exit box, its longest path). The last is the loosest: in a mixed cell
// the class's plane is a weighted least-squares fit, which the GPU solves
// in float; over the prism's many-times-reflected classes it moves the
// path by up to 1.1e-4 of its range (3.2e-4 m of 2.8 m), a dozen of the
// table's own quantisation steps, and the exit by 6e-5 m.
bool same(const Got& g, const TransportEntry& e, double box, double max_path) {
  const bool leaves = e.status == TransportStatus::kLeaves;
  if (g.leaves != leaves) return false;
  if (!leaves) return g.transmittance == 0.0;
  if (g.bounces != e.bounces) return false;
  double dexit = 0, ddir = 0;
  for (int a = 0; a < 3; ++a) {
    dexit = std::max(dexit, std::fabs(g.exit[a] - e.exit[a]));
    ddir = std::max(ddir, std::fabs(g.dir[a] - e.direction[a]));
  }
  return dexit <= 2e-4 * box && ddir <= 1e-4 && std::fabs(g.transmittance - e.transmittance) <= 1e-4 &&
         std::fabs(g.path - e.path) <= 2e-4 * max_path;
}

class TransportMirror : public test::GlTest {};

TEST_F(TransportMirror, GpuLookUpEqualsTheCpusOnEveryBranch) {
  const std::string src = std::string("#version 450 core\n") + shaders::k_transport_glsl + kMain;
  auto program = gl::Program::build_compute("transport_mirror", src.c_str());
  ASSERT_TRUE(program.ok()) << program.error().message;
  std::array<std::size_t, kBranches> seen{};
  std::size_t reflected = 0, below = 0, total = 0;
  // The prism: flat faces, total internal reflection on its slope, stored
  // switches. The ball: a smooth table, trapped at its horizon row.
  for (const char* name : {"prism", "glass_ball"}) {
    SCOPED_TRACE(name);
    nlohmann::json j = test::canonical_scene(name);
    for (auto& o : j["objects"]) {
      if (o.contains("material")) o["material"].erase("dispersion");
    }
    bake::BakeOptions opt;
    opt.transport.wavelengths = 0;
    auto loaded = test::bake_and_load(test::write_scene(j, "transport_mirror"), opt);
    ASSERT_TRUE(loaded);
    ASSERT_FALSE(loaded->transport_tables.empty());
    const LightTransportTable& t = loaded->transport_tables[0];
    const TriangleMesh& mesh = loaded->meshes[loaded->desc.objects[t.object].mesh_index];
    if (std::string(name) == "prism") EXPECT_FALSE(t.switches.empty()) << "the prism's table stores its switches";
    double box = 0;
    for (int a = 0; a < 3; ++a) box = std::max(box, static_cast<double>(t.exit_max[a] - t.exit_min[a]));

    // Random vertices, directions over the whole sphere around each normal
    // (a fifth below the horizon, which lookup() clamps onto it), and light
    // straight down at every vertex (the canonical scenes' sun).
    std::mt19937 rng(11);
    std::normal_distribution<float> gauss;
    std::vector<Query> queries;
    for (std::uint32_t v = 0; v < t.vertex_count; ++v) {
      const auto& nv = mesh.normals[v];
      const float len = std::sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
      queries.push_back({v, {nv[0] / len, nv[1] / len, nv[2] / len}, {0.0f, 1.0f, 0.0f}});
      for (int k = 0; k < 6; ++k) {
        std::array<float, 3> d{gauss(rng), gauss(rng), gauss(rng)};
        const float dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (float& c : d) c /= dl;
        const float facing = d[0] * queries.back().n[0] + d[1] * queries.back().n[1] + d[2] * queries.back().n[2];
        if (facing < 0 && k % 5 != 0) {
          for (float& c : d) c = -c;  // most above the horizon
        }
        queries.push_back({v, queries.back().n, d});
      }
    }
    const std::vector<Got> got = run_on_gpu(*program, t, queries);
    std::size_t agree = 0, ties = 0;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const Query& q = queries[i];
      const Dir3 n{q.n[0], q.n[1], q.n[2]}, l{q.to_light[0], q.to_light[1], q.to_light[2]};
      const TransportEntry want = lookup(t, q.vertex, n, l);
      ++seen[branch_of(t, q)];
      reflected += want.status == TransportStatus::kLeaves && want.bounces > 0 ? 1 : 0;
      below += n[0] * l[0] + n[1] * l[1] + n[2] * l[2] < 0 ? 1 : 0;
      if (same(got[i], want, box, t.max_path)) {
        ++agree;
        continue;
      }
      // On or below the horizon both snap onto the grid's border: no excuse.
      EXPECT_GE(n[0] * l[0] + n[1] * l[1] + n[2] * l[2], 0.0) << "vertex " << q.vertex << ": a query below the horizon disagrees";
      // A disagreement must sit on a discontinuity of lookup() itself,
      // where float rounding picks the other side: a turn of the query by
      // 1e-5 rad gives the GPU's answer.
      Dir3 tb, bb;
      tangent_frame(l, tb, bb);
      bool tie = false;
      for (int s = 0; s < 4 && !tie; ++s) {
        const Dir3& axis = s < 2 ? tb : bb;
        const double h = s % 2 ? 1e-5 : -1e-5;
        const Dir3 turned{l[0] + h * axis[0], l[1] + h * axis[1], l[2] + h * axis[2]};
        tie = same(got[i], lookup(t, q.vertex, n, turned), box, t.max_path);
      }
      ties += tie ? 1 : 0;
      EXPECT_TRUE(tie) << "vertex " << q.vertex << ", to light (" << l[0] << ", " << l[1] << ", " << l[2] << "): GPU exit ("
                       << got[i].exit[0] << ", " << got[i].exit[1] << ", " << got[i].exit[2] << ") class " << got[i].bounces
                       << " leaves " << got[i].leaves << ", C++ (" << want.exit[0] << ", " << want.exit[1] << ", " << want.exit[2]
                       << ") class " << int(want.bounces) << " leaves " << (want.status == TransportStatus::kLeaves);
    }
    total += queries.size();
    std::printf("[%s] %zu queries: %zu agree, %zu at a discontinuity where rounding picks the other side\n", name, queries.size(),
                agree, ties);
    EXPECT_GE(agree, queries.size() * 99 / 100);
  }
  for (int b = 0; b < kBranches; ++b) std::printf("  %s: %zu queries\n", kBranchNames[b], seen[static_cast<std::size_t>(b)]);
  std::printf("  totally reflected classes: %zu, below the horizon: %zu of %zu\n", reflected, below, total);
  for (int b = 0; b < kBranches; ++b) EXPECT_GT(seen[static_cast<std::size_t>(b)], 20u) << kBranchNames[b];
  EXPECT_GT(reflected, 100u);
  EXPECT_GT(below, 100u);
}

}  // namespace
}  // namespace caustix
