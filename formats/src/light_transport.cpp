// Light-transport tables: quantisation, direction maps, look-up and the LTTB
// payload (formats/SPEC.md).

#include "caustix/formats/light_transport.h"

#include <algorithm>
#include <cmath>

#include "bytes.h"
#include "caustix/formats/scene.h"
#include "caustix/formats/spectrum.h"
#include "chunk_decoder.h"
#include "zstd_frame.h"

namespace caustix {
namespace {

using cxb::detail::ByteWriter;
using cxb::detail::ChunkDecoder;
using cxb::detail::write_zstd_frame;
using cxb::detail::zstd_decompress_exact;

constexpr double kQ = 65535.0;
// zstd levels, from the sweep in docs/results/ltt_zstd_levels.csv
// (scripts/bench-ltt-zstd.sh, balanced): level 6, and level 1 for a table
// over 64 MiB raw. Level 6 compresses at 70-270 MB/s; level 1 at 420-1170
// MB/s. Against level 6, level 1 is 13.1 % larger on glass_ball, 3.6 % on
// prism and 11 % on an 8 k-vertex ball at fast, but 0.7 % smaller on
// glass_teapot and 0.5 % on an 82 k-triangle scan, whose 262 MB table took
// 3.7 s at level 6 and takes 0.62 s at level 1. A choice by size keeps
// every table under 64 MiB as it was, and caps a large table's write at
// about a quarter of a second per 100 MB.
constexpr int kZstdLevel = 6, kZstdLargeLevel = 1;
constexpr std::size_t kZstdLargeBytes = std::size_t{64} << 20;
constexpr std::size_t kMaxRatio = 4096;

// x in [lo, hi] to 16 bits, rounded to a multiple of 2^(16 - bits)
// (65535 itself stays representable).
std::uint16_t quantise(double x, double lo, double hi, std::uint32_t bits) {
  const double t = hi > lo ? (x - lo) / (hi - lo) : 0.0;
  const double step = static_cast<double>(1u << (16 - bits));
  return static_cast<std::uint16_t>(std::min(kQ, step * std::round(std::clamp(t, 0.0, 1.0) * kQ / step)));
}
double dequantise(std::uint32_t q, double lo, double hi) { return lo + (hi - lo) * (q / kQ); }

double dot3(const Dir3& a, const Dir3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Dir3 normalized(const Dir3& v) {
  const double l = std::sqrt(dot3(v, v));
  return l > 0 ? Dir3{v[0] / l, v[1] / l, v[2] / l} : Dir3{0, 0, 1};
}
double sign_not_zero(double x) { return x >= 0 ? 1.0 : -1.0; }

// Records as 8 u16 fields; the payload stores field-major planes, each
// delta-coded along the directions of a vertex (neighbouring directions
// have close exit points and directions), split into low and high bytes.
constexpr std::size_t kFields = 8;

std::vector<std::uint8_t> filter(const LightTransportTable& t) {
  const std::size_t n = t.words.size() / 4, per_vertex = std::size_t{t.resolution} * t.resolution;
  std::vector<std::uint8_t> raw(n * kFields * 2);
  for (std::size_t f = 0; f < kFields; ++f) {
    std::uint8_t* lo = raw.data() + f * 2 * n;
    std::uint8_t* hi = lo + n;
    std::uint16_t prev = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const auto v = static_cast<std::uint16_t>(t.words[4 * i + f / 2] >> (16 * (f % 2)));
      if (i % per_vertex == 0) prev = 0;
      const auto d = static_cast<std::uint16_t>(v - prev);
      prev = v;
      lo[i] = static_cast<std::uint8_t>(d & 0xFF);
      hi[i] = static_cast<std::uint8_t>(d >> 8);
    }
  }
  return raw;
}

void unfilter(const std::vector<std::uint8_t>& raw, LightTransportTable& t) {
  const std::size_t n = raw.size() / (kFields * 2), per_vertex = std::size_t{t.resolution} * t.resolution;
  t.words.assign(n * 4, 0);
  for (std::size_t f = 0; f < kFields; ++f) {
    const std::uint8_t* lo = raw.data() + f * 2 * n;
    const std::uint8_t* hi = lo + n;
    std::uint16_t prev = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (i % per_vertex == 0) prev = 0;
      prev = static_cast<std::uint16_t>(prev + (lo[i] | (hi[i] << 8)));
      t.words[4 * i + f / 2] |= std::uint32_t{prev} << (16 * (f % 2));
    }
  }
}

}  // namespace

