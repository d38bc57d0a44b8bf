// Diffuse receivers (prefixed with #version and caustix.glsl). Pass 0
// writes ambient and depth; each later pass adds one light with additive
// blending: I_o = sum_lights I_c I_d + I_a (Tipprasert 2006 eq. 4-19, 4-20), with
// I_c I_d = albedo * irradiance. Seen through water (u_fog = 1: the camera
// under water, or the reflection texture seen from below) the colour is
// attenuated towards the water colour by the distance to the eye, Mihalik 2008
// eq. 10: C = C_w + a (C_obj - C_w), a = e^(-k d) (eq. 4); with additive
// passes, the ambient pass carries (1 - a) C_w and every pass is scaled by a.
// A textured receiver's albedo is u_albedo times its texture's linear colour
// (Engine::albedo_map, caustix_texture_coords()).
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

uniform int u_pass;  // 0 ambient, 1 a light
uniform vec3 u_albedo;
uniform int u_albedo_projection;  // 0: untextured; else AlbedoMap::projection
uniform vec3 u_albedo_rows[2];
layout(binding = 0) uniform sampler2D u_albedo_map;
uniform vec3 u_ambient;
uniform int u_fog;
uniform vec3 u_fog_eye;
uniform vec3 u_fog_k;
uniform vec3 u_water_color;

out vec4 o_color;

void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;  // open meshes are lit from either side
  vec3 albedo = u_albedo;
  if (u_albedo_projection != 0) {
    albedo *= texture(u_albedo_map, caustix_texture_coords(u_albedo_projection, u_albedo_rows[0], u_albedo_rows[1], v_uv, v_world, n)).rgb;
  }
  vec3 a = u_fog != 0 ? exp(-u_fog_k * length(v_world - u_fog_eye)) : vec3(1.0);
  if (u_pass == 0) {
    o_color = vec4(a * albedo * u_ambient + (1.0 - a) * u_water_color, 1.0);
    return;
  }
  o_color = vec4(a * albedo * caustix_irradiance(v_world, n), 0.0);
}
