#version 450 core
// Smooth glass caustics (the glass ball's shadow ring had radial
// spokes and concentric steps; CausticsOptions::glass_smooth). Iwasaki et al.'s
// eq. 3 gives each intersection triangle one intensity I_t = flux / area on
// the plane, so a caustic made of a faceted mesh's triangles is piecewise
// constant: every facet of the ball prints a wedge. Here each whole
// (untorn, fully lit) triangle gets an intensity per corner: the mean of
// the triangles around that corner weighted by their areas on the plane,
// sum(I S0) / sum(S0), over those within a factor of 10 of I_t -- so that
// a real discontinuity (the bright line under a glass cube's edge, 10^2 to
// 10^4 times its flat face's light) is not smeared across, while the
// ball's facets (adjacent wedges up to ~5 times apart near the shadow
// ring: a factor of 2 left spread 0.098, 4 left 0.042, 10 reaches 0.024)
// are. The illumination pass interpolates
// the corners across the triangle and scales them so that the triangle
// keeps eq. 3's flux (the mean of a linear function over a triangle is
// its corners' mean). Stored as ratios to I_t in the w of primitive slots
// 3-5; corner beams keep their constant intensity.
layout(local_size_x = 64) in;

layout(std430, binding = 4) readonly buffer Indices { uint indices[]; };
layout(std430, binding = 8) buffer Primitives { vec4 prims[]; };
layout(std430, binding = 9) readonly buffer RingOffsets { uint ring_offsets[]; };   // vertex v: [offsets[v], offsets[v + 1])
layout(std430, binding = 10) readonly buffer RingTriangles { uint ring_triangles[]; };

uniform uint u_triangle_count;
uniform uint u_plane_count;

const float kSimilar = 10.0;

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

void main() {
  uint tp = gl_GlobalInvocationID.x;  // plane * T + t
  if (tp >= u_triangle_count * u_plane_count) return;
  uint t = tp % u_triangle_count, plane = tp / u_triangle_count, p = 3u * tp;
  vec4 meta = prims[6u * p + 1u];  // (q2, S0 in texels (-1: corner beams), reached)
  if (meta.w <= 0.0 || meta.z <= 0.0) return;
  float own = luminance(prims[6u * p + 2u].rgb);
  for (uint k = 0u; k < 3u; ++k) {
    uint v = indices[3u * t + k];
    float flux = 0.0, area = 0.0;
    for (uint r = ring_offsets[v]; r < ring_offsets[v + 1u]; ++r) {
      uint q = 3u * (plane * u_triangle_count + ring_triangles[r]);
      vec4 m = prims[6u * q + 1u];
      if (m.w <= 0.0 || m.z <= 0.0) continue;
      float other = luminance(prims[6u * q + 2u].rgb);
      if (other > kSimilar * own || own > kSimilar * other) continue;
      flux += other * m.z;
      area += m.z;
    }
    prims[6u * p + 3u + k].w = own > 0.0 && area > 0.0 ? flux / (area * own) : 1.0;
  }
}
