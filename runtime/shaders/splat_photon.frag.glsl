// Mihalik 2008 ch. 8 (GPU variant) / §9.2: the water surface rasterised along
// the frame's V (prefixed with #version, caustix.glsl's optics and
// position_code.glsl); each fragment is a
// photon. It stores where the refracted photon meets the receiver's first
// surface (the caustics map's uv, R and G) and the irradiance it adds to that
// texel (B): E_in cos(theta_i) T(theta_i) times the surface patch the
// fragment covers (pixel area / |n.V|), over the texel's area; A holds its
// direction of travel t as two halves, (t.U / t.V, t.W / t.V), for casting
// with the local light direction (caustics_geometry.comp). Bit patterns of
// floats in an integer texture, so they reach the vertex buffer exactly.
// Photons that miss the receiver store 0.
in vec3 v_world;
in vec3 v_normal;

uniform vec3 u_origin;
uniform vec3 u_U;
uniform vec3 u_V;
uniform vec3 u_W;
uniform vec3 u_half;
uniform int u_light_type;  // 1 directional, 2 point
uniform vec3 u_light_direction;
uniform vec3 u_light_position;
uniform float u_light_power;
uniform vec3 u_spot;  // a spot's cone about u_light_direction (caustix_spot_factor)
uniform float u_ior;
uniform float u_pixel_area;  // of a photon-texture pixel, in the frame's U-W plane (m^2)
uniform float u_texel_area;  // of a caustics-map texel (m^2)
uniform float u_tolerance;   // how far a landing may lie off the position map's surface (m)
layout(binding = 0) uniform sampler2D u_position_map;  // the first surface's frame V, coded

out uvec4 o_photon;

vec2 uv_of(vec3 c) { return 0.5 * (c.xz / u_half.xz + 1.0); }

void main() {
  o_photon = uvec4(0u);
  vec3 n = normalize(v_normal);
  vec3 d = v_world - u_light_position;
  vec3 l = u_light_type == 1 ? normalize(u_light_direction) : normalize(d);
  float e_in = u_light_type == 1 ? u_light_power : u_light_power / max(dot(d, d), 1e-12) * caustix_spot_factor(l, normalize(u_light_direction), u_spot);
  float cos_i = -dot(l, n);
  if (cos_i <= 0.0) return;
  vec3 t = refract(l, n, 1.0 / u_ior);
  vec3 rel = v_world - u_origin;
  vec3 c = vec3(dot(rel, u_U), dot(rel, u_V), dot(rel, u_W));
  vec3 ct = vec3(dot(t, u_U), dot(t, u_V), dot(t, u_W));
  if (ct.y > -1e-6) return;
  // §9.2 takes one step of the intersection: the depth under the photon,
  // then the depth where that step lands; repeated here (a fixed point of
  // s -> (surface V at c + s t) - c.V) / t.V). Empty texels count as the
  // frame's far side.
  float s = 0.0;
  for (int k = 0; k < 6; ++k) {
    float v = position_v(texture(u_position_map, uv_of(c + s * ct)).r, u_half.y);
    s = max((max(v, -u_half.y) - c.y) / ct.y, 0.0);
  }
  vec3 hit = c + s * ct;
  vec2 uv = uv_of(hit);
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return;
  float v = position_v(texture(u_position_map, uv).r, u_half.y);
  if (v < -u_half.y * 2.0 - 1.0 || abs(v - hit.y) > u_tolerance) return;  // no surface there, or not converged
  float flux = e_in * cos_i * caustix_fresnel_transmittance(cos_i, u_ior) * u_pixel_area / max(abs(dot(n, u_V)), 1e-3);
  o_photon = uvec4(floatBitsToUint(uv), floatBitsToUint(flux / u_texel_area), packHalf2x16(ct.xz / ct.y));
}
