// Outgoing rays of a transparent object for one light (Iwasaki et al. §4.1; prefixed
// with #version, caustix.glsl (the light's block and shadow maps) and transport.glsl): per vertex,
// the light's direction in object space, the table look-up, and the exit
// ray in world space with its colour, T * e^(-K path). (The mean exit
// direction that orients the virtual planes, §4.2, is estimated on the
// CPU from a sample of the same tables: glass.cpp, mean_travel.)
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };  // position, normal
// Per vertex, 6 vec4: exit + valid, dir + path class (bounces), colour +
// the distance (grid cells) to the switch to the other class (-1: none
// known); the other class's exit + valid, dir + class, colour + 0
// (ltt_lookup_ex: what glass_geometry.comp cuts torn triangles with).
layout(std430, binding = 2) writeonly buffer Rays { vec4 rays[]; };

uniform uint u_vertex_count;
uniform mat4 u_model;
uniform mat3 u_rotation;  // the model's rotation (model = T R s)
uniform float u_scale;
uniform vec3 u_glass_absorption;
uniform vec3 u_weight;  // the traced wavelength's RGB weight; (1, 1, 1) for one

void main() {
  uint v = gl_GlobalInvocationID.x;
  if (v >= u_vertex_count) return;
  vec3 p = vec3(vertices[6u * v], vertices[6u * v + 1u], vertices[6u * v + 2u]);
  vec3 n = normalize(vec3(vertices[6u * v + 3u], vertices[6u * v + 4u], vertices[6u * v + 5u]));
  vec3 pw = (u_model * vec4(p, 1.0)).xyz;
  vec3 to_light_w = caustix_light.mode.y == 1 ? -caustix_light.light_direction.xyz : normalize(caustix_light.light_position.xyz - pw);
  vec3 to_light = transpose(u_rotation) * to_light_w;
  Transport other;
  float dist;
  Transport t = ltt_lookup_ex(v, n, to_light, true, other, dist);
  // Light the object itself shadows from elsewhere does not enter here.
  float visible = t.leaves ? caustix_shadow_visibility(pw, u_rotation * n, to_light_w) : 0.0;
  rays[6u * v] = vec4((u_model * vec4(t.exit, 1.0)).xyz, t.leaves && visible > 0.0 ? 1.0 : 0.0);
  rays[6u * v + 1u] = vec4(u_rotation * t.dir, float(t.bounces));
  rays[6u * v + 2u] = vec4(t.transmittance * visible * exp(-u_glass_absorption * t.path * u_scale) * u_weight, dist);
  rays[6u * v + 3u] = vec4((u_model * vec4(other.exit, 1.0)).xyz, other.leaves && visible > 0.0 ? 1.0 : 0.0);
  rays[6u * v + 4u] = vec4(u_rotation * other.dir, float(other.bounces));
  rays[6u * v + 5u] = vec4(other.transmittance * visible * exp(-u_glass_absorption * other.path * u_scale) * u_weight, 0.0);
}
