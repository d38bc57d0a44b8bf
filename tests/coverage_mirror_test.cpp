// The exact texel coverage that every caustics splat deposits by
// (caustics_coverage.glsl: the area of a triangle inside a texel and that
// part's centroid), run on the GPU and checked against the texel square
// clipped by the triangle in double precision here: on triangles of every
// size, vertices and edges on texel lines or a rounding away from them, and
// far from the map's origin, where a float's spacing is widest.

#include <gtest/gtest.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "caustix_shaders.h"
#include "gl_fixture.h"
#include "gl_objects.h"

namespace caustix {
namespace {

namespace gl = runtime::gl;

struct Vec2 {
  double x, y;
};

struct Triangle {
  std::array<Vec2, 3> q;  // texel coordinates
};

// The shader's coverage in a compute shader: one invocation per (triangle,
// texel). The fragment's position and primitive become plain globals.
constexpr const char* kMain = R"GLSL(
layout(local_size_x = 64) in;
layout(std430, binding = 1) readonly buffer Jobs { vec4 jobs[]; };  // (q0, q1), (q2, texel)
layout(std430, binding = 2) writeonly buffer Out { vec4 results[]; };
uniform uint u_count;
uniform vec2 u_origin;  // added to every coordinate: a texel far across a large map
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  vec4 a = jobs[2u * i], b = jobs[2u * i + 1u];
  v_q0 = a.xy + u_origin;
  v_q1 = a.zw + u_origin;
  v_q2 = b.xy + u_origin;
  g_frag_coord = vec4(b.zw + u_origin + 0.5, 0.0, 1.0);
  float area = texel_coverage();
  results[i] = vec4(area, g_centroid - u_origin, 0.0);
}
)GLSL";

std::string coverage_source() {
  std::string src = shaders::k_caustics_coverage_glsl;
  auto replace = [&](const std::string& from, const std::string& to) {
    for (std::size_t at = src.find(from); at != std::string::npos; at = src.find(from, at + to.size())) src.replace(at, from.size(), to);
  };
  replace("flat in int v_prim;", "int v_prim = 0;");
  replace("gl_FragCoord", "g_frag_coord");
  return std::string("#version 450 core\nvec4 g_frag_coord;\n") + src + kMain;
}

double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

// The texel [tx, tx+1] x [ty, ty+1] clipped by the triangle
// (Sutherland-Hodgman in double): its area and centroid.
struct Exact {
  double area, cx, cy;
};
Exact clip(const Triangle& t, int tx, int ty) {
  std::array<Vec2, 3> tri = t.q;
  if (cross({tri[1].x - tri[0].x, tri[1].y - tri[0].y}, {tri[2].x - tri[0].x, tri[2].y - tri[0].y}) < 0) std::swap(tri[1], tri[2]);
  std::vector<Vec2> poly{{0.0 + tx, 0.0 + ty}, {1.0 + tx, 0.0 + ty}, {1.0 + tx, 1.0 + ty}, {0.0 + tx, 1.0 + ty}};
  for (int e = 0; e < 3 && !poly.empty(); ++e) {
    const Vec2 a = tri[static_cast<std::size_t>(e)], b = tri[static_cast<std::size_t>((e + 1) % 3)];
    const Vec2 d{b.x - a.x, b.y - a.y};
    std::vector<Vec2> next;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 p = poly[i], q = poly[(i + 1) % poly.size()];
      const double sp = cross(d, {p.x - a.x, p.y - a.y}), sq = cross(d, {q.x - a.x, q.y - a.y});
      if (sp >= 0) next.push_back(p);
      if ((sp >= 0) != (sq >= 0)) next.push_back({p.x + (q.x - p.x) * sp / (sp - sq), p.y + (q.y - p.y) * sp / (sp - sq)});
    }
    poly = next;
  }
  double twice = 0, mx = 0, my = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 p = poly[i], q = poly[(i + 1) % poly.size()];
    const double c = cross(p, q);
    twice += c;
    mx += (p.x + q.x) * c;
    my += (p.y + q.y) * c;
  }
  if (twice <= 0) return {0, tx + 0.5, ty + 0.5};
  return {0.5 * twice, mx / (3 * twice), my / (3 * twice)};
}

