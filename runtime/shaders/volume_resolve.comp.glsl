#version 450 core
// volume_resolve.comp.glsl: the radiance grid from the photons' fixed-point
// deposits (volume_photons.comp.glsl): per voxel, the scattering source
// S = sigma_s x power x length / volume (what the viewing pass integrates
// with the phase function) and the photons' mean direction of travel.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Accumulator { int acc[]; };
layout(binding = 0, rgba32f) uniform writeonly image3D u_source;
layout(binding = 1, rgba16f) uniform writeonly image3D u_direction;
layout(std430, binding = 1) buffer Tally { uint tally[]; };  // [10], [11]: the grid's luminance sum, low and high words
uniform ivec3 u_grid_n;
uniform float u_inv_scale_volume;  // 1 / (fixed-point scale x voxel volume)

void main() {
  int v = int(gl_GlobalInvocationID.x);
  if (v >= u_grid_n.x * u_grid_n.y * u_grid_n.z) return;
  ivec3 c = ivec3(v % u_grid_n.x, (v / u_grid_n.x) % u_grid_n.y, v / (u_grid_n.x * u_grid_n.y));
  vec3 s = vec3(acc[6 * v], acc[6 * v + 1], acc[6 * v + 2]) * u_inv_scale_volume;
  vec3 m = vec3(acc[6 * v + 3], acc[6 * v + 4], acc[6 * v + 5]);
  float l = length(m);
  float lum = dot(vec3(acc[6 * v], acc[6 * v + 1], acc[6 * v + 2]), vec3(0.2126, 0.7152, 0.0722));
  if (lum >= 0.5) {
    uint q = uint(lum + 0.5);
    uint old = atomicAdd(tally[10], q);
    if (old + q < old) atomicAdd(tally[11], 1u);
  }
  imageStore(u_source, c, vec4(max(s, vec3(0.0)), 0.0));
  imageStore(u_direction, c, vec4(l > 0.0 ? m / l : vec3(0.0), 0.0));
}
