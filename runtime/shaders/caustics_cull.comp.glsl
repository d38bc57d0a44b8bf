#version 450 core
// Beyond the thesis (Tipprasert 2006 §6.1): decide, before drawing, which
// illumination volumes can light the receiver and through which planes.
//
// A volume's footprint between two planes lies in the convex hull of its
// three rays' hits on them (each hit moves linearly with the plane), so the
// six hits on the first and last plane bound it. A volume whose footprint
// misses the frame is dropped (u_frame_cull). In pair mode the footprint's
// tiles of the position map's min/max depth pyramid give the depths of the
// surface beneath it, and only the planes whose acceptance windows overlap
// them are listed (u_plane_cull; without it every plane is, as the thesis
// drew every volume through every plane). Outside pair mode (volumetric
// baseline) volumes are listed once and drawn slice by slice.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 2) readonly buffer Indices { uint indices[]; };
layout(std430, binding = 3) readonly buffer Refracted { vec4 refracted[]; };
layout(std430, binding = 5) writeonly buffer List { uint list[]; };  // volumes, or (volume, plane) pairs
// A listed pair's primitive (caustics_geometry.comp), 16 words, by its
// place in the list: word 15 takes the depths of the surface beneath it
// until the geometry pass reads them and writes the primitive.
layout(std430, binding = 8) writeonly buffer Primitives { uint prim_words[]; };
layout(std430, binding = 6) buffer Command { uint cmd[]; };          // [8] list length, [9] overflow
// The planes (binding 7), planned on the CPU or by caustics_plan.comp:
// caustics_windows.glsl, prefixed.

#ifdef BATCH
// The maps u_map_base.. of the batch (caustics_batch.glsl): a row of work
// groups each, its entries in its own part of the list (CausticsMap::list)
// and counted in its own words (batch_counts), as a map drawn alone has.
uniform uint u_map_base;
layout(binding = 0) uniform sampler2DArray u_depth_tiles;  // per map, as below
vec2 u_texel;
int g_tiles;    // the map's layer of u_depth_tiles
uvec2 g_list;  // its part of the list
#define DEPTH_TILE(x, y) texelFetch(u_depth_tiles, ivec3(x, y, g_tiles), 0).rg
#else
layout(binding = 0) uniform sampler2D u_depth_tiles;  // min, max frame V per tile; min > max where empty
uniform vec3 u_origin;
uniform vec3 u_U;
uniform vec3 u_V;
uniform vec3 u_W;
uniform vec3 u_half;
uniform vec2 u_texel;     // caustics-map texel in frame U, W (metres) where it is coarser than the
                          // position map's (else 0): the acceptance test samples the surface across
                          // the whole texels a piece touches
#define DEPTH_TILE(x, y) texelFetch(u_depth_tiles, ivec2(x, y), 0).rg
#endif
uniform uint u_triangles;
// The water triangles read: those of the map's rectangle of the grid
// (caustics_rects.comp, entry u_rect; in a batch the map's list.z), or
// with u_rect < 0 every one. Word 6 of the header: the grid's cells along x.
layout(std430, binding = 12) readonly buffer Rects {
  uint rect_bounds[8];
  uvec4 rects[];
};
uniform int u_rect;
uniform int u_frame_cull;
uniform int u_plane_cull;
uniform int u_pairs;
uniform uint u_capacity;  // entries the list holds

// Footprint (in frame U, W) of volume t's rays between planes v = d0 and
// v = d1 (d0 > d1); false if a ray does not head down through the frame.
bool footprint(uint t, vec2 depths, out vec2 lo, out vec2 hi) {
  lo = vec2(1e30);
  hi = vec2(-1e30);
  for (int k = 0; k < 3; ++k) {
    uint i = indices[3u * t + uint(k)];
    vec4 r = refracted[i];
    vec3 rel = positions[i].xyz - u_origin;
    float tv = dot(r.xyz, u_V);
    if (r.w == 0.0 || tv > -1e-6) return false;
    float pv = dot(rel, u_V);
    for (int e = 0; e < 2; ++e) {
      float s = max(0.0, (pv - depths[e]) / -tv);
      vec3 q = rel + s * r.xyz;
      vec2 uw = vec2(dot(q, u_U), dot(q, u_W));
      lo = min(lo, uw);
      hi = max(hi, uw);
    }
  }
  return true;
}

// Depth range [vmin, vmax] of the surface under a footprint, from the tile
// pyramid; every depth if the footprint covers too many tiles to read.
vec2 surface_depths(vec2 lo, vec2 hi) {
  ivec2 tiles = textureSize(u_depth_tiles, 0).xy;
  vec2 to_tiles = vec2(tiles) / (2.0 * u_half.xz);
  ivec2 t0 = clamp(ivec2(floor((lo + u_half.xz) * to_tiles)), ivec2(0), tiles - 1);
  ivec2 t1 = clamp(ivec2(floor((hi + u_half.xz) * to_tiles)), ivec2(0), tiles - 1);
  if ((t1.x - t0.x + 1) * (t1.y - t0.y + 1) > 256) return vec2(-1e30, 1e30);
  vec2 range = vec2(1e30, -1e30);
  for (int y = t0.y; y <= t1.y; ++y)
    for (int x = t0.x; x <= t1.x; ++x) {
      vec2 mm = DEPTH_TILE(x, y);
      range = vec2(min(range.x, mm.x), max(range.y, mm.y));
    }
  return range;
}

