// Receivers (prefixed with #version, caustix.glsl and sky_model.glsl).
// Pass 0 writes ambient (and emission) and depth; each later pass adds one
// light with additive blending: I_o = sum_lights I_c I_d + I_a (Tipprasert
// 2006 eq. 4-19, 4-20), with I_c I_d = albedo * irradiance. Seen through
// water (u_fog = 1: the camera under water, or the reflection texture seen
// from below) the colour is attenuated towards the water colour by the
// distance to the eye, Mihalik 2008 eq. 10: C = C_w + a (C_obj - C_w), a =
// e^(-k d) (eq. 4); with additive passes, the ambient pass carries (1 - a)
// C_w and every pass is scaled by a. A textured receiver's albedo is
// u_albedo times its texture's linear colour (Engine::albedo_map,
// caustix_texture_coords()), times its vertex colour where the mesh has
// one (glTF COLOR_0).
//
// A receiver with a surface (u_surface 1: glTF's metallic-roughness
// material, formats/scene.h Surface) is shaded as glTF 2.0's appendix B
// has it: base colour c, metallic m, roughness r (alpha = r^2), F0 =
// mix(0.04, c, m); per light the diffuse (1 - m)(1 - F) c and the GGX
// specular D Vis F (Trowbridge-Reitz D, height-correlated Smith Vis,
// Schlick F) times pi, times the light's irradiance (the renderer's units
// leave out the 1/pi of a diffuse surface, as above); ambient from the
// sky (image-based light): the diffuse part (1 - m) c times the sky's
// cosine-weighted irradiance over pi from its spherical harmonics, the
// specular part the sky prefiltered with the GGX lobe of the surface's
// roughness in the reflected direction (the renderer's cube map; where
// the context lacks the unit, the sky there blended towards the
// irradiance as the lobe widens), times F0 A + B (Karis 2014's analytic
// fit of the split-sum's terms); plus the emission. docs/display.md,
// "Surfaces".
//
// Its maps (u_maps, Engine::surface_maps; glTF 2.0 §3.9.3-3.9.5): the
// metallic-roughness texture scales metallic by B and roughness by G; the
// normal texture tilts the normal in the tangent frame the texture
// coordinates' screen derivatives give (T along increasing s, B = N x T:
// the Khronos sample viewer's frame for meshes without tangents); the
// occlusion texture scales the ambient light by 1 + strength (R - 1); the
// emissive texture multiplies the emission. Alpha (the base colour
// factor's times its texture's): a masked surface is discarded below its
// cut-off; a blended one writes its alpha for the renderer's
// SRC_ALPHA blending. The maps are read only where the renderer defines
// SAMPLE_MAPS (a scene with maps): a uniform branch not taken still costs
// llvmpipe its work, masked.
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
in vec4 v_color;  // the vertex colour (glTF COLOR_0), (1, 1, 1, 1) without

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
uniform int u_surface;     // 1: metallic-roughness shading
uniform float u_metallic;
uniform float u_roughness;
uniform vec3 u_emissive;   // times the reference irradiance, as drawn
uniform vec3 u_eye;
uniform vec3 u_sky_sh[9];  // the sky's irradiance over pi, order-2 spherical harmonics
uniform samplerCube u_prefiltered;  // the sky prefiltered per roughness (prefilter.frag), unit set by the renderer
uniform int u_has_prefiltered;
uniform float u_prefiltered_levels;  // its last mip level: roughness 1
uniform int u_maps;        // bits: 1 metallic-roughness, 2 normal, 4 occlusion, 8 emission
uniform int u_map_projection[4];  // per map, in bit order: AlbedoMap::projection
uniform vec3 u_map_rows[8];       // per map: its transform's two rows
layout(binding = 1) uniform sampler2D u_metallic_roughness_map;
layout(binding = 2) uniform sampler2D u_normal_map;
layout(binding = 3) uniform sampler2D u_occlusion_map;
uniform sampler2D u_emissive_map;  // its unit set by the renderer (units 4..15 are caustix's)
uniform float u_normal_scale = 1.0;
uniform float u_occlusion_strength = 1.0;
uniform int u_alpha_mode;  // 0 opaque, 1 mask, 2 blend
uniform float u_alpha = 1.0;
uniform float u_alpha_cutoff = 0.5;

out vec4 o_color;

const float kPi = 3.14159265358979;

// Ramamoorthi & Hanrahan 2001's basis (real SH, l <= 2), with the cosine
// lobe's convolution folded into the coefficients on the CPU.
vec3 sky_irradiance(vec3 n) {
  return max(u_sky_sh[0] * 0.282095 + u_sky_sh[1] * (0.488603 * n.y) + u_sky_sh[2] * (0.488603 * n.z) +
             u_sky_sh[3] * (0.488603 * n.x) + u_sky_sh[4] * (1.092548 * n.x * n.y) + u_sky_sh[5] * (1.092548 * n.y * n.z) +
             u_sky_sh[6] * (0.315392 * (3.0 * n.z * n.z - 1.0)) + u_sky_sh[7] * (1.092548 * n.x * n.z) +
             u_sky_sh[8] * (0.546274 * (n.x * n.x - n.y * n.y)), vec3(0.0));
}

vec3 fresnel_schlick(vec3 f0, float cos_theta) { return f0 + (1.0 - f0) * pow(1.0 - clamp(cos_theta, 0.0, 1.0), 5.0); }

// One point of a surface: base colour, metallic, roughness, ambient
// occlusion and emission.
struct Point {
  vec3 c;
  float metallic;
  float roughness;
  float occlusion;
  vec3 emission;
};

