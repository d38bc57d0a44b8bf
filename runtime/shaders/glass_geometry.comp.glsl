#version 450 core
// Iwasaki et al. §4.1-4.2: the intersection triangle of each (transparent
// triangle's illumination volume, virtual plane) pair, in illumination-
// texture texels, with the incident intensity of eq. 3 except cos(gamma):
//   E_in cos(theta) F_t S / (S_0 cos(delta)),
// F_t (with absorption) the mean over the triangle's three outgoing rays,
// S its area, theta its angle to the light, S_0 the intersection
// triangle's area and delta the angle between the rays' mean direction
// and the plane normal. S_0 is kept above S cos(theta) / max_magnification
// (as for water, docs/caustics.md) by widening the triangle, which keeps
// its flux (below). Three primitives per (triangle,
// plane), p = (plane * triangles + t) * 3 + slot: slot 0 the triangle's
// volume; or, where it is torn between two path classes, its up to three
// parts cut at the switch; or, where some corners pass no light, one
// corner beam per slot (below). Each: (q0, q1), (q2, S0 in texels or -1 for
// a corner beam or a part, drawn at its constant intensity, reached), (rgb
// intensity, -), d0, d1, d2.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };
layout(std430, binding = 2) readonly buffer Rays { vec4 rays[]; };
layout(std430, binding = 4) readonly buffer Indices { uint indices[]; };
layout(std430, binding = 8) writeonly buffer Primitives { vec4 prims[]; };

uniform uint u_triangle_count;
uniform uint u_plane_count;
uniform float u_plane_v[16];
uniform mat4 u_model;
uniform int u_light_type;
uniform vec3 u_light_direction;
uniform vec3 u_light_position;
uniform float u_light_power;
uniform vec3 u_spot;  // a spot's cone about u_light_direction (caustix_spot_factor)
uniform vec3 u_origin;
uniform vec3 u_U;
uniform vec3 u_V;
uniform vec3 u_W;
uniform vec3 u_half;
uniform float u_map_size;
uniform float u_max_magnification;

// The rotation taking unit a onto unit b, applied to x (Rodrigues).
vec3 rotate_onto(vec3 a, vec3 b, vec3 x) {
  vec3 v = cross(a, b);
  float c = dot(a, b);
  if (c < -0.999999) {  // opposite: a half turn about any axis normal to a
    vec3 axis = normalize(abs(a.x) < 0.9 ? cross(a, vec3(1.0, 0.0, 0.0)) : cross(a, vec3(0.0, 1.0, 0.0)));
    return 2.0 * axis * dot(axis, x) - x;
  }
  return x * c + cross(v, x) + v * (dot(v, x) / (1.0 + c));
}

// Whether vertex a's ray at slot ia (1: its own class, 4: the other class
// of its stencil) and b's at ib leave alike: the same internal reflections
// and re-entries (the direction's w), exits within 30 degrees.
bool alike(uint a, uint ia, uint b, uint ib) {
  vec4 p = rays[6u * a + ia], q = rays[6u * b + ib];
  return p.w == q.w && dot(p.xyz, q.xyz) >= 0.8660254;
}

// Vertex v's ray of its own class, or (own false) of the other one.
void cut_ray(uint v, bool own, out vec3 exit, out vec3 dir, out vec3 colour) {
  uint b = 6u * v + (own ? 0u : 3u);
  exit = rays[b].xyz;
  dir = rays[b + 1u].xyz;
  colour = rays[b + 2u].rgb;
}

