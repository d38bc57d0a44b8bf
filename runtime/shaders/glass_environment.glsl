// What the glass view sees where its rays leave the scene: the
// application's environment cube map (GlassViewOptions::environment) in the
// ray's direction, else the flat sky colour; seen by reflection, the flat
// sky is brighter upward (0.6 at the horizon to 1 overhead).
layout(binding = 4) uniform samplerCube u_environment;
uniform int u_has_environment;
uniform vec3 u_sky;

vec3 glass_sky(vec3 d) { return u_has_environment != 0 ? texture(u_environment, d).rgb : u_sky; }
vec3 glass_sky_reflected(vec3 r) {
  return u_has_environment != 0 ? texture(u_environment, r).rgb : u_sky * (0.6 + 0.4 * max(r.y, 0.0));
}