void tangent_frame(const Dir3& n, Dir3& t, Dir3& b) {
  const double s = std::copysign(1.0, n[2]);
  const double a = -1.0 / (s + n[2]);
  const double c = n[0] * n[1] * a;
  t = {1.0 + s * n[0] * n[0] * a, s * c, -s * n[0]};
  b = {c, s + n[1] * n[1] * a, -n[1]};
}

std::array<double, 2> hemi_oct_encode(const Dir3& d) {
  const double z = std::max(d[2], 0.0);
  const double l1 = std::fabs(d[0]) + std::fabs(d[1]) + z;
  const double px = l1 > 0 ? d[0] / l1 : 0.0, py = l1 > 0 ? d[1] / l1 : 0.0;
  return {px + py, px - py};
}

Dir3 hemi_oct_decode(double s, double t) {
  const double px = 0.5 * (s + t), py = 0.5 * (s - t);
  return normalized({px, py, 1.0 - std::fabs(px) - std::fabs(py)});
}

std::array<double, 2> oct_encode(const Dir3& d) {
  const double l1 = std::fabs(d[0]) + std::fabs(d[1]) + std::fabs(d[2]);
  double u = d[0] / l1, v = d[1] / l1;
  if (d[2] < 0) {
    const double u0 = u;
    u = (1.0 - std::fabs(v)) * sign_not_zero(u0);
    v = (1.0 - std::fabs(u0)) * sign_not_zero(v);
  }
  return {u, v};
}

Dir3 oct_decode(double u, double v) {
  Dir3 d{u, v, 1.0 - std::fabs(u) - std::fabs(v)};
  if (d[2] < 0) {
    const double x = d[0];
    d[0] = (1.0 - std::fabs(d[1])) * sign_not_zero(x);
    d[1] = (1.0 - std::fabs(x)) * sign_not_zero(d[1]);
  }
  return normalized(d);
}

Dir3 grid_direction(const Dir3& n, std::uint32_t r, std::uint32_t row, std::uint32_t col) {
  return grid_direction_at(n, r, row, col);
}

Dir3 grid_direction_at(const Dir3& n, std::uint32_t r, double row, double col) {
  const double step = 2.0 / (r - 1);
  const Dir3 l = hemi_oct_decode(-1.0 + col * step, -1.0 + row * step);
  Dir3 t, b;
  tangent_frame(n, t, b);
  return normalized({l[0] * t[0] + l[1] * b[0] + l[2] * n[0], l[0] * t[1] + l[1] * b[1] + l[2] * n[1],
                     l[0] * t[2] + l[1] * b[2] + l[2] * n[2]});
}

void LightTransportTable::store(std::size_t i, const TransportEntry& e) {
  std::uint32_t* w = words.data() + 4 * i;
  if (e.status != TransportStatus::kLeaves) {
    w[0] = w[1] = w[2] = 0;
    w[3] = std::uint32_t{static_cast<std::uint8_t>(e.status)} << 16;
    return;
  }
  const std::uint32_t b = precision_bits;
  const std::uint32_t ex = quantise(e.exit[0], exit_min[0], exit_max[0], b);
  const std::uint32_t ey = quantise(e.exit[1], exit_min[1], exit_max[1], b);
  const std::uint32_t ez = quantise(e.exit[2], exit_min[2], exit_max[2], b);
  const auto o = oct_encode(e.direction);
  w[0] = ex | (ey << 16);
  w[1] = ez | (std::uint32_t{quantise(e.transmittance, 0.0, 1.0, b)} << 16);
  w[2] = std::uint32_t{quantise(o[0], -1.0, 1.0, b)} | (std::uint32_t{quantise(o[1], -1.0, 1.0, b)} << 16);
  w[3] = std::uint32_t{quantise(e.path, 0.0, max_path, b)} | (std::uint32_t{e.bounces} << 24);
}