void main() {
  uint p = gl_GlobalInvocationID.x;
  if (p >= 3u * u_triangle_count * u_plane_count) return;
  uint slot = p % 3u, tp = p / 3u;
  uint t = tp % u_triangle_count, plane = tp / u_triangle_count;
  uint id[3] = uint[3](indices[3u * t], indices[3u * t + 1u], indices[3u * t + 2u]);
  vec3 pw[3];
  for (int k = 0; k < 3; ++k) {
    uint i = id[k];
    pw[k] = (u_model * vec4(vertices[6u * i], vertices[6u * i + 1u], vertices[6u * i + 2u], 1.0)).xyz;
  }
  vec3 c = cross(pw[1] - pw[0], pw[2] - pw[0]);
  float area = 0.5 * length(c);  // S
  vec3 centre = (pw[0] + pw[1] + pw[2]) / 3.0;
  vec3 to_light = u_light_type == 1 ? -u_light_direction : normalize(u_light_position - centre);
  float cos_theta = area > 0.0 ? dot(c, to_light) / (2.0 * area) : 0.0;
  float e_in = u_light_type == 1 ? u_light_power : u_light_power / max(dot(u_light_position - centre, u_light_position - centre), 1e-12) * caustix_spot_factor(-to_light, u_light_direction, u_spot);
  float beam = area * max(cos_theta, 0.0);
  vec2 to_texels = u_map_size / (2.0 * u_half.xz);
  vec4 o[3];
  vec3 d[3];
  bool leaves = true;
  for (int k = 0; k < 3; ++k) {
    o[k] = rays[6u * id[k]];
    d[k] = rays[6u * id[k] + 1u].xyz;
    leaves = leaves && o[k].w > 0.0;
  }
  // A torn triangle: its corners leave after different numbers of
  // internal reflections, or through different faces, two exit rays then
  // differing by more than 30 degrees, more than a smooth surface turns
  // them across one triangle (glass_ball: nothing above 20, 1.2 % of its
  // flux above 12). Its volume would smear the light between the corners'
  // landings (a tilted pane: +2.6 % over its footprint; the prism's direct
  // and totally reflected exits, 27.8 degrees apart, spread its band's
  // light between them: docs/glass-tables.md). Where two classes meet and the
  // tables say where they switch (LTTW), it is cut there (below);
  // otherwise it is dropped. Nor can a
  // triangle whose corners do not all pass light (the object shades some
  // from the light, or traps their light) be interpolated across; its light
  // leaves as parallel beams instead, one per corner that passes light: a
  // third of the triangle's incident cross-section (its outline seen from
  // the light, turned to face the corner's exit direction, scaled by
  // 1/sqrt 3) from the corner's exit point along its exit direction, with
  // the corner's colour. Unfocused, but on the lit side of the shading
  // (glass_teapot: 0.416 -> 0.447 m^2 E0 of the reference's 0.533). Beams
  // for torn triangles too would bring 0.481, but as scattered spots where
  // grazing exits spread the light thinly (docs/glass.md).
  float spread = min(min(dot(d[0], d[1]), dot(d[1], d[2])), dot(d[2], d[0]));
  bool same_class = alike(id[0], 1u, id[1], 1u) && alike(id[0], 1u, id[2], 1u);
  bool whole = leaves && spread >= 0.8660254 && same_class;

  // The cut of a triangle whose corners fall in two path classes: corner s
  // alone in one, u and w in the other. Each corner's rays (glass_rays.comp)
  // hold its own class and the other class of its table's stencil
  // extrapolated to the light's direction, with the distance d (grid
  // cells) from that direction to the switch between the two. The switch
  // crosses edge s-u at t = d_s / (d_s + d_u) from s (the switch moving
  // evenly across the triangle) and s-w likewise; there each class's ray is
  // interpolated between its own ray at one end and its extrapolated one at
  // the other. s's part is the triangle (s, P_u, P_w), the others' the
  // quad (u, w, P_w, P_u) as (u, w, P_w) and (u, P_w, P_u): slots 0, 1, 2,
  // each its share of the triangle's area, at its own constant intensity.
  bool cut = false;
  int cs = 0;
  float t_u = 0.0, t_w = 0.0;
  bool part_s = false, part_uw = false;
  if (leaves && !same_class) {
    bool g1 = !alike(id[0], 1u, id[1], 1u), g2 = !alike(id[0], 1u, id[2], 1u);
    cs = g1 && g2 ? 0 : (g1 ? 1 : 2);
    int cu = (cs + 1) % 3, cw = (cs + 2) % 3;
    uint vs = id[cs], vu = id[cu], vw = id[cw];
    float ds = rays[6u * vs + 2u].w, du = rays[6u * vu + 2u].w, dw = rays[6u * vw + 2u].w;
    if (alike(vu, 1u, vw, 1u) && ds >= 0.0 && du >= 0.0 && dw >= 0.0) {
      t_u = ds / max(ds + du, 1e-6);
      t_w = ds / max(ds + dw, 1e-6);
      // s's class at u and w, and u's and w's at s: the extrapolated rays.
      part_s = rays[6u * vu + 3u].w > 0.0 && rays[6u * vw + 3u].w > 0.0 && alike(vs, 1u, vu, 4u) && alike(vs, 1u, vw, 4u);
      part_uw = rays[6u * vs + 3u].w > 0.0 && alike(vu, 1u, vs, 4u);
      cut = part_s || part_uw;
    }
  }
  int corner = whole || cut ? -1 : int(slot);
  bool reached = cos_theta > 0.0 && (whole ? slot == 0u : (cut ? (slot == 0u ? part_s : part_uw) : !leaves && o[corner].w > 0.0));
  if (!reached) {  // an empty slot (most of them): the draw skips it
    prims[6u * p + 1u] = vec4(0.0);
    return;
  }
  vec3 colour, dir[3], start[3];
  float flux;
  if (cut) {
    // The part's three points: (corner, corner, corner, or a cut point on
    // s-u (3) or s-w (4)); and whose class they carry.
    int cu = (cs + 1) % 3, cw = (cs + 2) % 3;
    ivec3 pts = slot == 0u ? ivec3(cs, 3, 4) : (slot == 1u ? ivec3(cu, cw, 4) : ivec3(cu, 4, 3));
    bool of_s = slot == 0u;
    float share = slot == 0u ? t_u * t_w : (slot == 1u ? 1.0 - t_w : t_w * (1.0 - t_u));
    colour = vec3(0.0);
    for (int k = 0; k < 3; ++k) {
      vec3 e, dd, cc;
      if (pts[k] < 3) {
        cut_ray(id[pts[k]], of_s == (pts[k] == cs), e, dd, cc);
      } else {
        int other_end = pts[k] == 3 ? cu : cw;
        float tt = pts[k] == 3 ? t_u : t_w;
        vec3 e0, d0, c0, e1, d1, c1;
        cut_ray(id[cs], of_s, e0, d0, c0);
        cut_ray(id[other_end], !of_s, e1, d1, c1);
        e = mix(e0, e1, tt);
        dd = normalize(mix(d0, d1, tt));
        cc = mix(c0, c1, tt);
      }
      start[k] = e;
      dir[k] = dd;
      colour += cc / 3.0;
    }
    flux = beam * share;
  } else if (corner < 0) {
    colour = (rays[6u * id[0] + 2u].rgb + rays[6u * id[1] + 2u].rgb + rays[6u * id[2] + 2u].rgb) / 3.0;
    flux = beam;
    for (int k = 0; k < 3; ++k) {
      dir[k] = d[k];
      start[k] = o[k].xyz;
    }
  } else {
    colour = rays[6u * id[corner] + 2u].rgb;
    flux = beam / 3.0;
    vec3 dk = d[corner];
    for (int k = 0; k < 3; ++k) {
      vec3 r = pw[k] - centre;
      r -= to_light * dot(r, to_light);  // the outline seen from the light
      dir[k] = dk;
      start[k] = o[corner].xyz + 0.57735027 * rotate_onto(-to_light, dk, r);
    }
  }
  vec2 q[3];
  vec3 mean_dir = vec3(0.0);
  for (int k = 0; k < 3; ++k) {
    mean_dir += dir[k];
    vec3 rel = start[k] - u_origin;
    float along = -dot(dir[k], u_V);
    float s = (dot(rel, u_V) - u_plane_v[plane]) / max(along, 1e-6);
    reached = reached && along > 1e-4 && s >= 0.0;  // the plane lies ahead of the exit point
    vec3 x = rel + s * dir[k];
    q[k] = (vec2(dot(x, u_U), dot(x, u_W)) + u_half.xz) * to_texels;
  }
  if (!reached || flux <= 0.0) {
    prims[6u * p + 1u] = vec4(0.0);
    return;
  }
  float texel_area = 1.0 / (to_texels.x * to_texels.y);
  float s0 = 0.5 * abs((q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y)) * texel_area;
  // Magnification above max_magnification (a focus: glass_ball's pole
  // triangles land some 47 000 times smaller than they are): the triangle
  // is widened across its longest edge until S_0 = S cos(theta) / M, its
  // third vertex moved away from that edge, so that it keeps its flux at
  // the capped intensity. Capping the intensity alone lost what it did not
  // draw over the smaller area: 0.9 % of the light through glass_ball, all
  // of it from the focal millimetres.
  float s_min = flux / u_max_magnification;
  if (s0 < 1e-4 * s_min) {
    // A point or so thin that widening it would lose the float precision
    // of its corners (a cut part's rays can meet in one point, where the
    // coverage of a degenerate triangle would be a whole texel's): a
    // triangle of area s_min, as wide as it is high, on its centroid.
    vec2 m = (q[0] + q[1] + q[2]) / 3.0;
    float h = sqrt(s_min * to_texels.x * to_texels.y);
    q[0] = m + vec2(-h, -h / 3.0);
    q[1] = m + vec2(h, -h / 3.0);
    q[2] = m + vec2(0.0, 2.0 * h / 3.0);
    s0 = s_min;
  } else if (s0 < s_min && s0 > 0.0) {
    int a = 0;
    float longest = 0.0;
    for (int k = 0; k < 3; ++k) {
      float l = dot(q[(k + 1) % 3] - q[k], q[(k + 1) % 3] - q[k]);
      if (l > longest) {
        longest = l;
        a = k;
      }
    }
    int b = (a + 1) % 3, c = (a + 2) % 3;
    vec2 along = (q[b] - q[a]) / sqrt(longest);
    vec2 foot = q[a] + along * dot(q[c] - q[a], along);
    q[c] = foot + (q[c] - foot) * (s_min / s0);
    s0 = s_min;
  }
  float cos_delta = max(-dot(normalize(mean_dir), u_V), 1e-3);
  vec3 intensity = e_in * flux * colour / (max(s0, s_min) * cos_delta);
  prims[6u * p] = vec4(q[0], q[1]);
  // z: the intersection triangle's area in texels for a whole triangle
  // (glass_vertex_intensity.comp weighs its one-rings by it), -1 for a
  // corner beam (drawn with its own constant intensity).
  prims[6u * p + 1u] = vec4(q[2], corner < 0 && !cut ? max(s0 / texel_area, 1e-12) : -1.0, 1.0);
  prims[6u * p + 2u] = vec4(intensity, 0.0);
  prims[6u * p + 3u] = vec4(dir[0], 0.0);
  prims[6u * p + 4u] = vec4(dir[1], 0.0);
  prims[6u * p + 5u] = vec4(dir[2], 0.0);
}
