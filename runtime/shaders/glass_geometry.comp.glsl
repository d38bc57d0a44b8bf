#version 450 core
// Seed 002 §4.1-4.2: the intersection triangle of each (transparent
// triangle's illumination volume, virtual plane) pair, in illumination-
// texture texels, with the incident intensity of eq. 3 except cos(gamma):
//   E_in cos(theta) F_t S / (S_0 cos(delta)),
// F_t (with absorption) the mean over the triangle's three outgoing rays,
// S its area, theta its angle to the light, S_0 the intersection
// triangle's area and delta the angle between the rays' mean direction
// and the plane normal. S_0 is kept above S cos(theta) / max_magnification
// (as for water, docs/caustics.md). Primitive p = plane * triangles + t:
// (q0, q1), (q2, -, reached), (rgb intensity, -), d0, d1, d2.
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
uniform vec3 u_origin;
uniform vec3 u_U;
uniform vec3 u_V;
uniform vec3 u_W;
uniform vec3 u_half;
uniform float u_map_size;
uniform float u_max_magnification;

void main() {
  uint p = gl_GlobalInvocationID.x;
  if (p >= u_triangle_count * u_plane_count) return;
  uint t = p % u_triangle_count, plane = p / u_triangle_count;
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
  float e_in = u_light_type == 1 ? u_light_power : u_light_power / max(dot(u_light_position - centre, u_light_position - centre), 1e-12);
  bool reached = cos_theta > 0.0;
  vec2 to_texels = u_map_size / (2.0 * u_half.xz);
  vec2 q[3];
  vec3 colour = vec3(0.0), mean_dir = vec3(0.0), d[3];
  for (int k = 0; k < 3; ++k) {
    vec4 o = rays[3u * id[k]];
    d[k] = rays[3u * id[k] + 1u].xyz;
    colour += rays[3u * id[k] + 2u].rgb / 3.0;
    mean_dir += d[k];
    reached = reached && o.w > 0.0;
    vec3 rel = o.xyz - u_origin;
    float along = -dot(d[k], u_V);
    float s = (dot(rel, u_V) - u_plane_v[plane]) / max(along, 1e-6);
    reached = reached && along > 1e-4 && s >= 0.0;  // the plane lies ahead of the exit point
    vec3 x = rel + s * d[k];
    q[k] = (vec2(dot(x, u_U), dot(x, u_W)) + u_half.xz) * to_texels;
  }
  // A torn triangle: its corners leave through different faces of the
  // object (or after different reflections), and two exit rays differ by
  // more than 30 degrees, more than a smooth surface turns them across one
  // triangle (glass_ball: nothing dropped above 20, 1.2 % of its flux
  // above 12). Its volume would smear the light between the corners'
  // landings (a tilted pane: +2.6 % over its footprint); it is dropped
  // instead (docs/glass.md).
  float spread = min(min(dot(d[0], d[1]), dot(d[1], d[2])), dot(d[2], d[0]));
  reached = reached && spread >= 0.8660254;
  float texel_area = 1.0 / (to_texels.x * to_texels.y);
  float s0 = 0.5 * abs((q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y)) * texel_area;
  float beam = area * max(cos_theta, 0.0);
  float cos_delta = max(-dot(normalize(mean_dir), u_V), 1e-3);
  vec3 intensity = e_in * beam * colour / (max(s0, beam / u_max_magnification) * cos_delta);
  if (!reached || beam <= 0.0) intensity = vec3(0.0);
  prims[6u * p] = vec4(q[0], q[1]);
  prims[6u * p + 1u] = vec4(q[2], 0.0, reached && beam > 0.0 ? 1.0 : 0.0);
  prims[6u * p + 2u] = vec4(intensity, 0.0);
  prims[6u * p + 3u] = vec4(d[0], 0.0);
  prims[6u * p + 4u] = vec4(d[1], 0.0);
  prims[6u * p + 5u] = vec4(d[2], 0.0);
}
