// Diffuse receivers (prefixed with #version and lighting.glsl). Pass 0
// writes ambient and depth; each later pass adds one light with additive
// blending: I_o = sum_lights I_c I_d + I_a (seed 000 eq. 4-19, 4-20), with
// I_c I_d = albedo * irradiance.
in vec3 v_world;
in vec3 v_normal;

uniform int u_pass;  // 0 ambient, 1 a light
uniform vec3 u_albedo;
uniform vec3 u_ambient;

out vec4 o_color;

void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;  // open meshes are lit from either side
  if (u_pass == 0) {
    o_color = vec4(u_albedo * u_ambient, 1.0);
    return;
  }
  o_color = vec4(u_albedo * irradiance_from_light(v_world, n), 0.0);
}
