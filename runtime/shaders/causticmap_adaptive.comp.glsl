#version 450 core
// causticmap_adaptive.comp: adaptive caustic maps (Wyman & Nichols 2009,
// "Adaptive caustic maps using deferred shading", EG 2009 §4; Wyman 2008,
// "Hierarchical caustic maps"; docs/caustic-maps.md). Instead of one photon
// per texel of the casters' capture, photons start as a coarse grid of
// cells over it and only cells that cover a caster are refined, level by
// level, into their four children; a photon budget bounds how many are
// traced. The paper's traversal runs in deferred passes over a photon
// buffer; here each pass is a compute dispatch over a cell list (indirect,
// sized on the GPU, no read-back). Where the budget cannot take every
// refinement of a level, the cells where photons are most useful go first:
// the casters' outline (partly covered cells) and where their normal turns
// within the cell (the surface that focuses light), ranked by a score in 16
// buckets so that the set refined is the same every run. Stages
// (u_stage):
//  0 pyramid level 0 from the front capture: (normal * coverage, coverage)
//  1 pyramid level u_level as the mean of its 2x2 children
//  2 seed: the covered cells of the coarsest level into list 0
//  3 prepare (one invocation): the dispatch over the current list
//  4 count: per cell of the current list, the photons its refinement adds
//    (covered children - 1) into the bucket of its score
//  5 decide (one invocation): the lowest bucket still refined within the
//    budget
//  6 emit: cells at or above that bucket append their covered children to
//    the next list, the others (and every cell at the finest level) become
//    leaves: the photons causticmap_photons traces
//  7 finish (one invocation): the photon pass's dispatch and the splats'
//    draw from the leaves' count
layout(local_size_x = 64) in;

layout(binding = 0) uniform sampler2D u_front_pos;  // world xyz, object + 1 (0: none)
layout(binding = 1) uniform sampler2D u_front_nrm;
// The pyramid: level k (side u_side >> k) at offset u_offset[k]; per texel
// the mean of (normal * covered, covered) over the capture texels it holds.
layout(std430, binding = 3) buffer Pyramid { vec4 pyramid[]; };
// Cells packed x | y << 12 | level << 24 (level 0: a capture texel).
layout(std430, binding = 4) buffer Lists { uint cells[]; };  // two lists of u_budget, then the leaves
layout(std430, binding = 5) buffer State {
  uint count[2];       // cells in list 0 and 1
  uint leaves;         // photons to trace
  uint threshold;      // lowest bucket refined at this level (16: none)
  uvec4 dispatch;      // (groups over the current list, 1, 1, -)
  uvec4 photon_dispatch;  // (groups over the leaves, 1, 1, -)
  uvec4 draw;          // glDrawArraysIndirect: (leaves, 1, 0, 0)
  uint hist[16];       // photons added by refining the cells of each bucket
};

uniform int u_stage;
uniform int u_level;     // pyramid level (stages 0, 1); the current list's level (4..6)
uniform int u_levels;    // the coarsest level
uniform int u_side;      // capture side (a multiple of 2^u_levels)
uniform int u_offset[9];
uniform uint u_budget;
uniform int u_cur;       // current list 0 or 1

vec4 pyr(int k, ivec2 p) { return pyramid[u_offset[k] + p.y * (u_side >> k) + p.x]; }
uint pack_cell(ivec2 p, int k) { return uint(p.x) | (uint(p.y) << 12) | (uint(k) << 24); }
ivec2 cell_xy(uint c) { return ivec2(int(c & 0xfffu), int((c >> 12) & 0xfffu)); }

// Where photons are useful: 1 - coverage (outline) or 1 - |mean normal|
// (the normal turns within the cell), on a log scale in 16 buckets.
int bucket(vec4 m) {
  float score = max(1.0 - m.w, 1.0 - length(m.xyz) / max(m.w, 1e-6));
  return score <= 0.0 ? 0 : clamp(int(floor(16.0 + 1.5 * log2(score))), 0, 15);
}

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (u_stage == 0 || u_stage == 1 || u_stage == 2) {
    int k = u_stage == 2 ? u_levels : u_level;
    int side = u_side >> k;
    if (id >= uint(side * side)) return;
    ivec2 p = ivec2(int(id) % side, int(id) / side);
    if (u_stage == 0) {
      bool covered = texelFetch(u_front_pos, p, 0).w > 0.5;
      vec3 n = covered ? normalize(texelFetch(u_front_nrm, p, 0).xyz) : vec3(0.0);
      pyramid[u_offset[0] + id] = covered ? vec4(n, 1.0) : vec4(0.0);
    } else if (u_stage == 1) {
      vec4 s = pyr(k - 1, 2 * p) + pyr(k - 1, 2 * p + ivec2(1, 0)) + pyr(k - 1, 2 * p + ivec2(0, 1)) + pyr(k - 1, 2 * p + ivec2(1, 1));
      pyramid[u_offset[k] + id] = 0.25 * s;
    } else if (pyr(k, p).w > 0.0) {
      cells[atomicAdd(count[0], 1u)] = pack_cell(p, k);
    }
    return;
  }
  if (u_stage == 3) {
    if (id == 0u) {
      count[1 - u_cur] = 0u;
      dispatch = uvec4((count[u_cur] + 63u) / 64u, 1u, 1u, 0u);
    }
    return;
  }
  if (u_stage == 7) {
    if (id == 0u) {
      photon_dispatch = uvec4((leaves + 63u) / 64u, 1u, 1u, 0u);
      draw = uvec4(leaves, 1u, 0u, 0u);
    }
    return;
  }
  if (u_stage == 5) {
    if (id != 0u) return;
    // Refine the highest buckets while the photons stay within the budget:
    // the leaves so far, this level's cells (each at least one photon), and
    // what refining adds.
    uint total = leaves + count[u_cur];
    uint t = 16u;
    for (int b = 15; b >= 0; --b) {
      if (total + hist[b] > u_budget) break;
      total += hist[b];
      t = uint(b);
    }
    threshold = u_level == 0 ? 16u : t;  // level 0 cells are leaves anyway
    for (int b = 0; b < 16; ++b) hist[b] = 0u;
    return;
  }
  if (id >= count[u_cur]) return;
  uint c = cells[uint(u_cur) * u_budget + id];
  ivec2 p = cell_xy(c);
  int k = u_level;
  int added = -1;
  if (k > 0) {
    for (int j = 0; j < 4; ++j) added += pyr(k - 1, 2 * p + ivec2(j & 1, j >> 1)).w > 0.0 ? 1 : 0;
  }
  int b = bucket(pyr(k, p));
  if (u_stage == 4) {
    if (k > 0) atomicAdd(hist[b], uint(added));
    return;
  }
  // Stage 6.
  if (k > 0 && uint(b) >= threshold) {
    uint next = uint(1 - u_cur) * u_budget;
    for (int j = 0; j < 4; ++j) {
      ivec2 q = 2 * p + ivec2(j & 1, j >> 1);
      if (pyr(k - 1, q).w > 0.0) cells[next + atomicAdd(count[1 - u_cur], 1u)] = pack_cell(q, k - 1);
    }
  } else {
    cells[2u * u_budget + atomicAdd(leaves, 1u)] = c;
  }
}
