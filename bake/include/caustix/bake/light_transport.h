#pragma once
// The light-transport stage of the baker (Iwasaki et al. §3; formats/light_transport.h
// describes the table): for every vertex of every transparent object and every
// direction of the hemi-octahedral grid, the refracted ray is traced through
// the object with exact ray-mesh intersection (CGAL AABB tree) until it
// leaves the object for good: through overlapping shells of the mesh (one
// glass), out and into the object again, and up to `max_bounces` total
// internal reflections and re-entries. Parallel over vertices with
// oneTBB; every entry has its own slot, so the table does not depend on the
// thread count.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "caustix/common/mesh.h"
#include "caustix/common/status.h"
#include "caustix/formats/scene.h"

namespace caustix::bake {

// What casts the tables' rays: Embree (the default; robust
// mode, single precision) or CGAL's AABB tree (exact predicates, double
// precision: the baker's only caster before Embree, `caustix-bake --ltt-rays cgal`).
// Both give tables that do not depend on the thread count; they differ in
// the last bits of exit points and, for a few grazing directions, in
// whether the object blocks the light (docs/glass-tables.md).
enum class RayEngine { kEmbree, kCgal };

struct TransportOptions {
  std::uint32_t resolution = kDefaultTransportResolution;  // R: R x R directions per vertex
  std::uint32_t max_bounces = 4;  // internal reflections and re-entries followed (the paper: 0)
  std::uint32_t bits = kDefaultTransportBits;  // significant bits kept per field (8..16)
  // Dispersive objects (docs/dispersion.md): tables at this many
  // more wavelengths, evenly over 380..780 nm with both ends (0 or
  // 2..kMaxTransportWavelengths), besides the one at n_d. The runtime
  // interpolates between the two whose indices bracket each traced
  // wavelength's. 0: caustics from the tables refract at n_d only.
  std::uint32_t wavelengths = kDefaultTransportWavelengths;
  RayEngine rays = RayEngine::kEmbree;
  // Locate where the path class switches between neighbouring grid
  // directions (LightTransportTable::switches, the LTTW chunk), by
  // kSwitchSteps traces per such grid edge, at the vertices of flat faces:
  // what the runtime cuts triangles torn between two classes with.
  bool switches = true;
};

// The wavelengths (nm) of a dispersive object's extra tables for `count`
// (above): 380 + 400 k / (count - 1), k = 0..count-1; none for 0.
std::vector<float> transport_wavelengths(std::uint32_t count);

struct TransportReport {
  std::uint32_t object = 0;
  float wavelength_nm = 0;           // 0: the table at n_d (LTTB), else an LTTS table's wavelength
  std::uint32_t vertices = 0;
  std::uint64_t entries = 0, leaving = 0, trapped = 0, occluded = 0, reflected = 0;
  std::uint64_t switch_edges = 0;    // grid edges whose ends leave unalike, bisected for the switch (LTTW)
  std::uint64_t rays = 0;            // ray casts (occlusion + inside segments)
  double seconds = 0;
  std::uint64_t raw_bytes = 0;       // 16 bytes per entry
  std::uint64_t stored_bytes = 0;    // the LTTB (or LTTS) chunk
  double position_error_m = 0;       // quantisation bound of exit points
  double direction_error_rad = 0;    // quantisation bound of exit directions
};

// Exact transport of one incident direction at one vertex (what each table
// entry stores, before quantisation); for the table and as the oracle of
// the look-up tests. Thread-safe.
class TransportTracer {
 public:
  TransportTracer(const Material& material, const TriangleMesh& mesh, std::uint32_t max_bounces, RayEngine rays = RayEngine::kEmbree);
  ~TransportTracer();
  // `to_light`: unit object-space direction towards the light. `rays`
  // counts the ray casts.
  TransportEntry trace(std::uint32_t vertex, const Dir3& to_light, std::uint64_t* rays = nullptr) const;
  // Whether every triangle of the vertex lies in its tangent plane (a flat
  // face's vertex, whose rays start just inside the face).
  bool flat(std::uint32_t vertex) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Traces the table of one transparent object over `mesh` (the Draco-decoded
// mesh, whose vertex order the runtime sees): at the material's IOR, or
// with wavelength_nm > 0 at its index there (an LTTS table). `progress`,
// if set, is called with the fraction of vertices traced, from the tracing
// threads (possibly at once: the caller serialises); when it returns false
// the tracing stops early and the table is incomplete (the caller drops it).
LightTransportTable trace_transport_table(std::uint32_t object, const Material& material, const TriangleMesh& mesh,
                                          const TransportOptions& options, TransportReport* report,
                                          float wavelength_nm = 0, const std::function<bool(double)>& progress = {});

}  // namespace caustix::bake
