// Run-time depth profile (Tipprasert 2006 §4.7.2; the thesis re-profiled every
// frame): mode 0 bins the position map's texels into the L depth levels
// (fig. 4-19); mode 1 writes the min/max depth of each tile for culling.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D u_position_map;  // frame V's code (position_code.glsl, prefixed)
layout(std430, binding = 9) buffer Histogram { uint bins[]; };
layout(rg32f, binding = 0) writeonly uniform image2D u_tiles;
uniform int u_mode;
uniform uint u_levels;
uniform float u_half_v;
uniform int u_tile;

void main() {
  ivec2 size = textureSize(u_position_map, 0);
  if (u_mode == 0) {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size))) return;
    float v = position_v(texelFetch(u_position_map, p, 0).r, u_half_v);
    if (v <= -1e29) return;
    float t = clamp((u_half_v - v) / (2.0 * u_half_v), 0.0, 1.0);
    atomicAdd(bins[min(u_levels - 1u, uint(t * float(u_levels)))], 1u);
    return;
  }
  ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(tile * u_tile, size))) return;
  vec2 mm = vec2(1e30, -1e30);
  for (int y = 0; y < u_tile; ++y)
    for (int x = 0; x < u_tile; ++x) {
      ivec2 p = tile * u_tile + ivec2(x, y);
      if (any(greaterThanEqual(p, size))) continue;
      float v = position_v(texelFetch(u_position_map, p, 0).r, u_half_v);
      if (v > -1e29) mm = vec2(min(mm.x, v), max(mm.y, v));
    }
  imageStore(u_tiles, tile, vec4(mm, 0.0, 0.0));
}
