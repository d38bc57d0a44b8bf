#version 450 core
// The intersection triangle of each listed (illumination volume, reference
// plane) pair (Tipprasert 2006 §4.4-4.5), in caustics-map texels, and its
// irradiance on the plane by eq. 4-18,
//   I_c = E_in T (A_w cos theta_i) / A_d,
// with A_d its area on the plane (perpendicular to V); cos theta_t and
// e^(-K d) are applied where the map is cast (§4.6), per receiver point.
// A_d is kept above beam / max_magnification so folds where rays cross stay
// finite (docs/caustics.md states the bound). Computed here rather than per
// vertex: compute runs in parallel where vertex processing may not.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 2) readonly buffer Indices { uint indices[]; };
layout(std430, binding = 3) readonly buffer Refracted { vec4 refracted[]; };
layout(std430, binding = 4) readonly buffer Flux { vec2 flux[]; };
layout(std430, binding = 5) readonly buffer List { uint list[]; };
layout(std430, binding = 6) readonly buffer Command { uint cmd[]; };
// The planes (binding 7): caustics_windows.glsl, prefixed.
// Per primitive, four vec4 (16 words; caustics_intersect.vert and
// caustics_coverage.glsl read them):
// (q0, q1), (q2, irradiance, reached), (plane offset D, shift, reach, s0)
// and (s1, s2, c0 c1, c2): s_k and c_k each a pair of half floats in one
// word. c_k: the corners' irradiance over the triangle's (below; c0 = -1
// where they are the triangle's own). The fragment shader moves the
// triangle from D to the receiver's depth within the plane's window; the
// cull found that depth within D + shift +- reach (metres), so the draw
// covers the triangle there and no wider (caustics_intersect.vert). s_k:
// vertex k's direction of travel d as (d.U / d.V, d.W / d.V). Their mean is
// the beam's, so that a receiver with normal n gets
// I_c (n.V + s_u n.U + s_w n.W) = I_c n.d / V.d (beyond the thesis, whose
// casting takes n.V: under waves the light does not arrive along V,
// docs/caustics.md "Local light direction"); each vertex's carries it from
// the plane to the receiver's depth (caustics_levelmap.frag). Half floats
// (11 significant bits) move a vertex by at most 2^-11 |s| (v - D), under
// 0.1 mm over a 10 cm window, and the corners' rounding keeps the
// triangle's flux (corner_factor divides by their own mean).
layout(std430, binding = 8) writeonly buffer Primitives { uvec4 prims[]; };
// The same, as words: the cull left a pair's depths in word 15 of its
// primitive (caustics_cull.comp), read here before the primitive is.
layout(std430, binding = 8) readonly buffer PrimitiveWords { uint prim_words[]; };

#ifdef BATCH
uniform uint u_map_base;
// The primitive's map (caustics_batch.glsl), read from its list entry.
float u_map_size;
#else
uniform vec3 u_origin;
uniform vec3 u_U;
uniform vec3 u_V;
uniform vec3 u_W;
uniform vec3 u_half;
uniform float u_map_size;
#endif
uniform int u_pairs;      // list holds (volume, plane) pairs; else volumes and plane u_plane
uniform int u_plane;
uniform float u_max_magnification;
uniform uvec2 u_grid;     // water grid vertices along x and z (index j * u_grid.x + i)
uniform int u_smooth;     // CausticsOptions::water_smooth

// Where vertex j's refracted ray meets the plane at v = plane_v, in metres
// along (U, W); w < 0 where it does not (no ray, or the plane above it).
vec3 on_plane(uint j, float plane_v) {
  vec3 rel = positions[j].xyz - u_origin;
  vec4 dir = refracted[j];
  float s = (dot(rel, u_V) - plane_v) / -dot(dir.xyz, u_V);
  vec3 pt = rel + s * dir.xyz;
  return vec3(dot(pt, u_U), dot(pt, u_W), dir.w > 0.0 && s >= 0.0 ? 1.0 : -1.0);
}

// Smooth caustics (moire in caustic lines). Eq. 4-18 gives each
// water triangle one irradiance, so the caustics map is a mosaic of the
// water grid's triangles, and the mosaic beats against the pixels. A
// corner's irradiance is estimated from the grid around its vertex instead:
// the triangle's flux per unit water area times the ratio of the water's
// local area to its image's on the plane, both from central differences
// (one-sided at the border), with the triangle's magnification clamp. The
// corners' ratios to the triangle's own irradiance go to the fragment
// shaders, which interpolate them and rescale so that the triangle keeps
// its flux exactly (the mean of a linear function over a triangle is its
// corners'). Triangles at folds (a ratio beyond 10x either way) keep the
// paper's constant: interpolating across a fold would smear its line; from
// 5x to 10x the corners fade to it.
float corner_ratio(uint j, float plane_v, float flux_per_area, float beam_per_area, float irradiance) {
  uint gx = u_grid.x, ix = j % gx, iz = j / gx;
  uint xm = ix > 0u ? j - 1u : j, xp = ix + 1u < gx ? j + 1u : j;
  uint zm = iz > 0u ? j - gx : j, zp = iz + 1u < u_grid.y ? j + gx : j;
  vec3 a = on_plane(xm, plane_v), b = on_plane(xp, plane_v), c = on_plane(zm, plane_v), d = on_plane(zp, plane_v);
  if (min(min(a.z, b.z), min(c.z, d.z)) < 0.0) return -1.0;
  vec2 du = b.xy - a.xy, dw = d.xy - c.xy;
  float plane_area = abs(du.x * dw.y - du.y * dw.x);
  float water_area = length(cross(positions[xp].xyz - positions[xm].xyz, positions[zp].xyz - positions[zm].xyz));
  if (water_area <= 0.0) return -1.0;
  float e = flux_per_area * water_area / max(plane_area, beam_per_area * water_area / u_max_magnification);
  return e / max(irradiance, 1e-30);
}

