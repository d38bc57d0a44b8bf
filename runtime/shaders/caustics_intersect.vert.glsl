#version 450 core
// Draws the intersection triangles of caustics_geometry.comp, six vertices
// each (a quad as two triangles, or a triangle with its last vertex
// repeated), from gl_VertexID alone: no index buffer.
//
// Exact-coverage splatting (beyond the thesis): near folds the triangles
// are slivers far thinner than a texel, which point-sampled rasterisation
// would either miss or smear along whole texel rows, breaking energy
// conservation. So each triangle is drawn as a rectangle that contains it dilated by half a texel diagonal, so that every texel it
// touches gets a fragment, and the fragment shader deposits the irradiance
// times the exact area of the triangle inside the texel.
#ifndef PRIM_STRIDE
#define PRIM_STRIDE 4  // vec4s per primitive (glass: 6, defined by the renderer)
#endif
layout(std430, binding = 8) readonly buffer Primitives { vec4 prims[]; };
#ifdef DEPTH_SHIFT
// Water caustics' directions, pairs of half floats (caustics_geometry.comp).
layout(std430, binding = 8) readonly buffer PrimitiveWords { uint prim_words[]; };
#endif

#ifdef BATCH
// Each primitive in its map's layer (caustics_batch.glsl, prefixed with
// GL_ARB_shader_viewport_layer_array): its side and texels from the map.
// caustics_levelmap.frag reads the rest of the map itself: a software
// rasteriser runs the vertices on one thread and sets up every varying
// of every primitive, most of which cover a texel or two.
float u_map_size = 1.0;
vec2 u_texels_per_metre = vec2(0.0);
#else
uniform float u_map_size;
#endif
#ifdef TEXEL_MAP
// Glass focus windows: the primitives are in the main
// texture's texels; this texture's are (q - xy) * z. The window's wide
// ones are GLASS_WIDE's (glass_window_split.glsl, prefixed).
uniform vec3 u_texel_map;
#endif
#if defined(DEPTH_SHIFT) && !defined(BATCH)
uniform vec2 u_texels_per_metre;  // caustics_levelmap.frag moves each vertex by up to eps (s_u, s_w), its own direction
#endif
// WINDOW_DEPTH (level maps): plane k's primitives at depth (k + 1) / 65535,
// where caustics_windows.frag put the texels whose surface is lit through
// k. Exact in the 16-bit depth buffer, as the depth test (GL_EQUAL) needs.

#ifdef GLASS_TENT
uniform int u_tent;  // CausticsOptions::glass_focus_tent, in a focus window
#endif
flat out int v_prim;  // the fragment shader fetches the primitive itself (one varying to set up)

