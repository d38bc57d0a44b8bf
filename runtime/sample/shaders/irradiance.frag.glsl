// Irradiance images (shared/DESIGN.md; prefixed with #version and
// caustix.glsl): irradiance at the receiver's first surface seen from
// above, divided by E0; no albedo, no ambient. One additive pass per light.
in vec3 v_world;
in vec3 v_normal;

uniform int u_pass;  // 0 lays down depth, 1 adds a light
uniform float u_inv_e0;

out vec4 o_color;

void main() {
  // The viewer is straight above: open surfaces face up (gl_FrontFacing
  // depends on the projection's handedness, which this view mirrors).
  vec3 n = normalize(v_normal);
  if (n.y < 0.0) n = -n;
  o_color = u_pass == 0 ? vec4(0.0) : vec4(caustix_irradiance(v_world, n) * u_inv_e0, 0.0);
}