vec3 surface_ambient(Point p, vec3 n, vec3 v) {
  float nv = max(dot(n, v), 1e-4);
  vec3 f0 = mix(vec3(0.04), p.c, p.metallic);
  // Karis 2014, "Physically Based Shading on Mobile": A, B of the split sum.
  const vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022), c1 = vec4(1.0, 0.0425, 1.04, -0.04);
  vec4 k = p.roughness * c0 + c1;
  float a004 = min(k.x * k.x, exp2(-9.28 * nv)) * k.x + k.y;
  vec2 ab = max(vec2(-1.04, 1.04) * a004 + k.zw, vec2(0.0));
  vec3 r = reflect(-v, n);
  float alpha = p.roughness * p.roughness;
  vec3 prefiltered = u_has_prefiltered != 0 ? textureLod(u_prefiltered, r, p.roughness * u_prefiltered_levels).rgb
                                            : mix(sky_radiance(r), sky_irradiance(r), alpha);
  return p.occlusion * ((1.0 - p.metallic) * p.c * sky_irradiance(n) + prefiltered * (f0 * ab.x + ab.y)) + p.emission;
}

vec3 surface_direct(Point p, vec3 n, vec3 v, vec3 l, vec3 e) {
  vec3 h = normalize(l + v);
  float nl = max(dot(n, l), 0.0), nv = max(dot(n, v), 1e-4), nh = max(dot(n, h), 0.0);
  float alpha = max(p.roughness * p.roughness, 2e-3), a2 = alpha * alpha;
  vec3 f = fresnel_schlick(mix(vec3(0.04), p.c, p.metallic), dot(v, h));
  float denom = nh * nh * (a2 - 1.0) + 1.0;
  float d = a2 / (kPi * denom * denom);
  float vis = 0.5 / max(nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2), 1e-6);
  return ((1.0 - p.metallic) * (1.0 - f) * p.c + kPi * d * vis * f) * e;
}

vec2 map_coords(int k, vec3 n) { return caustix_texture_coords(u_map_projection[k], u_map_rows[2 * k], u_map_rows[2 * k + 1], v_uv, v_world, n); }

void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;  // open meshes are lit from either side
  vec3 ng = n;  // the geometric normal: where box-projected maps are looked up
#ifdef SAMPLE_MAPS
  // The normal map's frame, from derivatives taken before anything discards.
  // (u_maps is uniform: the branch keeps the derivatives defined.)
  vec2 normal_st = vec2(0.0), dst_dx = vec2(0.0), dst_dy = vec2(0.0);
  vec3 dp_dx = vec3(0.0), dp_dy = vec3(0.0);
  if ((u_maps & 2) != 0) {
    normal_st = map_coords(1, ng);
    dp_dx = dFdx(v_world);
    dp_dy = dFdy(v_world);
    dst_dx = dFdx(normal_st);
    dst_dy = dFdy(normal_st);
  }
#endif
  vec4 base = vec4(u_albedo, u_alpha) * v_color;
  if (u_albedo_projection != 0) {
    base *= texture(u_albedo_map, caustix_texture_coords(u_albedo_projection, u_albedo_rows[0], u_albedo_rows[1], v_uv, v_world, n));
  }
  if (u_alpha_mode == 1 && base.a < u_alpha_cutoff) discard;
  float alpha = u_alpha_mode == 2 ? base.a : 1.0;
  Point p = Point(base.rgb, u_metallic, u_roughness, 1.0, u_emissive);
#ifdef SAMPLE_MAPS
  if ((u_maps & 1) != 0) {
    vec3 mr = texture(u_metallic_roughness_map, map_coords(0, ng)).rgb;
    p.metallic *= mr.b;
    p.roughness *= mr.g;
  }
  if ((u_maps & 2) != 0) {
    float det = dst_dx.x * dst_dy.y - dst_dy.x * dst_dx.y;
    vec3 t = (dst_dy.y * dp_dx - dst_dx.y * dp_dy) * (det < 0.0 ? -1.0 : 1.0);
    t -= n * dot(n, t);
    if (dot(t, t) > 1e-20) {
      t = normalize(t);
      vec3 tn = texture(u_normal_map, normal_st).rgb * 2.0 - 1.0;
      tn.xy *= u_normal_scale;
      n = normalize(mat3(t, cross(n, t), n) * tn);
    }
  }
  if ((u_maps & 4) != 0) p.occlusion = 1.0 + u_occlusion_strength * (texture(u_occlusion_map, map_coords(2, ng)).r - 1.0);
  if ((u_maps & 8) != 0) p.emission *= texture(u_emissive_map, map_coords(3, ng)).rgb;
#endif
  vec3 a = u_fog != 0 ? exp(-u_fog_k * length(v_world - u_fog_eye)) : vec3(1.0);
  vec3 v = normalize(u_eye - v_world);
  if (u_pass == 0) {
    vec3 ambient = u_surface != 0 ? surface_ambient(p, n, v) : p.c * u_ambient;
    o_color = vec4(a * ambient + (1.0 - a) * u_water_color, alpha);
    return;
  }
  vec3 e = caustix_irradiance(v_world, n);
  vec3 lit = u_surface != 0 ? surface_direct(p, n, v, -caustix_light_travel(v_world), e) : p.c * e;
  o_color = vec4(a * lit, u_alpha_mode == 2 ? alpha : 0.0);  // blended: SRC_ALPHA weighs it; opaque: alpha stays
}