void main() {
  int prim = gl_VertexID / 6;
  vec4 p0 = prims[PRIM_STRIDE * prim];
  vec4 p1 = prims[PRIM_STRIDE * prim + 1];
  vec2 q0 = p0.xy, q1 = p0.zw, q2 = p1.xy;
  float window = p1.w;  // the plane's index + 1 (caustics_geometry.comp)
#ifdef BATCH
  if (p1.w > 0.0) {
    CausticsMap cm = batch_maps[batch_prim_map(p1.w)];
    u_map_size = cm.origin.w;
    u_texels_per_metre = cm.texel.zw;
    gl_Layer = int(cm.ints.x);
    window = batch_prim_window(p1.w);
  }
#endif
#ifdef TEXEL_MAP
  q0 = (q0 - u_texel_map.xy) * u_texel_map.z;
  q1 = (q1 - u_texel_map.xy) * u_texel_map.z;
  q2 = (q2 - u_texel_map.xy) * u_texel_map.z;
#ifdef GLASS_WIDE
  const bool wide_pass = true;
#else
  const bool wide_pass = false;
#endif
  if (glass_window_wide(q0, q1, q2) != wide_pass) {  // the other program draws it
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
#endif
  v_prim = prim;
  float delta = 0.7072;  // half a texel diagonal, rounded up
#ifdef GLASS_TENT
  // glass_illumination.frag's tent reaches a texel from a triangle up to a
  // texel away along each axis: a centre within a whole diagonal.
  if (u_tent != 0) delta = 1.4143;
#endif
#ifdef DEPTH_SHIFT
  // caustics_levelmap.frag moves vertex k by (v - D) s_k to the receiver's
  // depth v, which the cull bounded to D + shift +- reach
  // (caustics_geometry.comp): the triangle at D + shift, dilated by how
  // far a vertex moves over +- reach, holds it at every such depth. (Over
  // the whole window, +- eps, the 8 x 8 m pool's 16 mm texels had the
  // draw shade 4.0 M fragments a frame with 4 objects for 1.2 M kept;
  // with the surface's part of it, 2.2 M: docs/runtime-speed.md.)
  vec4 p2 = prims[PRIM_STRIDE * prim + 2];
  float shift = p2.y, reach = p2.z;
  int words = 4 * PRIM_STRIDE * prim;
  vec2 s0 = unpackHalf2x16(prim_words[words + 11]) * u_texels_per_metre;
  vec2 s1 = unpackHalf2x16(prim_words[words + 12]) * u_texels_per_metre;
  vec2 s2 = unpackHalf2x16(prim_words[words + 13]) * u_texels_per_metre;
  q0 += shift * s0;
  q1 += shift * s1;
  q2 += shift * s2;
  delta += reach * max(length(s0), max(length(s1), length(s2)));
#endif
  // Quad corners (0,0) (1,0) (0,1) (1,1), drawn as triangles 0-1-3 and 0-3-2.
  int j = gl_VertexID % 6;
  int k = j == 0 || j == 3 ? 0 : j == 1 ? 1 : j == 5 ? 2 : 3;
  vec2 p;
  // A well-shaped triangle (every angle >= 15 degrees) is dilated itself:
  // each vertex moves out along its bisector by delta / sin(angle / 2), so
  // the triangle grows by delta on every side; vertex 3 repeats vertex 2, so
  // the second triangle of the quad is empty.
  vec2 e01 = q1 - q0, e12 = q2 - q1, e20 = q0 - q2;
  float twice = e01.x * (-e20.y) - e01.y * (-e20.x);  // signed double area
  float l01 = length(e01), l12 = length(e12), l20 = length(e20);
  float sin_min = min(min(abs(twice) / (l01 * l20), abs(twice) / (l01 * l12)), abs(twice) / (l12 * l20));
  if (l01 > 0.0 && l12 > 0.0 && l20 > 0.0 && sin_min > 0.2588) {
    float s = sign(twice);
    // Outward unit normals of the edges.
    vec2 n01 = s * vec2(e01.y, -e01.x) / l01, n12 = s * vec2(e12.y, -e12.x) / l12, n20 = s * vec2(e20.y, -e20.x) / l20;
    vec2 v = k == 0 ? q0 : k == 1 ? q1 : q2;
    vec2 na = k == 0 ? n20 : k == 1 ? n01 : n12;  // the two edges meeting at v
    vec2 nb = k == 0 ? n01 : k == 1 ? n12 : n20;
    p = v + delta * (na + nb) / (1.0 + dot(na, nb));
  } else {
    // Otherwise (slivers near folds): the rectangle on the longest edge a-b
    // and the height of the third vertex c (whose projection falls between
    // a and b), dilated by delta. Written without arrays: dynamic indexing
    // is slow on some vertex paths.
    vec2 a = q0, b = q1, c = q2;
    float longest = l01;
    if (l12 > longest) { a = q1; b = q2; c = q0; longest = l12; }
    if (l20 > longest) { a = q2; b = q0; c = q1; longest = l20; }
    vec2 along = longest > 0.0 ? (b - a) / longest : vec2(1.0, 0.0);
    vec2 across = vec2(-along.y, along.x);
    float h = dot(c - a, across);
    float lo = min(0.0, h) - delta, hi = max(0.0, h) + delta;
    p = a + along * mix(-delta, longest + delta, float(k & 1)) + across * mix(lo, hi, float(k >> 1));
  }
  float z = 0.0;
#ifdef WINDOW_DEPTH
  z = window * (2.0 / 65535.0) - 1.0;  // window depth (k + 1) / 65535
#endif
  gl_Position = p1.w > 0.0 ? vec4(p / u_map_size * 2.0 - 1.0, z, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
#ifdef GLASS_WIDE
  glass_wide_corner(q0, q1, q2, p, p1, prims[PRIM_STRIDE * prim + 2], prims[PRIM_STRIDE * prim + 3], prims[PRIM_STRIDE * prim + 4],
                    prims[PRIM_STRIDE * prim + 5]);
#endif
}
