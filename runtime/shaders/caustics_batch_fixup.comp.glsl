#version 450 core
// A batch's bookkeeping around its cull (prefixed with caustics_batch.glsl),
// an invocation per map of the run u_map_base..:
//
// u_stage 0, before the cull: the run's cull dispatch, as many groups as
// the largest water rectangle of its maps needs (caustics_rects.comp) by
// one row of groups per map, so that a run of small receivers does not
// launch the whole grid's groups for each (words 4..6 of the run's first
// counts line, cleared with the counts).
//
// u_stage 1, after the cull: each map gets its entries drawn (its count,
// clamped to its part of the list) and its level-map draw command:
// caustics_fixup.comp, a map at a time.
layout(local_size_x = 64) in;
layout(std430, binding = 6) buffer Command { uint cmd[]; };
layout(std430, binding = 12) readonly buffer Rects {
  uint rect_bounds[8];
  uvec4 rects[];  // per map: its cull dispatch, its rectangle
};
uniform uint u_map_base;
uniform uint u_count;    // maps in the run
uniform int u_stage;     // 0: the cull's dispatch; 1: the draws
void main() {
  if (gl_GlobalInvocationID.x >= u_count) return;
  uint k = u_map_base + gl_GlobalInvocationID.x;
  if (u_stage == 0) {
    uint d = batch_cull_dispatch(u_map_base);
    atomicMax(cmd[d], rects[2u * batch_maps[k].list.z].x);
    if (gl_GlobalInvocationID.x == 0u) {
      cmd[d + 1u] = u_count;
      cmd[d + 2u] = 1u;
    }
    return;
  }
  uvec2 list = batch_maps[k].list.xy;
  uint n = min(cmd[batch_counts(k)], list.y);
  cmd[batch_counts(k) + 2u] = n;
  uint d = batch_draw(k);
  cmd[d] = 6u * n;  // DrawArraysIndirect {count, instances, first, base instance}
  cmd[d + 1u] = 1u;
  cmd[d + 2u] = 6u * list.x;
  cmd[d + 3u] = 0u;
}
