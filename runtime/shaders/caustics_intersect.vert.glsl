#version 450 core
// Draws the intersection triangles of caustics_geometry.comp, six vertices
// (two triangles of a rectangle) each.
//
// Exact-coverage splatting (beyond the thesis): near folds the triangles
// are slivers far thinner than a texel, which point-sampled rasterisation
// would either miss or smear along whole texel rows, breaking energy
// conservation. So each triangle is drawn as a rectangle that contains it dilated by half a texel diagonal, so that every texel it
// touches gets a fragment, and the fragment shader deposits the irradiance
// times the exact area of the triangle inside the texel.
layout(std430, binding = 8) readonly buffer Primitives { vec4 prims[]; };

uniform float u_map_size;

flat out int v_prim;  // the fragment shader fetches the primitive itself (one varying to set up)

void main() {
  int prim = gl_VertexID / 6;
  vec4 p0 = prims[3 * prim];
  vec4 p1 = prims[3 * prim + 1];
  vec2 q0 = p0.xy, q1 = p0.zw, q2 = p1.xy;
  v_prim = prim;
  // The rectangle on the longest edge a-b and the height of the third
  // vertex c (whose projection falls between a and b), dilated by delta.
  // Written without arrays: dynamic indexing is slow on some vertex paths.
  float l01 = distance(q0, q1), l12 = distance(q1, q2), l20 = distance(q2, q0);
  vec2 a = q0, b = q1, c = q2;
  float longest = l01;
  if (l12 > longest) { a = q1; b = q2; c = q0; longest = l12; }
  if (l20 > longest) { a = q2; b = q0; c = q1; longest = l20; }
  vec2 along = longest > 0.0 ? (b - a) / longest : vec2(1.0, 0.0);
  vec2 across = vec2(-along.y, along.x);
  float h = dot(c - a, across);
  const float delta = 0.7072;  // half a texel diagonal, rounded up
  float lo = min(0.0, h) - delta, hi = max(0.0, h) + delta;
  // Corners of the two triangles (0,0) (1,0) (1,1) / (0,0) (1,1) (0,1).
  int k = gl_VertexID % 6;
  float cx = (k == 1 || k == 2 || k == 4) ? 1.0 : 0.0;
  float cy = (k == 2 || k == 4 || k == 5) ? 1.0 : 0.0;
  vec2 p = a + along * mix(-delta, longest + delta, cx) + across * mix(lo, hi, cy);
  gl_Position = p1.w > 0.0 ? vec4(p / u_map_size * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
}