// The planes volume t is listed through: first and n (n 0: none; outside
// pair mode, 1 where the volume is listed), and the depths [vmin, vmax] of
// the surface beneath it (every depth where unknown).
void select_planes(uint t, out int first, out int n, out float vmin, out float vmax) {
  first = 0;
  n = 0;
  vmin = -1e30;
  vmax = 1e30;
  if (t >= u_triangles || PLANE_COUNT == 0u) return;
  vec2 lo, hi;
  if (!footprint(t, vec2(DEPTH_HI, DEPTH_LO), lo, hi)) return;
  if (u_frame_cull != 0 && (any(greaterThan(lo, u_half.xz)) || any(lessThan(hi, -u_half.xz)))) return;
  if (u_pairs == 0 || u_plane_cull == 0) {
    n = u_pairs == 0 ? 1 : int(PLANE_COUNT);
    return;
  }
  // The surface under the footprint bounds the depths that matter; the
  // footprint over just those depths is smaller, so refine twice.
  vec2 range = surface_depths(lo - u_texel, hi + u_texel);
  for (int it = 0; it < 2 && range.x <= range.y && range.x > -1e29; ++it) {
    vec2 l2, h2;
    footprint(t, range.yx, l2, h2);
    range = surface_depths(l2 - u_texel, h2 + u_texel);
  }
  vmin = range.x;
  vmax = range.y;
  if (vmin > vmax) return;  // no surface under the footprint
  // Planes whose half-open window (D - eps, D + eps] meets [vmin, vmax].
  first = -1;
  for (int p = 0; p < int(PLANE_COUNT); ++p) {
    vec2 pl = PLANE(p);
    if (pl.x - pl.y < vmax && pl.x + pl.y >= vmin) {
      if (first < 0) first = p;
      n = p - first + 1;
    }
  }
}

void main() {
  uint t = gl_GlobalInvocationID.x;
  uint map_bits = 0u;  // the list entry's map (batch)
  int rect = u_rect;
#ifdef BATCH
  uint map = u_map_base + gl_WorkGroupID.y;
  CausticsMap cm = batch_frame(map);
  u_texel = cm.texel.xy;
  g_tiles = int(cm.ints.w);
  g_planes = cm.ints.y;
  map_bits = map << kBatchPlaneBits;
  g_list = cm.list.xy;
  if (rect >= 0) rect = int(cm.list.z);
#endif
  if (rect >= 0) {
    // The k-th triangle of the rectangle: cell k / 2 of its columns x rows,
    // its triangle k % 2 (the grid's triangles are 2 per cell, row-major).
    uvec4 r = rects[2 * rect + 1];
    if (t >= r.w) return;
    uint per_row = 2u * r.z, row = t / per_row;
    t = 2u * (r.y + row) * rect_bounds[6] + 2u * r.x + (t - row * per_row);
  }
  int first, n;
  float vmin, vmax;
  select_planes(t, first, n, vmin, vmax);
  if (u_pairs == 0) {
    if (n == 0) return;
    uint slot = atomicAdd(cmd[8], 1u);
    if (slot < u_capacity) list[slot] = t; else atomicOr(cmd[9], 1u);
    return;
  }
  if (n == 0) return;
#ifdef BATCH
  uint counts = batch_counts(map), base = g_list.x, capacity = g_list.y;
#else
  uint counts = 8u, base = 0u, capacity = u_capacity;
#endif
  uint slot = atomicAdd(cmd[counts], uint(n));
  for (int k = 0; k < n; ++k) {
    if (slot + uint(k) >= capacity) {
      atomicOr(cmd[counts + 1u], 1u);
      return;
    }
    uint at = base + slot + uint(k);
    list[2u * at] = t;
    list[2u * at + 1u] = uint(first + k) | map_bits;
    // The part of the plane's window that the surface beneath fills, as
    // fractions of eps either side of the plane, rounded outwards: the
    // fragment shader moves the triangle to depths within it, and the draw
    // covers no more than that (caustics_intersect.vert).
    vec2 pl = PLANE(first + k);
    vec2 part = clamp((vec2(vmin, vmax) - pl.x) / max(pl.y, 1e-30), -1.0, 1.0);
    prim_words[16u * at + 15u] = packSnorm2x16(vec2(floor(part.x * 32767.0), ceil(part.y * 32767.0)) / 32767.0);
  }
}
