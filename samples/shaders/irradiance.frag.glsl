// Irradiance images (docs/architecture.md; prefixed with #version and
// caustix.glsl): irradiance at the receiver's first surface seen from
// above, divided by E0; no albedo, no ambient. Pass 0 lays down depth and
// the auxiliary samples (seen, |n_y|, cosine towards the first light), each
// later pass adds a light. The renderer averages the samples per pixel.
in vec3 v_world;
in vec3 v_normal;

uniform int u_pass;  // 0 lays down depth and aux, 1 adds a light
uniform float u_inv_e0;
uniform vec3 u_to_light;  // first light, unit; 0 for a point light

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_aux;

void main() {
  // The viewer is straight above: open surfaces face up (gl_FrontFacing
  // depends on the projection's handedness, which this view mirrors).
  vec3 n = normalize(v_normal);
  if (n.y < 0.0) n = -n;
  o_color = u_pass == 0 ? vec4(0.0) : vec4(caustix_irradiance(v_world, n) * u_inv_e0, 0.0);
  o_aux = vec4(1.0, abs(n.y), dot(n, u_to_light), 0.0);
}
