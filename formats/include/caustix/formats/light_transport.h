#pragma once
// Light-transport tables (Iwasaki et al. §3, §4.1; its reference [12]): for every
// vertex of a transparent object and every incident direction of a grid over
// the hemisphere around the vertex normal, where the refracted ray leaves
// the object again, in which direction, with which Fresnel transmittance and
// after how long a path inside. Baked by bake/light_transport.h, stored as
// one "LTTB" chunk per transparent object (formats/SPEC.md), looked up per
// frame by the runtime (runtime/shaders/glass_rays.comp.glsl mirrors
// lookup() below).
//
// Direction grid: the hemi-octahedral map of the hemisphere around the
// vertex normal (Cigolle et al. 2014, "A Survey of Efficient Representations
// for Independent Unit Vectors", §3.3): omega (unit, towards the light, in
// the vertex's tangent frame with z = normal) maps to
//   p = omega.xy / (|x| + |y| + z),  (s, t) = (p.x + p.y, p.x - p.y) in [-1, 1]^2,
// sampled at R x R grid points s_i = -1 + 2 i / (R - 1) (the horizon is on
// the square's boundary, so every direction that can reach the vertex lies
// inside the grid: no back-facing entries are stored). The map is not
// equal-area: a cell's solid angle varies by a factor of about 2 between the
// pole and the corners (stated in docs/glass-tables.md with the measured error).
// The tangent frame is the branchless one of Duff et al. 2017 ("Building an
// orthonormal basis, revisited"), computed identically in GLSL.
//
// Record (16 bytes, four little-endian u32 words; also the GPU layout):
//   w0 = ex | ey << 16, w1 = ez | T << 16, w2 = ou | ov << 16,
//   w3 = path | status << 16 | bounces << 24
// exit point e quantised to 16 bits per axis over the exit box; exit
// direction as a full-sphere octahedral pair quantised to 16 bits each;
// T = Fresnel transmittance product in [0, 1] to 16 bits; path length inside
// to 16 bits over [0, max_path] (each field q / 65535 of its range). The
// writer may keep fewer significant bits b (precision_bits): it rounds
// every field to a multiple of 2^(16 - b), which readers need not know
// and which the compressor turns into a smaller chunk (docs/glass-tables.md has
// the measured sizes). status 0 = the ray leaves the object for good, 1 =
// trapped (still inside after max_bounces internal reflections and
// re-entries), 2 = the object itself blocks the light from this direction
// before it reaches the vertex (that light is in the entries of the
// vertices it enters first). bounces = the internal reflections and
// re-entries before it leaves, the path's class for the look-up.
// Entries with status != 0 have every other field zero.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/types.h"

