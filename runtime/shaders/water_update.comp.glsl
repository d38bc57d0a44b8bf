#version 450 core
// Animates the water grid (Tipprasert 2006 §4.3): positions and analytic normals of
// y = level + sum A sin(k (d . xz) - k c t + phi) (formats/scene.h), one
// invocation per grid vertex, into SSBOs read by every later pass.
layout(local_size_x = 64) in;

const int kMaxWaves = 256;
layout(std140, binding = 0) uniform Waves {
  vec4 u_wave_a[kMaxWaves];  // amplitude, k, direction.x, direction.z
  vec4 u_wave_b[kMaxWaves];  // k * speed, phase, -, -
  ivec4 u_wave_count;
};
layout(std430, binding = 0) writeonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) writeonly buffer Normals { vec4 normals[]; };

uniform uvec2 u_cells;
uniform vec4 u_extent;  // x0, z0, x1, z1
uniform float u_level;
uniform float u_time;
uniform float u_amplitude_scale;  // 1 as baked; the viewer tunes it

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint nx = u_cells.x + 1u;
  if (i >= nx * (u_cells.y + 1u)) return;
  vec2 f = vec2(float(i % nx) / float(u_cells.x), float(i / nx) / float(u_cells.y));
  vec2 xz = mix(u_extent.xy, u_extent.zw, f);
  float h = u_level;
  vec2 grad = vec2(0.0);
  for (int w = 0; w < u_wave_count.x; ++w) {
    vec4 a = u_wave_a[w];
    vec4 b = u_wave_b[w];
    float arg = a.y * dot(a.zw, xz) - b.x * u_time + b.y;
    float amp = a.x * u_amplitude_scale;
    h += amp * sin(arg);
    grad += amp * a.y * cos(arg) * a.zw;
  }
  positions[i] = vec4(xz.x, h, xz.y, 1.0);
  normals[i] = vec4(normalize(vec3(-grad.x, 1.0, -grad.y)), 0.0);
}
