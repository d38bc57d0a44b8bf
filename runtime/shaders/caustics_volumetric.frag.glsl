// Volumetric baseline (Tipprasert 2006 §5.2.1; prefixed with #version and
// caustics_coverage.glsl): the intersection triangles of sample plane i are
// drawn into slice i of the illumination volume and multiplied by that
// slice's image of the receiver (the surface within the slab around the
// plane, rendered beforehand).
layout(binding = 0) uniform sampler2DArray u_slices;  // receiver mask per slice
uniform int u_slice;

out vec4 o_irradiance;  // as caustics_levelmap.frag

void main() {
  load_primitive();
  if (texelFetch(u_slices, ivec3(ivec2(gl_FragCoord.xy), u_slice), 0).r < 0.5) discard;
  float covered = texel_coverage();
  if (covered <= 0.0) discard;
  covered *= corner_factor();  // smooth caustics (caustics_coverage.glsl)
  o_irradiance = vec4(1.0, v_slopes, 0.0) * (v_irradiance * covered);
}
