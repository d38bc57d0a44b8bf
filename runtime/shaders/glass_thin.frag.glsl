// A thin-walled sheet in the glass view (Role::kThin; prefixed
// with #version, caustix.glsl's optics and glass_environment.glsl): what is behind it is seen
// straight through, scaled by what the sheet transmits, plus the sky it
// reflects. Blended with dual-source blending (GlassEngine::draw_glass):
// result = o_color + destination * o_transmit, so that sheets drawn back to
// front each scale what lies behind them (the window holds the caller's
// scene where nothing else was drawn).
in vec3 v_world;
in vec3 v_normal;

uniform vec3 u_eye;
uniform float u_ior;
uniform vec3 u_tint;

layout(location = 0, index = 0) out vec4 o_color;
layout(location = 0, index = 1) out vec4 o_transmit;

void main() {
  vec3 n = normalize(v_normal);
  vec3 view = normalize(v_world - u_eye);
  if (dot(n, view) > 0.0) n = -n;
  // The sheet transmits tint (1 - r) / (1 + r) and reflects 2 r / (1 + r),
  // its inner reflections summed (formats/scene.h Role::kThin).
  float r = caustix_fresnel_reflectance(max(dot(-view, n), 0.0), 1.0 / u_ior);
  vec3 reflected = glass_sky_reflected(reflect(view, n));
  o_color = vec4(2.0 * r / (1.0 + r) * reflected, 1.0);
  o_transmit = vec4(u_tint * ((1.0 - r) / (1.0 + r)), 0.0);
}
