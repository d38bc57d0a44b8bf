#version 450 core
// The water grid, displaced by the scene's sum of directional waves
// (formats/scene.h: y = level + sum A sin(k (d . xz - c t) + phi)), with the
// analytic normal of that height field.
layout(location = 0) in vec2 a_xz;

const int kMaxWaves = 256;
layout(std140, binding = 0) uniform Waves {
  vec4 u_wave_a[kMaxWaves];  // amplitude, k, direction.x, direction.z
  vec4 u_wave_b[kMaxWaves];  // k * speed, phase, -, -
  ivec4 u_wave_count;
};
uniform float u_level;
uniform float u_time;
uniform mat4 u_view_proj;

out vec3 v_world;
out vec3 v_normal;

void main() {
  float h = u_level;
  vec2 grad = vec2(0.0);
  for (int i = 0; i < u_wave_count.x; ++i) {
    vec4 a = u_wave_a[i];
    vec4 b = u_wave_b[i];
    float arg = a.y * dot(a.zw, a_xz) - b.x * u_time + b.y;
    h += a.x * sin(arg);
    grad += a.x * a.y * cos(arg) * a.zw;
  }
  v_world = vec3(a_xz.x, h, a_xz.y);
  v_normal = normalize(vec3(-grad.x, 1.0, -grad.y));
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