TransportEntry LightTransportTable::load(std::size_t i) const {
  const std::uint32_t* w = words.data() + 4 * i;
  TransportEntry e;
  e.status = static_cast<TransportStatus>((w[3] >> 16) & 0xFF);
  e.bounces = static_cast<std::uint8_t>(w[3] >> 24);
  if (e.status != TransportStatus::kLeaves) return e;
  e.exit = {dequantise(w[0] & 0xFFFF, exit_min[0], exit_max[0]), dequantise(w[0] >> 16, exit_min[1], exit_max[1]),
            dequantise(w[1] & 0xFFFF, exit_min[2], exit_max[2])};
  e.transmittance = dequantise(w[1] >> 16, 0.0, 1.0);
  e.direction = oct_decode(dequantise(w[2] & 0xFFFF, -1.0, 1.0), dequantise(w[2] >> 16, -1.0, 1.0));
  e.path = dequantise(w[3] & 0xFFFF, 0.0, max_path);
  return e;
}

double LightTransportTable::position_error_bound() const {
  double extent = 0;
  for (std::size_t k = 0; k < 3; ++k) extent = std::max(extent, double{exit_max[k]} - exit_min[k]);
  return 0.5 * extent * (1u << (16 - precision_bits)) / kQ;
}

double LightTransportTable::direction_error_bound() const {
  // Half a quantisation step, h = 2^(16 - b) / 65535, in each octahedral
  // coordinate: an (u, v) error of length at most sqrt(2) h. The largest
  // angle per unit (u, v) length is at the face centre p = (1, 1, 1) / 3
  // along the diagonal: (u, v) += (h, h) moves p by (h, h, -2h), sqrt(3)
  // times as long and perpendicular to p, and normalising divides by
  // |p| = 1 / sqrt(3): a stretch of 3 (checked numerically over the whole
  // map). So the angle is below 3 sqrt(2) h radians.
  return 3.0 * std::sqrt(2.0) * (1u << (16 - precision_bits)) / kQ;
}

const char* to_string(Interpolation mode) { return mode == Interpolation::kBicubic ? "bicubic" : "bilinear"; }

