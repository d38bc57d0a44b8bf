#version 450 core
// After a batch's cull (prefixed with caustics_batch.glsl): each map of the
// run u_map_base.. gets its entries drawn (its count, clamped to its part
// of the list) and its level-map draw command, and a several-windows
// command with no vertices, which caustics_windows.frag gives the first's
// count where the map has such texels: caustics_fixup.comp, a map at a
// time.
layout(local_size_x = 64) in;
layout(std430, binding = 6) buffer Command { uint cmd[]; };
uniform uint u_map_base;
uniform uint u_count;  // maps in the run
void main() {
  if (gl_GlobalInvocationID.x >= u_count) return;
  uint k = u_map_base + gl_GlobalInvocationID.x;
  uvec2 list = batch_maps[k].list.xy;
  uint n = min(cmd[batch_counts(k)], list.y);
  cmd[batch_counts(k) + 2u] = n;
  uint d = batch_draw(k), d2 = batch_draw2(k);
  cmd[d] = 6u * n;  // DrawArraysIndirect {count, instances, first, base instance}
  cmd[d + 1u] = 1u;
  cmd[d + 2u] = 6u * list.x;
  cmd[d + 3u] = 0u;
  cmd[d2] = 0u;
  cmd[d2 + 1u] = 1u;
  cmd[d2 + 2u] = 6u * list.x;
  cmd[d2 + 3u] = 0u;
}
