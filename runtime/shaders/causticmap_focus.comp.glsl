#version 450 core
// causticmap_focus.comp: where the caustic map needs finer texels (issue
// 47's focus window; the tables' counterpart is glass.cpp's focus_window).
// Placed from where this update's photons landed, on the GPU, so nothing
// waits for a read-back:
//   stage 0, one invocation per photon slot (the photon pass's grid or
//     its adaptive leaves): each landed photon adds its weight, the
//     finest-grid photons it stands for (spacing^2), to one of
//     kBins x kBins cells over the map;
//   stage 1, one work group: a cell is concentrated where at least
//     u_min_count photons landed in it -- kConcentration times the photons
//     its area would catch straight from the light, and at least
//     kMinPhotons -- and the window is the square around the concentrated
//     cells and one cell more, no smaller than u_min_half and dropped
//     above u_max_half (the main map does nearly as well there).
// The window, (centre s, centre t, half-size, 1) in the main map's texture
// coordinates (half-size 0: none), goes to the Focus buffer, which the
// window's splats read, and to the map's last texel, which the shading
// (caustix.glsl's caustix_caustic_map_irradiance) reads.
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Photons { vec4 photon[]; };  // 2 per photon: (s, t, spacing, -), (flux, alive)
layout(std430, binding = 5) readonly buffer State { uint list_count[2]; uint leaves; };  // adaptive: the leaves traced
layout(std430, binding = 6) buffer Focus { vec4 window; uint bins[]; };
layout(rgba32f, binding = 0) writeonly uniform image2D u_map;
const int kBins = 128;  // gl/focus_window.h
uniform int u_stage;
uniform int u_photons;     // grid side (uniform grid)
uniform int u_adaptive;
uniform float u_min_count;
uniform float u_min_half, u_max_half;
uniform ivec2 u_params;    // the map's texel that carries the window

shared ivec4 box;  // (lo s, lo t, hi s, hi t) in cells

void main() {
  if (u_stage == 0) {
    int id;
    if (u_adaptive != 0) {
      id = int(gl_WorkGroupID.x * 64u + gl_LocalInvocationIndex);
      if (uint(id) >= leaves) return;
    } else {
      ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
      if (ij.x >= u_photons || ij.y >= u_photons) return;
      id = ij.y * u_photons + ij.x;
    }
    vec4 a = photon[2 * id], b = photon[2 * id + 1];
    if (b.w <= 0.0) return;
    ivec2 c = ivec2(floor(a.xy * float(kBins)));
    if (any(lessThan(c, ivec2(0))) || any(greaterThanEqual(c, ivec2(kBins)))) return;
    atomicAdd(bins[c.y * kBins + c.x], uint(a.z * a.z));
    return;
  }
  if (gl_LocalInvocationIndex == 0u) box = ivec4(kBins, kBins, -1, -1);
  barrier();
  ivec4 mine = ivec4(kBins, kBins, -1, -1);
  for (int c = int(gl_LocalInvocationIndex); c < kBins * kBins; c += 64) {
    if (float(bins[c]) < u_min_count) continue;
    ivec2 ij = ivec2(c % kBins, c / kBins);
    mine = ivec4(min(mine.xy, ij), max(mine.zw, ij));
  }
  atomicMin(box.x, mine.x);
  atomicMin(box.y, mine.y);
  atomicMax(box.z, mine.z);
  atomicMax(box.w, mine.w);
  barrier();
  if (gl_LocalInvocationIndex != 0u) return;
  vec4 w = vec4(0.0, 0.0, 0.0, 1.0);
  if (box.z >= 0) {
    // Cell i spans [i, i + 1] / kBins; one cell more on every side.
    vec2 lo = vec2(box.xy - 1) / float(kBins), hi = vec2(box.zw + 2) / float(kBins);
    float half_size = max(max(0.5 * (hi.x - lo.x), 0.5 * (hi.y - lo.y)), u_min_half);
    if (half_size <= u_max_half) w.xyz = vec3(0.5 * (lo + hi), half_size);
  }
  window = w;
  imageStore(u_map, u_params, w);
}