namespace {

// Catmull-Rom weights of the samples at x0 - 1 .. x0 + 2 for the fraction
// a in [0, 1]. An outer sample that is missing (outside the grid, or not
// usable: `use_lo` / `use_hi` false) is replaced by the linear
// extrapolation of the two inner ones, its weight folded onto them.
std::array<double, 4> catmull_rom(double a, bool use_lo, bool use_hi) {
  const double a2 = a * a, a3 = a2 * a;
  std::array<double, 4> w{0.5 * (-a3 + 2 * a2 - a), 0.5 * (3 * a3 - 5 * a2 + 2), 0.5 * (-3 * a3 + 4 * a2 + a),
                          0.5 * (a3 - a2)};
  if (!use_lo) {
    w[1] += 2 * w[0];
    w[2] -= w[0];
    w[0] = 0;
  }
  if (!use_hi) {
    w[2] += 2 * w[3];
    w[1] -= w[3];
    w[3] = 0;
  }
  return w;
}


// Where the inner 2 x 2 of the bicubic stencil does not leave alike (a
// jump of the transport inside the cell), the value at the query (ax, ay)
// of the plane a + b x + c y fitted by weighted least squares to the
// stencil's entries that leave alike with entry `heavy` (x, y their grid
// offsets from the query, weights 1 / (1/4 + x^2 + y^2)): linear
// extrapolation of that path class up to the query instead of its nearest
// corners' mean, which is off by the transport's gradient times up to a
// cell (the prism's vertex 6 cm from its switch between the direct and
// the totally reflected exit landed 3.1 cm off the floor, docs/glass-tables.md).
// The slopes are held near 0 where the entries do not fix them (all on a
// line: constant across it). Writes each entry's weight (summing to 1);
// false where no entry leaves alike with `heavy` (never for a leaving one).
bool linear_fit_weights(const std::array<TransportEntry, 16>& e, std::uint32_t heavy, double ax, double ay,
                        std::array<double, 16>& lambda) {
  std::array<double, 16> wk{};
  std::array<double, 6> m{};  // sum w [1 x y]^T [1 x y]: 00 01 02 11 12 22
  for (std::uint32_t k = 0; k < 16; ++k) {
    if (!leave_alike(e[k], e[heavy])) continue;
    const double x = double(k & 3) - 1 - ax, y = double(k >> 2) - 1 - ay;
    wk[k] = 1 / (0.25 + x * x + y * y);
    m[0] += wk[k];
    m[1] += wk[k] * x;
    m[2] += wk[k] * y;
    m[3] += wk[k] * x * x;
    m[4] += wk[k] * x * y;
    m[5] += wk[k] * y * y;
  }
  if (m[0] == 0) return false;
  // A slope held near 0 where the entries do not fix it (all on a line:
  // constant across it; one entry: its value).
  m[3] += 1e-3 * m[0];
  m[5] += 1e-3 * m[0];
  // First row of the inverse (cofactors over the determinant).
  const double c0 = m[3] * m[5] - m[4] * m[4], c1 = m[2] * m[4] - m[1] * m[5], c2 = m[1] * m[4] - m[2] * m[3];
  const double det = m[0] * c0 + m[1] * c1 + m[2] * c2;
  for (std::uint32_t k = 0; k < 16; ++k) {
    if (wk[k] == 0) continue;
    const double x = double(k & 3) - 1 - ax, y = double(k >> 2) - 1 - ay;
    lambda[k] = wk[k] * (c0 + c1 * x + c2 * y) / det;
  }
  return true;
}

// The heaviest leaving corner of the query's cell on the query's side of
// the switch through the cell, where the table stores the switch on
// exactly two of the cell's edges: the class at the query direction
// itself, not the heaviest corner's (a tie at the cell's middle); else
// `best`. Corner k is (x0 + (k & 1), y0 + (k >> 1)). As
// ltt_side_of_switch() in transport.glsl.
int side_of_switch(const LightTransportTable& t, std::uint32_t vertex, std::uint32_t x0, std::uint32_t y0,
                   const std::array<TransportEntry, 4>& c, double ax, double ay, const std::array<double, 4>& w, int best) {
  if (t.switches.empty()) return best;
  static constexpr int kEnds[4][2] = {{0, 1}, {2, 3}, {0, 2}, {1, 3}};  // bottom, top (along columns), left, right
  std::array<double, 2> px{}, py{};
  int count = 0;
  for (int s = 0; s < 4; ++s) {
    const int i = kEnds[s][0], j = kEnds[s][1];
    if (c[i].status != TransportStatus::kLeaves || c[j].status != TransportStatus::kLeaves || leave_alike(c[i], c[j])) continue;
    const std::size_t entry = t.entry_index(vertex, y0 + (i >> 1), x0 + (i & 1));
    const std::uint8_t b = t.switches[2 * entry + (s < 2 ? 0 : 1)];
    if (b == 0 || count == 2) return best;
    const double f = b / 256.0;
    px[count] = (i & 1) + (s < 2 ? f : 0.0);
    py[count] = (i >> 1) + (s < 2 ? 0.0 : f);
    ++count;
  }
  if (count != 2) return best;
  const double dx = px[1] - px[0], dy = py[1] - py[0];
  const bool side = dx * (ay - py[0]) - dy * (ax - px[0]) > 0;
  int pick = -1;
  for (int k = 0; k < 4; ++k) {
    const bool sk = dx * ((k >> 1) - py[0]) - dy * ((k & 1) - px[0]) > 0;
    if (w[k] > 0 && sk == side && (pick < 0 || w[k] > w[pick])) pick = k;
  }
  return pick < 0 ? best : pick;
}

}  // namespace

