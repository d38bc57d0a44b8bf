#version 450 core
// Beyond the thesis: the part of the water grid whose light can reach each
// map's frame, so that the cull (caustics_cull.comp) reads those water
// triangles only, not the whole grid once per map. One invocation per map.
//
// caustics_prepare.comp bounded, over this frame's water, the refracted
// rays' horizontal travel per metre of descent, g = (d.x, d.z) / -d.y, and
// the water's height y. A point p of the frame's box (its world box here)
// is reached from water at height y_w >= p.y by a ray only from
// x_w = p_xz - t g with t = y_w - p.y, so from the rectangle of the box's
// xz range moved by every t g with t in [max(0, y_lo - box_hi),
// y_hi - box_lo] and g within its bounds (t g is bilinear: its extremes lie
// at the corners). A triangle's beam is the convex combination of its
// rays, each within the bounds, so every triangle that can light the box
// has a cell there. Unbounded g (a ray not heading down) takes the grid.
layout(local_size_x = 64) in;

// caustics_prepare.comp's bounds (words 0-5) and the grid's cells along x
// (word 6, for the cull), then per map two uvec4: the cull's dispatch
// (groups, 1, 1) and its rectangle (first column, first row, columns,
// triangles).
layout(std430, binding = 12) buffer Rects {
  uint bounds[8];
  uvec4 rects[];
};
layout(std430, binding = 13) readonly buffer Boxes { vec4 boxes[]; };  // per map: world box lo.xyz, hi.xyz

uniform uint u_count;   // maps
uniform uvec2 u_cells;  // water cells along x and z
uniform vec4 u_extent;  // the grid's x0, z0, x1, z1

float decode(uint u) { return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u); }

void no_triangles(uint i) {
  rects[2u * i] = uvec4(0u, 1u, 1u, 0u);
  rects[2u * i + 1u] = uvec4(0u);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i == 0u) bounds[6] = u_cells.x;
  if (i >= u_count) return;
  vec3 lo = boxes[2u * i].xyz, hi = boxes[2u * i + 1u].xyz;
  // Minima of gx, gz, y, then of their negatives (the maxima).
  vec3 b_lo = vec3(decode(bounds[0]), decode(bounds[1]), decode(bounds[2]));
  vec3 b_hi = -vec3(decode(bounds[3]), decode(bounds[4]), decode(bounds[5]));
  // No ray heading down (or none at all: no bound was written), or the
  // box above the water: no triangle reaches it.
  float t0 = max(0.0, b_lo.z - hi.y), t1 = b_hi.z - lo.y;
  if (bounds[0] == 0xffffffffu || !(t1 >= 0.0)) {
    no_triangles(i);
    return;
  }
  vec2 g_lo = b_lo.xy, g_hi = b_hi.xy;
  vec2 m_lo = min(min(t0 * g_lo, t0 * g_hi), min(t1 * g_lo, t1 * g_hi));
  vec2 m_hi = max(max(t0 * g_lo, t0 * g_hi), max(t1 * g_lo, t1 * g_hi));
  vec2 w_lo = lo.xz - m_hi, w_hi = hi.xz - m_lo;
  // In cells, a cell more on every side for rounding; the grid where a
  // bound is not finite.
  vec2 cells = vec2(u_cells);
  vec2 to_cells = cells / (u_extent.zw - u_extent.xy);
  vec2 c_lo = floor((w_lo - u_extent.xy) * to_cells) - 1.0, c_hi = floor((w_hi - u_extent.xy) * to_cells) + 1.0;
  bvec2 finite = lessThan(abs(c_lo) + abs(c_hi), vec2(1e30));  // false for inf and NaN
  c_lo = mix(vec2(0.0), clamp(c_lo, vec2(0.0), cells), finite);
  c_hi = mix(cells - 1.0, clamp(c_hi, vec2(-1.0), cells - 1.0), finite);
  if (any(lessThan(c_hi, c_lo))) {
    no_triangles(i);
    return;
  }
  uvec2 first = uvec2(c_lo), span = uvec2(c_hi - c_lo) + 1u;
  uint triangles = 2u * span.x * span.y;
  rects[2u * i] = uvec4((triangles + 63u) / 64u, 1u, 1u, 0u);
  rects[2u * i + 1u] = uvec4(first, span.x, triangles);
}
