#pragma once
// Refinement of transparent meshes for the light-transport table (Iwasaki et al.
// §3 samples the transport at vertices only; the runtime interpolates it
// linearly across each triangle, §4.1). Glass as people model it breaks
// both: a wedge prism of 6 vertices has no vertex inside any face, and the
// importer's averaged normals at its corners bend light as no face does,
// so it cast no refracted light at all. Two steps, both
// deterministic:
//
//  1. Creases: an edge whose two triangles' normals differ by more than
//     `crease_deg` is a crease. Each vertex is split into one copy per fan
//     of triangles joined across smooth edges, each copy with the
//     angle-weighted normal of its fan (a flat face gets its own normal).
//     Vertices on no crease keep their normal (the file's, when it gave
//     them).
//  2. Flat regions: a triangle is flat when its three vertex normals are
//     within `flat_deg` of its face normal (curved surfaces, whose
//     tessellation the modeller already matched to the curvature, are
//     left alone). Every edge of a flat triangle longer than `max_edge`
//     times the mesh's bounding-box diagonal is split at its midpoint,
//     edges shared by position split alike (no T-junctions), triangles
//     re-cut by the usual 1/2/3-split templates, until none is longer.
//     Triangles touching a crease get a quarter of that bound: light
//     entering next to a crease may leave through the face beyond it, and
//     a triangle whose corners leave through different faces smears its
//     light between their landings, so the rim strip is kept narrow.
//  3. Curved regions (optional, `max_turn_deg` > 0): an edge whose end
//     normals turn by more than `max_turn_deg` is split too, while it is
//     longer than the rim's bound (max_edge / 4 times the diagonal). The
//     runtime maps each triangle's light linearly between its corners'
//     exit rays; on a ball lens the landing point is far from linear in
//     the entry point (spherical aberration), so coarse curved triangles
//     spread the focal spot (docs/glass-tables.md measures it). The
//     new vertex lies on the old edge with the normalised mean of its
//     ends' normals, the Phong normal there, so the surface that is traced
//     is the same (to second order in the turn) and caustix-reference,
//     which traces the unrefined mesh, needs no matching option.
//
// The mesh stays closed and consistently wound if it was (edges match by
// position), and its shape is unchanged: new vertices lie on old edges.

#include <cstdint>
#include <string>

#include "caustix/common/mesh.h"

namespace caustix::bake {

struct GlassRefineOptions {
  double crease_deg = 30.0;        // dihedral angle above which an edge is sharp
  double flat_deg = 1.0;           // vertex normals within this of the face normal: flat
  // Longest edge of a flat triangle / bounding-box diagonal (a quarter of
  // it for triangles touching a crease); 0: no splitting.
  double max_edge = 1.0 / 16.0;
  // Step 3: largest normal turn along an edge (degrees); 0: off.
  double max_turn_deg = 0;
  // Rounds stop once the mesh has more vertices than this (the caller then
  // refuses the table as too large instead of running out of memory).
  std::uint32_t max_vertices = UINT32_MAX;
};

struct GlassRefineReport {
  std::uint32_t vertices_in = 0, triangles_in = 0;
  std::uint32_t vertices_out = 0, triangles_out = 0;
  std::uint32_t crease_edges = 0;      // edges (by position) sharper than crease_deg, open ones included
  std::uint32_t crease_vertices = 0;   // vertex copies added at creases
  std::uint32_t flat_triangles = 0;    // of the input, after step 1
  std::uint32_t edges_split = 0;       // midpoints added by steps 2 and 3 (shared by position: counted once per side)
  std::uint32_t curved_edges_split = 0;  // of those, edges split for their normals' turn alone (step 3)
  double max_turn_in = 0, max_turn_out = 0;  // largest normal turn along an edge above the rim's bound, degrees
  std::uint32_t rounds = 0;            // halving rounds of steps 2 and 3
  double max_edge_m = 0;               // the bound in object units (max_edge x diagonal)
  double longest_flat_edge_in = 0, longest_flat_edge_out = 0;  // object units
  bool stopped_at_vertex_limit = false;
  bool changed() const { return vertices_out != vertices_in || triangles_out != triangles_in; }
};

// One line for the bake's output: what was done and why.
std::string describe_refinement(const GlassRefineReport& report, const GlassRefineOptions& options);

TriangleMesh refine_transparent_mesh(const TriangleMesh& mesh, const GlassRefineOptions& options, GlassRefineReport* report);

}  // namespace caustix::bake