namespace caustix {

struct SceneDesc;

inline constexpr std::uint32_t kMinTransportResolution = 2;
inline constexpr std::uint32_t kMaxTransportResolution = 128;
inline constexpr std::uint32_t kMaxTransportBounces = 64;
// Defaults from the resolution sweep in docs/glass-tables.md (caustix-bench ltt):
// with bicubic look-up, R = 20 at 12 bits keeps the exit-direction error
// under 0.5 deg and a 10k-vertex sphere under 20 MB.
inline constexpr std::uint32_t kDefaultTransportResolution = 20;
inline constexpr std::uint32_t kMinTransportBits = 8;
inline constexpr std::uint32_t kMaxTransportBits = 16;
inline constexpr std::uint32_t kDefaultTransportBits = 12;
// Entries (vertices x R^2) of one table: 16 bytes each, 1 GiB at most. The
// baker refuses a larger table before tracing it, the reader a file that
// claims one.
inline constexpr std::uint64_t kMaxTransportEntries = std::uint64_t{1} << 26;
// Tables of a dispersive object at other wavelengths (LTTS; the baker's
// --ltt-wavelengths): 2 (380 and 780 nm, with n_d's between) keeps the
// interpolated ball-lens images within the caustic maps' error
// (docs/dispersion.md).
inline constexpr std::uint32_t kDefaultTransportWavelengths = 2;
inline constexpr std::uint32_t kMaxTransportWavelengths = 16;

enum class TransportStatus : std::uint8_t { kLeaves = 0, kTrapped = 1, kOccluded = 2 };

// One decoded (or about-to-be-quantised) entry, object space.
struct TransportEntry {
  std::array<double, 3> exit{};       // exit point
  std::array<double, 3> direction{};  // unit exit direction (travel)
  double transmittance = 0;           // Fresnel T of every interface crossed (internal reflections count 1 each)
  double path = 0;                    // metres inside the object (object space)
  TransportStatus status = TransportStatus::kTrapped;
  std::uint8_t bounces = 0;           // internal reflections and re-entries before leaving
};

struct LightTransportTable {
  std::uint32_t object = 0;        // index into SceneDesc::objects (transparent)
  std::uint32_t resolution = 0;    // R: R x R directions per vertex
  std::uint32_t max_bounces = 0;   // internal reflections and re-entries followed
  float ior = 1.5f;                // as baked: the material's IOR, or its index at wavelength_nm
  // 0: the table at n_d (LTTB). Else the wavelength (nm, 380..780) of a
  // dispersive object's table at another index (LTTS; docs/dispersion.md):
  // ior = index_at(material ior, material dispersion, wavelength_nm).
  float wavelength_nm = 0;
  Vec3f absorption{0, 0, 0};       // 1/m per RGB channel (the material's)
  Vec3f exit_min{}, exit_max{};    // quantisation box of exit points (object space)
  float max_path = 0;              // quantisation range of path lengths
  std::uint32_t vertex_count = 0;  // of the decoded (Draco) mesh; entries follow its order
  std::vector<std::uint32_t> words;  // vertex_count * R^2 * 4, vertex-major, then grid row (t), column (s)
  // Significant bits store() keeps per field (kMinTransportBits..16). Not
  // stored in the file; a decoded table says 16.
  std::uint32_t precision_bits = 16;
  // Where the path class switches between neighbouring grid directions
  // (the optional LTTW chunk): 2 bytes per entry, in the order
  // of the entries, for the grid edge to the next column and to the next
  // row. 0: no switch there (the two do not both leave, or leave alike, or
  // the edge leaves the grid); k in 1..255: the two leave unalike and the
  // class switches at k / 256 of the way from this entry, found by
  // bisecting the traced direction (kSwitchSteps halvings). Empty: none
  // stored (files from before the tables stored their switches, or a table
  // without a switch).
  std::vector<std::uint8_t> switches;

