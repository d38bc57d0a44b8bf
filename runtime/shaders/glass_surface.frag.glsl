// The glass's colour (prefixed with #version, caustix.glsl's optics and
// glass_environment.glsl): Fresnel
// reflection of the sky plus the transmitted view ray's scene colour. The
// exit ray from the table is marched through the opaque scene's depth
// buffer in screen space (the first sample behind the stored depth is the
// nearby geometry seen through the glass); rays that leave the screen or
// hit nothing see the sky.
in vec3 v_world;
in vec3 v_normal;
in vec3 v_exit;
in vec3 v_exit_dir;
in vec3 v_transmitted;

layout(binding = 0) uniform sampler2D u_scene_color;
layout(binding = 1) uniform sampler2D u_scene_depth;
uniform mat4 u_view_proj;
uniform vec3 u_eye;
uniform float u_ior;
uniform float u_march_length;

out vec4 o_color;

vec3 scene_along(vec3 o, vec3 d) {
  const int kSteps = 48;
  // A surface nearer the camera than the exit point is not what the exit
  // ray meets (it starts behind it): an object inside the glass, or in
  // front of its far side, would otherwise be "hit" at the first sample
  // wherever it covers the exit point's pixel (an insect in
  // amber turned the whole block black). The table view maps the glass's
  // front straight to its exit, so what is inside it is not seen here
  // (GlassView::kNearby sees it).
  vec4 cs = u_view_proj * vec4(o, 1.0);
  float start = cs.w > 0.0 ? cs.z / cs.w * 0.5 + 0.5 : 0.0;
  for (int k = 1; k <= kSteps; ++k) {
    float t = u_march_length * float(k * k) / float(kSteps * kSteps);  // denser near the glass
    vec4 c = u_view_proj * vec4(o + d * t, 1.0);
    if (c.w <= 0.0) break;
    vec3 ndc = c.xyz / c.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) break;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    float depth = texture(u_scene_depth, uv).r;
    if (depth < 1.0 && depth >= start && ndc.z * 0.5 + 0.5 >= depth) return texture(u_scene_color, uv).rgb;
  }
  return glass_sky(d);
}

void main() {
  vec3 n = normalize(v_normal);
  vec3 view = normalize(v_world - u_eye);
  if (dot(n, view) > 0.0) n = -n;
  float r = 1.0 - caustix_fresnel_transmittance(max(dot(-view, n), 0.0), u_ior);
  vec3 reflected = glass_sky_reflected(reflect(view, n));
  o_color = vec4(r * reflected + v_transmitted * scene_along(v_exit, normalize(v_exit_dir)), 1.0);
}