TransportEntry lookup(const LightTransportTable& t, std::uint32_t vertex, const Dir3& n, const Dir3& to_light,
                      Interpolation mode) {
  Dir3 tb, bb;
  tangent_frame(n, tb, bb);
  const Dir3 local{dot3(to_light, tb), dot3(to_light, bb), std::max(dot3(to_light, n), 0.0)};
  const auto st = hemi_oct_encode(local);
  const double r1 = t.resolution - 1;
  // A direction on or below the horizon maps onto the grid's border, where
  // rounding may leave it a hair inside: snapped onto it (transport.glsl
  // alike, whose float rounding is coarser), so that the row or column
  // beyond gets no weight (a trapped horizon row stays trapped).
  const auto grid = [r1](double s) {
    const double f = std::clamp((s + 1.0) * 0.5 * r1, 0.0, r1);
    return f < 1e-5 ? 0.0 : f > r1 - 1e-5 ? r1 : f;
  };
  const double fx = grid(st[0]), fy = grid(st[1]);
  const auto x0 = static_cast<std::uint32_t>(std::min(std::floor(fx), r1 - 1));
  const auto y0 = static_cast<std::uint32_t>(std::min(std::floor(fy), r1 - 1));
  const double ax = fx - x0, ay = fy - y0;
  TransportEntry out;
  Dir3 dir{0, 0, 0};
  std::array<TransportEntry, 16> e;  // the bicubic stencil, loaded in that mode
  std::array<bool, 16> ok{};
  if (mode == Interpolation::kBicubic) {
    // Stencil k = (column x0 - 1 + (k & 3), row y0 - 1 + (k >> 2)). The
    // inner 2 x 2 must leave alike with entry 5 (b reflections, exit
    // within 30 degrees); an outer column or row with a sample outside the
    // grid or not leaving alike is replaced by linear extrapolation.
    for (std::uint32_t k = 0; k < 16; ++k) {
      const std::int64_t x = std::int64_t{x0} + (k & 3) - 1, y = std::int64_t{y0} + (k >> 2) - 1;
      if (x < 0 || y < 0 || x >= t.resolution || y >= t.resolution) continue;
      e[k] = t.load(t.entry_index(vertex, static_cast<std::uint32_t>(y), static_cast<std::uint32_t>(x)));
      ok[k] = e[k].status == TransportStatus::kLeaves;
    }
    const std::uint8_t b = e[5].bounces;
    for (std::uint32_t k = 0; k < 16; ++k) {
      ok[k] = ok[k] && e[k].bounces == b && dot3(e[k].direction, e[5].direction) >= kSameExitCos;
    }
    if (ok[5] && ok[6] && ok[9] && ok[10]) {
      // An outer row is used where its two inner entries are; an outer
      // column where its inner entries and the corners of used rows are.
      const bool row0 = ok[1] && ok[2], row3 = ok[13] && ok[14];
      const auto column = [&](std::uint32_t i) {
        return ok[i + 4] && ok[i + 8] && (!row0 || ok[i]) && (!row3 || ok[i + 12]);
      };
      const auto wx = catmull_rom(ax, column(0), column(3)), wy = catmull_rom(ay, row0, row3);
      for (std::uint32_t k = 0; k < 16; ++k) {
        const double w = wx[k & 3] * wy[k >> 2];
        if (w == 0) continue;
        out.transmittance += w * e[k].transmittance;
        out.path += w * e[k].path;
        for (std::size_t c = 0; c < 3; ++c) {
          out.exit[c] += w * e[k].exit[c];
          dir[c] += w * e[k].direction[c];
        }
      }
      out.transmittance = std::clamp(out.transmittance, 0.0, 1.0);
      out.path = std::max(out.path, 0.0);
      out.direction = normalized(dir);
      out.bounces = b;
      out.status = TransportStatus::kLeaves;
      return out;
    }
  }
  // Bilinear over the inner 2 x 2. Where they do not all leave alike (a
  // discontinuity: another number of reflections, or another face, whose
  // exit direction differs by more than 30 degrees) only the class of the
  // heaviest leaving corner is interpolated, its weights renormalised: the
  // exit lies on one side of the jump, not between two paths where no
  // light goes. The transmittance is scaled by the leaving corners' share
  // of the weight, so a trapped or occluded corner still passes nothing.
  std::array<TransportEntry, 4> c;
  std::array<double, 4> w{};
  int best = -1;
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t dx = k & 1, dy = k >> 1;
    w[k] = (dx ? ax : 1 - ax) * (dy ? ay : 1 - ay);
    c[k] = t.load(t.entry_index(vertex, y0 + dy, x0 + dx));
    if (c[k].status != TransportStatus::kLeaves || w[k] <= 0) w[k] = 0;
    if (w[k] > 0 && (best < 0 || w[k] > w[best])) best = k;
  }
  if (best < 0) return TransportEntry{};
  best = side_of_switch(t, vertex, x0, y0, c, ax, ay, w, best);
  if (mode == Interpolation::kBicubic) {
    const std::uint32_t heavy = 5 + (best & 1) + 4 * (best >> 1);
    std::array<double, 16> lambda{};
    if (linear_fit_weights(e, heavy, ax, ay, lambda)) {
      // As below: the transmittance scaled by the leaving share of the weight.
      double leaving = 0, transmittance = 0;
      for (int k = 0; k < 4; ++k) leaving += w[k];
      for (std::uint32_t k = 0; k < 16; ++k) {
        if (lambda[k] == 0) continue;
        transmittance += lambda[k] * e[k].transmittance;
        out.path += lambda[k] * e[k].path;
        for (std::size_t i = 0; i < 3; ++i) {
          out.exit[i] += lambda[k] * e[k].exit[i];
          dir[i] += lambda[k] * e[k].direction[i];
        }
      }
      out.path = std::max(out.path, 0.0);
      out.transmittance = std::clamp(transmittance, 0.0, 1.0) * leaving;
      out.bounces = c[best].bounces;
      out.direction = normalized(dir);
      out.status = TransportStatus::kLeaves;
      return out;
    }
  }
  double leaving = 0, same = 0, transmittance = 0;
  for (int k = 0; k < 4; ++k) {
    if (w[k] <= 0) continue;
    leaving += w[k];
    if (!leave_alike(c[k], c[best])) continue;
    same += w[k];
    transmittance += w[k] * c[k].transmittance;
    out.path += w[k] * c[k].path;
    for (std::size_t i = 0; i < 3; ++i) {
      out.exit[i] += w[k] * c[k].exit[i];
      dir[i] += w[k] * c[k].direction[i];
    }
  }
  for (std::size_t i = 0; i < 3; ++i) out.exit[i] /= same;
  out.path /= same;
  out.transmittance = transmittance / same * leaving;
  out.bounces = c[best].bounces;
  out.direction = normalized(dir);
  out.status = TransportStatus::kLeaves;
  return out;
}

