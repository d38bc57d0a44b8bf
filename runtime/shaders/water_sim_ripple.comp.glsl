#version 450 core
// A ripple dropped into the interactive water (WaterSimulation::add_ripple):
// a * (0.5 + 0.5 cos(pi r / R) - m) inside the disc of radius R, with
// m = 1/2 - 2/pi^2 the raised cosine's mean over the disc, so the ripple
// adds no volume (to the grid's sampling of it).
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) buffer Heights { float h[]; };

uniform uvec2 u_vertices;
uniform vec2 u_origin;   // x0, z0
uniform vec2 u_spacing;  // dx, dz
uniform vec2 u_center;
uniform float u_radius;
uniform float u_amplitude;

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= u_vertices.x || p.y >= u_vertices.y) return;
  float r = distance(u_origin + vec2(p) * u_spacing, u_center);
  if (r >= u_radius) return;
  const float kPi = 3.14159265358979;
  const float kMean = 0.5 - 2.0 / (kPi * kPi);
  h[p.y * u_vertices.x + p.x] += u_amplitude * (0.5 + 0.5 * cos(kPi * r / u_radius) - kMean);
}
