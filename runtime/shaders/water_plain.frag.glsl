#version 450 core
// The plain water surface (WaterLook::textures off): over the already-drawn scene (premultiplied
// alpha): Schlick-Fresnel reflection of the sky, a faint body colour, and the
// sun's specular highlight; no refraction or reflection textures (Mihalik 2008
// surface: water.frag).
in vec3 v_world;
in vec3 v_normal;

uniform vec3 u_eye;
uniform vec3 u_sky;
uniform float u_ior;
uniform vec3 u_sun_direction;  // direction of travel; zero if no sun
uniform vec3 u_sun_color;

out vec4 o_color;

void main() {
  vec3 n = normalize(v_normal);
  vec3 v = normalize(u_eye - v_world);
  if (dot(n, v) < 0.0) n = -n;  // seen from below
  float cos_i = clamp(dot(n, v), 0.0, 1.0);
  float r0 = (u_ior - 1.0) / (u_ior + 1.0);
  r0 *= r0;
  float fresnel = r0 + (1.0 - r0) * pow(1.0 - cos_i, 5.0);
  vec3 r = reflect(-v, n);
  vec3 sky = u_sky * (0.55 + 0.45 * clamp(r.y, 0.0, 1.0));
  float spec = pow(max(dot(r, -u_sun_direction), 0.0), 600.0) * 30.0;
  const vec3 body = vec3(0.01, 0.05, 0.07);
  const float body_alpha = 0.2;
  float alpha = fresnel + (1.0 - fresnel) * body_alpha;
  o_color = vec4(fresnel * sky + (1.0 - fresnel) * body_alpha * body + spec * u_sun_color, alpha);
}