bool leave_alike(const TransportEntry& a, const TransportEntry& b) {
  return a.status == TransportStatus::kLeaves && b.status == TransportStatus::kLeaves && a.bounces == b.bounces &&
         dot3(a.direction, b.direction) >= kSameExitCos;
}

std::vector<std::uint8_t> encode_transport_switches(const LightTransportTable& t) {
  ByteWriter w;
  w.u32(t.object);
  w.f32(t.wavelength_nm);
  w.u32(t.resolution);
  w.u32(t.vertex_count);
  write_zstd_frame(w, t.switches, kZstdLevel);
  return w.take();
}

Status decode_transport_switches(std::span<const std::uint8_t> payload, std::vector<LightTransportTable*> tables) {
  ChunkDecoder d(cxb::kTagTransportSwitches, payload);
  std::uint32_t object = 0, resolution = 0, vertex_count = 0, packed_size = 0;
  float wavelength = 0;
  if (!d.u32(object, "object index") || !d.f32(wavelength, "wavelength") || !d.u32(resolution, "resolution") ||
      !d.u32(vertex_count, "vertex count") || !d.u32(packed_size, "switch data size")) {
    return d.error();
  }
  LightTransportTable* t = nullptr;
  for (LightTransportTable* c : tables) t = c->object == object && c->wavelength_nm == wavelength ? c : t;
  if (!t || !t->switches.empty() || t->resolution != resolution || t->vertex_count != vertex_count) {
    d.fail("no table of object " + std::to_string(object) + " at " + std::to_string(wavelength) +
           " nm without switches and of this resolution and vertex count");
    return d.error();
  }
  std::span<const std::uint8_t> packed;
  if (!d.span(packed, packed_size, "switch data") || !d.finish()) return d.error();
  // The size is the table's (already bounded with its own data), an eighth
  // of its raw entries; no ratio bound: a table with few switches is
  // almost all zeros, which compress past 4096:1.
  const std::size_t raw_size = std::size_t{vertex_count} * resolution * resolution * 2;
  const std::string expected = std::to_string(vertex_count) + " x " + std::to_string(resolution) + "^2 entries";
  std::vector<std::uint8_t> raw;
  if (!zstd_decompress_exact(d, packed, raw_size, "switch data", expected, raw)) return d.error();
  t->switches = std::move(raw);
  return {};
}

std::vector<std::uint8_t> encode_transport_table(const LightTransportTable& t) {
  ByteWriter w;
  if (t.wavelength_nm > 0) w.f32(t.wavelength_nm);  // LTTS
  w.u32(t.object);
  w.u32(t.resolution);
  w.u32(t.max_bounces);
  w.f32(t.ior);
  w.vec3(t.absorption);
  w.vec3(t.exit_min);
  w.vec3(t.exit_max);
  w.f32(t.max_path);
  w.u32(t.vertex_count);
  const std::vector<std::uint8_t> raw = filter(t);
  write_zstd_frame(w, raw, raw.size() > kZstdLargeBytes ? kZstdLargeLevel : kZstdLevel);
  return w.take();
}