// Its height under its longest edge, in texels (the shader takes a
// triangle under 1/16 of a texel as a sliver: a line density, not clipped).
double height(const Triangle& t) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec2 a = t.q[static_cast<std::size_t>(k)], b = t.q[static_cast<std::size_t>((k + 1) % 3)];
    longest = std::max(longest, std::hypot(b.x - a.x, b.y - a.y));
  }
  const double twice = std::fabs(cross({t.q[1].x - t.q[0].x, t.q[1].y - t.q[0].y}, {t.q[2].x - t.q[0].x, t.q[2].y - t.q[0].y}));
  return longest > 0 ? twice / longest : 0;
}

class CoverageMirror : public test::GlTest {};

TEST_F(CoverageMirror, AreaAndCentroidInEveryTexelAreTheClippedPolygons) {
  const std::string src = coverage_source();
  auto program = gl::Program::build_compute("coverage_mirror", src.c_str());
  ASSERT_TRUE(program.ok()) << program.error().message;

  // Triangles within 12 texels of the origin: random ones from a tenth of a
  // texel to 10 texels across; ones with vertices on texel corners and lines
  // (edges along texel lines, as flat water over an aligned grid gives);
  // the same moved off those lines by 1e-6 texel either way; thin ones
  // (heights 0.1 to 0.001 texel, the sliver path's).
  std::vector<Triangle> tris;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> at(1.0, 11.0), size(0.1, 10.0), unit(-1.0, 1.0);
  for (int i = 0; i < 60; ++i) {
    const Vec2 c{at(rng), at(rng)};
    const double s = size(rng);
    Triangle t;
    for (Vec2& v : t.q) v = {c.x + s * unit(rng), c.y + s * unit(rng)};
    tris.push_back(t);
  }
  for (double off : {0.0, 1e-6, -1e-6}) {
    tris.push_back({{{{2 + off, 2}, {6, 2 + off}, {2, 6}}}});          // legs along texel lines
    tris.push_back({{{{3, 3 + off}, {3 + off, 8}, {9, 3}}}});          // clockwise
    tris.push_back({{{{1.5, 1.5 + off}, {7.5 + off, 1.5}, {4.5, 9}}}});  // edges through texel centres
    tris.push_back({{{{4, 4}, {5 + off, 4}, {4, 5 + off}}}});          // one texel's half
    tris.push_back({{{{2, 2}, {10, 10 + off}, {2 + off, 10}}}});        // a diagonal through texel corners
  }
  for (double h : {0.1, 0.05, 0.01, 0.001}) {
    tris.push_back({{{{1.3, 2.2}, {10.7, 8.9}, {6.0 - 0.6 * h, 5.55 + 0.8 * h}}}});
  }

  // Far across a large map too: the same triangles at texel 4000.
  for (float origin : {0.0f, 4000.0f}) {
    SCOPED_TRACE("origin " + std::to_string(origin));
    std::vector<float> jobs;
    std::vector<std::array<int, 3>> which;  // triangle, texel x, texel y
    // The triangles as the shader holds them: in float, at the origin.
    std::vector<Triangle> held = tris;
    for (Triangle& t : held) {
      for (Vec2& v : t.q) {
        v = {static_cast<double>(static_cast<float>(v.x) + origin) - origin, static_cast<double>(static_cast<float>(v.y) + origin) - origin};
      }
    }
    for (std::size_t k = 0; k < tris.size(); ++k) {
      const Triangle& t = tris[k];
      double lo[2] = {1e30, 1e30}, hi[2] = {-1e30, -1e30};
      for (const Vec2& v : t.q) {
        lo[0] = std::min(lo[0], v.x), lo[1] = std::min(lo[1], v.y);
        hi[0] = std::max(hi[0], v.x), hi[1] = std::max(hi[1], v.y);
      }
      for (int ty = static_cast<int>(std::floor(lo[1])) - 1; ty <= static_cast<int>(hi[1]) + 1; ++ty) {
        for (int tx = static_cast<int>(std::floor(lo[0])) - 1; tx <= static_cast<int>(hi[0]) + 1; ++tx) {
          for (const Vec2& v : t.q) jobs.insert(jobs.end(), {static_cast<float>(v.x), static_cast<float>(v.y)});
          jobs.insert(jobs.end(), {static_cast<float>(tx), static_cast<float>(ty)});
          which.push_back({static_cast<int>(k), tx, ty});
        }
      }
    }
    gl::Buffer in = gl::make_buffer(), out = gl::make_buffer();
    glNamedBufferStorage(in.get(), static_cast<GLsizeiptr>(jobs.size() * 4), jobs.data(), 0);
    glNamedBufferStorage(out.get(), static_cast<GLsizeiptr>(which.size() * 16), nullptr, 0);
    program->use();
    program->set("u_count", static_cast<unsigned>(which.size()));
    program->set("u_origin", glm::vec2(origin));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, in.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, out.get());
    glDispatchCompute(static_cast<GLuint>((which.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> got(which.size() * 4);
    glGetNamedBufferSubData(out.get(), 0, static_cast<GLsizeiptr>(got.size() * 4), got.data());
    glUseProgram(0);
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

    // What float allows: the shader works relative to the texel's corner
    // (exact: both lie within a factor 2), on coordinates up to 12 texels
    // whose products carry a relative 2^-24 each.
    const double area_tol = 1e-5;
    std::vector<double> sum(tris.size(), 0.0);
    double worst = 0, worst_centroid = 0;
    for (std::size_t i = 0; i < which.size(); ++i) {
      const Triangle& t = held[static_cast<std::size_t>(which[i][0])];
      const float* g = &got[4 * i];
      ASSERT_TRUE(std::isfinite(g[0]) && std::isfinite(g[1]) && std::isfinite(g[2]));
      ASSERT_GE(g[0], 0.0f);
      ASSERT_LE(g[0], 1.0f);
      sum[static_cast<std::size_t>(which[i][0])] += g[0];
      if (height(t) < 0.125) continue;  // a sliver is a line density, not clipped: its sum is checked below
      const Exact e = clip(t, which[i][1], which[i][2]);
      const double d = std::fabs(g[0] - e.area);
      worst = std::max(worst, d);
      EXPECT_LE(d, area_tol) << "triangle " << which[i][0] << " texel " << which[i][1] << "," << which[i][2] << ": " << g[0]
                             << " against " << e.area;
      // The centroid (corner_factor's point) where the part is not a
      // rounding: within 1e-3 texel, or the rounding over the part's area.
      if (e.area > 1e-3) {
        const double dc = std::hypot(g[1] - e.cx, g[2] - e.cy);
        worst_centroid = std::max(worst_centroid, dc);
        EXPECT_LE(dc, 1e-3 + 4.0 * area_tol / e.area) << "triangle " << which[i][0] << " texel " << which[i][1] << "," << which[i][2];
      }
    }
    // Every triangle's texels add up to its area: slivers included, whose
    // tent density integrates to the triangle's area.
    for (std::size_t k = 0; k < tris.size(); ++k) {
      const Triangle& t = held[k];
      const double area = 0.5 * std::fabs(cross({t.q[1].x - t.q[0].x, t.q[1].y - t.q[0].y}, {t.q[2].x - t.q[0].x, t.q[2].y - t.q[0].y}));
      EXPECT_NEAR(sum[k], area, 1e-5 * area + 1e-4) << "triangle " << k;
    }
    std::printf("coverage at origin %.0f: %zu texels, largest area error %.2e (bound %.2e), centroid %.2e texel\n", origin,
                which.size(), worst, area_tol, worst_centroid);
  }
}

}  // namespace
}  // namespace caustix