  std::size_t entry_index(std::uint32_t vertex, std::uint32_t row, std::uint32_t col) const {
    return (std::size_t{vertex} * resolution + row) * resolution + col;
  }
  // Quantises `e` into entry `index` (words must be sized).
  void store(std::size_t index, const TransportEntry& e);
  TransportEntry load(std::size_t index) const;
  // Largest quantisation error of a stored exit point (metres, per axis) and
  // of a stored exit direction (radians) at precision_bits.
  double position_error_bound() const;
  double direction_error_bound() const;
};

// --- direction parameterisations (shared with the GLSL) ---
using Dir3 = std::array<double, 3>;
// Orthonormal tangent frame (t, b, n) of a unit normal n (Duff et al. 2017).
void tangent_frame(const Dir3& n, Dir3& t, Dir3& b);
// Hemi-octahedral map of a local direction with z >= 0 to [-1, 1]^2 and back.
std::array<double, 2> hemi_oct_encode(const Dir3& local);
Dir3 hemi_oct_decode(double s, double t);
// Full-sphere octahedral map of a unit direction to [-1, 1]^2 and back.
std::array<double, 2> oct_encode(const Dir3& d);
Dir3 oct_decode(double u, double v);
// The grid direction (object space, towards the light) of (row, col) at a
// vertex with unit normal n; grid_direction_at() between grid points
// (fractional row and column, linear in the hemi-octahedral square).
Dir3 grid_direction(const Dir3& n, std::uint32_t resolution, std::uint32_t row, std::uint32_t col);
Dir3 grid_direction_at(const Dir3& n, std::uint32_t resolution, double row, double col);
// Halvings of a grid edge when the baker looks for a class switch on it.
inline constexpr std::uint32_t kSwitchSteps = 4;
// Two entries leave alike: both leave, after the same count b, with exit
// directions within kSameExitCos (defined below).
bool leave_alike(const TransportEntry& a, const TransportEntry& b);

// How lookup() blends the grid directions around the query direction.
//  kBilinear: the four neighbours, bilinear weights.
//  kBicubic:  the 4 x 4 neighbours, Catmull-Rom weights per axis (exact for
//             quadratics). The inner 2 x 2 must leave alike (after the same
//             count b of internal reflections and re-entries, exit directions within 30
//             degrees of each other). Else (a discontinuity of the
//             transport, which a cubic would ring across) the class of the
//             heaviest leaving corner is extrapolated linearly up to the
//             query: the plane fitted by weighted least squares to the
//             16 entries of that class, its slopes held near 0 where they
//             lie on a line. An outer row or column that leaves the grid or holds
//             an entry not leaving alike (the horizon row of a sphere is
//             trapped at the critical angle) is replaced by the linear
//             extrapolation of the two inner ones.
enum class Interpolation : std::uint8_t { kBilinear, kBicubic };
// Two entries leave alike when their exit directions are closer than this
// cosine (30 degrees) and their counts b equal; otherwise the paths leave
// through different faces or after different reflections or re-entries.
inline constexpr double kSameExitCos = 0.8660254037844387;
inline constexpr Interpolation kDefaultInterpolation = Interpolation::kBicubic;
const char* to_string(Interpolation mode);

// Look-up between the grid directions around `to_light` (unit, object
// space, towards the light) at vertex `vertex` with unit normal `n`. In
// bilinear mode exit points, directions (renormalised) and path lengths are
// averaged over the neighbours that leave alike with the heaviest leaving
// one (a jump is not blended: the exit lies on one side of it), weighted by
// their bilinear weight; the transmittance is their mean scaled by the
// share of the weight that leaves (trapped and occluded count as 0), so
// light fades out where the table says it cannot pass. A direction below
// the vertex's horizon is clamped onto it. Returns status kTrapped if no
// neighbour leaves. Where the table has switches (LTTW) crossing exactly
// two edges of the query's cell, "the heaviest leaving one" is taken on the
// query's side of the line through them. runtime/shaders/transport.glsl
// mirrors this function; its ltt_lookup_ex() also gives the other class
// and the distance to the switch, which have no C++ counterpart.
TransportEntry lookup(const LightTransportTable& table, std::uint32_t vertex, const Dir3& n, const Dir3& to_light,
                      Interpolation mode = kDefaultInterpolation);

// The LTTW payload of a table's switches (table.switches non-empty), and
// its decoding onto the table it names (object and wavelength), which must
// have no switches yet; refuses sizes other than the table's (which bound
// the decompressed size: no ratio bound, few switches compress past 4096:1).
std::vector<std::uint8_t> encode_transport_switches(const LightTransportTable& table);
Status decode_transport_switches(std::span<const std::uint8_t> payload, std::vector<LightTransportTable*> tables);

// The LTTB payload (a table at n_d), or for wavelength_nm > 0 the LTTS
// payload: f32 wavelength, then LTTB's fields.
std::vector<std::uint8_t> encode_transport_table(const LightTransportTable& table);
// Safe on hostile bytes: fields checked against the scene, decompression
// bounded (raw size at most 1 GiB and at most 4096 x the compressed size).
// `spectral` reads an LTTS payload: the object must disperse and the IOR
// be its index at the wavelength.
Result<LightTransportTable> decode_transport_table(std::span<const std::uint8_t> payload, const SceneDesc& scene,
                                                   bool spectral = false);

}  // namespace caustix