Result<LightTransportTable> decode_transport_table(std::span<const std::uint8_t> payload, const SceneDesc& scene,
                                                   bool spectral) {
  ChunkDecoder d(spectral ? cxb::kTagSpectralTransport : cxb::kTagTransport, payload);
  LightTransportTable t;
  std::uint32_t packed_size = 0;
  if (spectral && !d.f32(t.wavelength_nm, "wavelength")) return d.error();
  if (spectral && !(t.wavelength_nm >= kMinWavelength && t.wavelength_nm <= kMaxWavelength)) {
    d.fail("wavelength " + std::to_string(t.wavelength_nm) + " nm is outside 380..780 nm");
    return d.error();
  }
  const bool ok = d.u32(t.object, "object index") && d.u32(t.resolution, "resolution") &&
                  d.u32(t.max_bounces, "max bounces") && d.f32(t.ior, "IOR") && d.vec3(t.absorption, "absorption") &&
                  d.vec3(t.exit_min, "exit box") && d.vec3(t.exit_max, "exit box") && d.f32(t.max_path, "max path") &&
                  d.u32(t.vertex_count, "vertex count") && d.u32(packed_size, "table data size");
  if (!ok) return d.error();
  if (t.object >= scene.objects.size() || !is_transparent(scene.objects[t.object].role)) {
    d.fail("object index " + std::to_string(t.object) + " is not a transparent object of the scene");
    return d.error();
  }
  const Object& o = scene.objects[t.object];
  if (spectral && !(o.material.dispersion > 0)) {
    d.fail("object '" + o.name + "' does not disperse: it has no tables at other wavelengths");
    return d.error();
  }
  // The baker computes the index with index_at(), as this does: equal bits.
  const float ior = spectral ? index_at(o.material.ior, o.material.dispersion, t.wavelength_nm) : o.material.ior;
  if (t.resolution < kMinTransportResolution || t.resolution > kMaxTransportResolution ||
      t.max_bounces > kMaxTransportBounces || t.ior != ior) {
    d.fail("resolution, bounce count or IOR out of range or not the object's");
    return d.error();
  }
  bool finite = std::isfinite(t.max_path) && t.max_path >= 0;
  for (std::size_t k = 0; k < 3; ++k) {
    finite = finite && std::isfinite(t.absorption[k]) && t.absorption[k] >= 0 && std::isfinite(t.exit_min[k]) &&
             std::isfinite(t.exit_max[k]) && t.exit_min[k] <= t.exit_max[k];
  }
  if (!finite || t.vertex_count < 3 || t.vertex_count > kMaxMeshVertices) {
    d.fail("absorption, exit box, path range or vertex count out of range");
    return d.error();
  }
  std::span<const std::uint8_t> packed;
  if (!d.span(packed, packed_size, "table data") || !d.finish()) return d.error();
  const std::size_t raw_size = std::size_t{t.vertex_count} * t.resolution * t.resolution * kFields * 2;
  const std::string expected = std::to_string(t.vertex_count) + " x " + std::to_string(t.resolution) + "^2 entries";
  if (raw_size > kMaxTransportEntries * 16 || raw_size > kMaxRatio * (packed.size() + 64)) {
    d.fail("table data of " + expected + " exceeds the 1 GiB / 4096:1 bounds");
    return d.error();
  }
  std::vector<std::uint8_t> raw;
  if (!zstd_decompress_exact(d, packed, raw_size, "table data", expected, raw)) return d.error();
  unfilter(raw, t);
  for (std::size_t i = 0; i < t.words.size(); i += 4) {
    const std::uint32_t status = (t.words[i + 3] >> 16) & 0xFF;
    const std::uint32_t bounces = t.words[i + 3] >> 24;
    const bool empty = t.words[i] == 0 && t.words[i + 1] == 0 && t.words[i + 2] == 0 && (t.words[i + 3] & 0xFF00FFFF) == 0;
    if (status > 2 || bounces > t.max_bounces || (status != 0 && !empty)) {
      d.fail("entry " + std::to_string(i / 4) + " has an invalid status or bounce count");
      return d.error();
    }
  }
  return t;
}

}  // namespace caustix
