#version 450 core
// Diffuse receivers. Pass 0 writes ambient (and depth); each later pass adds
// one light with additive blending: albedo * E * cos(theta) * visibility,
// where E is the directional irradiance E0 or I / r^2 for a point light.
in vec3 v_world;
in vec3 v_normal;

uniform int u_pass;              // 0 ambient, 1 directional, 2 point
uniform vec3 u_albedo;
uniform vec3 u_ambient;
uniform vec3 u_light_direction;  // directional: unit direction of travel
uniform vec3 u_light_position;   // point
uniform vec3 u_light_power;      // colour * E0 (directional) or colour * I (point)
uniform mat4 u_shadow_matrix;    // world -> shadow texture coordinates
uniform float u_shadow_far;
uniform float u_shadow_texel;    // world size of one shadow texel
layout(binding = 0) uniform sampler2DShadow u_shadow_2d;
layout(binding = 1) uniform samplerCubeShadow u_shadow_cube;

out vec4 o_color;

float directional_visibility(vec3 n, vec3 l) {
  // Normal offset against acne, 3x3 PCF against aliasing.
  vec3 p = v_world + n * (1.5 * u_shadow_texel);
  vec4 s = u_shadow_matrix * vec4(p, 1.0);
  s.xyz /= s.w;
  if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0)))) return 1.0;
  float bias = 0.002 * (1.0 - dot(n, l)) + 0.0005;
  vec2 texel = 1.0 / vec2(textureSize(u_shadow_2d, 0));
  float sum = 0.0;
  for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x)
      sum += texture(u_shadow_2d, vec3(s.xy + vec2(x, y) * texel, s.z - bias));
  return sum / 9.0;
}

float point_visibility(vec3 n, vec3 to_light, float dist) {
  vec3 p = v_world + n * (0.01 * dist);
  vec3 d = p - u_light_position;
  return texture(u_shadow_cube, vec4(d, length(d) / u_shadow_far - 0.002));
}

void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;  // open meshes are lit from either side
  if (u_pass == 0) {
    o_color = vec4(u_albedo * u_ambient, 1.0);
    return;
  }
  vec3 l;
  vec3 e;
  float vis;
  if (u_pass == 1) {
    l = -u_light_direction;
    e = u_light_power;
    vis = directional_visibility(n, l);
  } else {
    vec3 to_light = u_light_position - v_world;
    float r2 = max(dot(to_light, to_light), 1e-8);
    l = to_light * inversesqrt(r2);
    e = u_light_power / r2;
    vis = point_visibility(n, to_light, sqrt(r2));
  }
  float cos_theta = max(dot(n, l), 0.0);
  o_color = vec4(u_albedo * e * cos_theta * vis, 0.0);
}