void make_primitive(uint p) {
  uint t = u_pairs != 0 ? list[2u * p] : list[p];
  uint plane_index = u_pairs != 0 ? list[2u * p + 1u] : uint(u_plane);
  // The window's part the surface fills, in eps (caustics_cull.comp); all
  // of it outside pair mode.
  vec2 part = u_pairs != 0 ? unpackSnorm2x16(prim_words[16u * p + 15u]) : vec2(-1.0, 1.0);
  float window_bits = 0.0;  // the map, in the primitive's w (batch)
#ifdef BATCH
  uint map = batch_entry_map(plane_index);
  plane_index = batch_entry_plane(plane_index);
  CausticsMap cm = batch_frame(map);
  u_map_size = cm.origin.w;
  g_planes = cm.ints.y;
  window_bits = float(map << kBatchPlaneBits);
#endif
  vec2 plane = PLANE(plane_index);
  vec2 to_texels = u_map_size / (2.0 * u_half.xz);
  vec2 q[3];
  vec2 slopes[3];
  bool reached = true;
  for (int k = 0; k < 3; ++k) {
    uint i = indices[3u * t + uint(k)];
    vec3 rel = positions[i].xyz - u_origin;
    vec3 dir = refracted[i].xyz;
    float s = (dot(rel, u_V) - plane.x) / -dot(dir, u_V);
    reached = reached && s >= 0.0;  // a plane above the water point is not lit through it
    slopes[k] = vec2(dot(dir, u_U), dot(dir, u_W)) / min(dot(dir, u_V), -1e-6);
    vec3 pt = rel + s * dir;
    q[k] = (vec2(dot(pt, u_U), dot(pt, u_W)) + u_half.xz) * to_texels;  // texel coordinates
  }
  // Areas in texels; the irradiance is flux over the area in metres.
  float texel_area = 1.0 / (to_texels.x * to_texels.y);
  float area = 0.5 * abs((q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y));
  vec2 f = flux[t];
  float irradiance = f.x / max(area * texel_area, f.y / u_max_magnification);
  vec3 corners = vec3(-1.0, 1.0, 1.0);
  if (u_smooth != 0 && reached && irradiance > 0.0) {
    uint i0 = indices[3u * t], i1 = indices[3u * t + 1u], i2 = indices[3u * t + 2u];
    float water_tri = 0.5 * length(cross(positions[i1].xyz - positions[i0].xyz, positions[i2].xyz - positions[i0].xyz));
    if (water_tri > 0.0) {
      vec3 c = vec3(corner_ratio(i0, plane.x, f.x / water_tri, f.y / water_tri, irradiance),
                    corner_ratio(i1, plane.x, f.x / water_tri, f.y / water_tri, irradiance),
                    corner_ratio(i2, plane.x, f.x / water_tri, f.y / water_tri, irradiance));
      // Towards a fold the corners fade to the constant: fully theirs up
      // to a spread of 5x, the constant from 10x, linear in the log
      // between. A switch at 10x moved a triangle's light within it at
      // once when the moving water took its spread across, and the
      // caustics map's texels along the folds jumped from frame to frame
      // (docs/temporal.md).
      float spread = max(max(max(c.x, c.y), c.z), 1.0 / max(min(min(c.x, c.y), c.z), 1e-30));
      float keep = min(c.x, min(c.y, c.z)) > 0.0 ? clamp(log2(10.0 / spread), 0.0, 1.0) : 0.0;
      if (keep > 0.0) corners.xyz = mix(vec3(1.0), c, keep);
    }
  }
  // w: 0 where the plane is not reached, else the plane's index + 1 (the
  // level-map draw's depth, caustics_windows.frag; in a batch plus 8192
  // times the map, caustics_batch.glsl).
  float window = reached ? float(plane_index + 1u) + window_bits : 0.0;
  float reach = 0.5 * (part.y - part.x) * plane.y;
  prims[4u * p] = floatBitsToUint(vec4(q[0], q[1]));
  prims[4u * p + 1u] = floatBitsToUint(vec4(q[2], irradiance, window));
  prims[4u * p + 2u] = uvec4(floatBitsToUint(vec3(plane.x, 0.5 * (part.x + part.y) * plane.y, reach)), packHalf2x16(slopes[0]));
  prims[4u * p + 3u] = uvec4(packHalf2x16(slopes[1]), packHalf2x16(slopes[2]), packHalf2x16(corners.xy), packHalf2x16(vec2(corners.z, 0.0)));
}

void main() {
#ifdef BATCH
  // The maps u_map_base.. a row of work groups each, over their own part
  // of the list; a row has at most 65535 groups (GL's least limit), each
  // invocation taking every such stride's entry.
  uint run_map = u_map_base + gl_WorkGroupID.y;
  uint n = cmd[batch_counts(run_map) + 2u], first = batch_maps[run_map].list.x;
  for (uint k = gl_GlobalInvocationID.x; k < n; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x) make_primitive(first + k);
#else
  uint p = gl_GlobalInvocationID.x;
  if (p < cmd[10]) make_primitive(p);
#endif
}
