#version 450 core
// volume_resolve.comp.glsl: the radiance grid from the photons' fixed-point
// deposits (volume_photons.comp.glsl): per voxel, the scattering source
// S = sigma_s x power x length / volume (what the viewing pass integrates
// with the phase function) and the photons' mean direction of travel. Run
// once for the radiance grid and once for the focus grid, whose voxels
// follow it in the accumulator and in the textures' slices.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Accumulator { int acc[]; };
layout(binding = 0, rgba32f) uniform writeonly image3D u_source;
layout(binding = 1, rgba16f) uniform writeonly image3D u_direction;
layout(std430, binding = 1) buffer Tally { uint tally[]; };  // [10], [11]: the grid's luminance sum, low and high words
uniform ivec3 u_grid_n;
uniform int u_base;                // the grid's first voxel in the accumulator
uniform int u_slice;               // its first slice in the textures
uniform int u_count;               // 1: adds its luminance to the tally (the radiance grid only)
uniform float u_inv_scale_volume;  // 1 / (fixed-point scale x voxel volume)

void main() {
  int v = int(gl_GlobalInvocationID.x);
  if (v >= u_grid_n.x * u_grid_n.y * u_grid_n.z) return;
  ivec3 c = ivec3(v % u_grid_n.x, (v / u_grid_n.x) % u_grid_n.y, v / (u_grid_n.x * u_grid_n.y));
  int a = u_base + 6 * v;
  vec3 s = vec3(acc[a], acc[a + 1], acc[a + 2]) * u_inv_scale_volume;
  vec3 m = vec3(acc[a + 3], acc[a + 4], acc[a + 5]);
  float l = length(m);
  float lum = dot(vec3(acc[a], acc[a + 1], acc[a + 2]), vec3(0.2126, 0.7152, 0.0722));
  if (u_count != 0 && lum >= 0.5) {
    uint q = uint(lum + 0.5);
    uint old = atomicAdd(tally[10], q);
    if (old + q < old) atomicAdd(tally[11], 1u);
  }
  c.z += u_slice;
  imageStore(u_source, c, vec4(max(s, vec3(0.0)), 0.0));
  imageStore(u_direction, c, vec4(l > 0.0 ? m / l : vec3(0.0), 0.0));
}
