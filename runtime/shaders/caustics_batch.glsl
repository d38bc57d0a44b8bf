// A light's level maps drawn together (BATCH, beyond the thesis): the
// maps of one caustics-map size and one position-map size share a texture
// array each, a map to a layer, and one cull, one geometry pass and one
// draw serve them all, so that the calls a frame makes do not grow with
// the receivers (docs/runtime-speed.md, "As the scene grows"). Prefixed,
// after #version, to the batch's shaders; the engine fills the buffer
// (caustics.cpp, BatchMap) with the maps of the batch, in its order.
struct CausticsMap {
  vec4 origin;     // xyz: the frame's origin; w: the caustics map's side in texels
  vec4 u;          // xyz: the frame's U; w: position-map texels per caustics texel
  vec4 v;          // xyz: V
  vec4 w;          // xyz: W
  vec4 half_size;  // xyz: the frame's half-extents along U, V, W
  vec4 texel;      // xy: the cull's footprint widening along U, W (m); zw: caustics texels per metre along U, W
  uvec4 ints;      // x: layer of the caustics array, y: its planes' offset (words), z: samples per axis, w: layer of the position maps' array
  uvec4 list;      // x: its first entry in the shared list, y: the entries it has room for (in the run of maps drawn),
                   // z: its water rectangle (caustics_rects.comp)
};
layout(std430, binding = 11) readonly buffer BatchMaps { CausticsMap batch_maps[]; };

// The frame of the map at hand, where the cull and the geometry pass of a
// map drawn alone have their uniforms; batch_frame sets it and returns the
// map.
vec3 u_origin, u_U, u_V, u_W, u_half;
CausticsMap batch_frame(uint map) {
  CausticsMap cm = batch_maps[map];
  u_origin = cm.origin.xyz;
  u_U = cm.u.xyz;
  u_V = cm.v.xyz;
  u_W = cm.w.xyz;
  u_half = cm.half_size.xyz;
  return cm;
}

// The batch's command buffer (binding 6), in words: from 16, per map its
// count of entries, overflow and entries drawn, 64 bytes apart (the
// culls of different maps add to them at once: a cache line each; the
// first map of a run keeps the run's cull dispatch in words 4..6 of its
// line); then per map its level-map draw {count, 1, first, 0}
// (glMultiDrawArraysIndirect); u_batch_maps maps each.
uniform uint u_batch_maps;
uint batch_counts(uint k) { return 16u + 16u * k; }
uint batch_cull_dispatch(uint k) { return batch_counts(k) + 4u; }
uint batch_draw(uint k) { return 16u + 16u * u_batch_maps + 4u * k; }

// A list entry's plane and map (caustics_cull.comp packs them in one word:
// plane indices stay below 8192, kMaxPlanes), and a primitive's window
// depth and map (caustics_geometry.comp's w: plane + 1 + 8192 map, an
// integer a float holds exactly below 2^24).
const uint kBatchPlaneBits = 13u;
uint batch_entry_plane(uint e) { return e & ((1u << kBatchPlaneBits) - 1u); }
uint batch_entry_map(uint e) { return e >> kBatchPlaneBits; }
uint batch_prim_map(float w) { return uint(w - 1.0) >> kBatchPlaneBits; }
float batch_prim_window(float w) { return float(uint(w - 1.0) & ((1u << kBatchPlaneBits) - 1u)) + 1.0; }
