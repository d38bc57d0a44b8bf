#version 450 core
// Seed 001 §9.3: only the water's specular highlight, pow(R.E, 200) times
// the sun's colour, into a low-resolution target that glow.frag spreads.
in vec3 v_world;
in vec3 v_normal;

uniform vec3 u_eye;
uniform vec3 u_sun_direction;  // direction of travel
uniform vec3 u_sun_color;

out vec4 o_color;

void main() {
  vec3 n = normalize(v_normal);
  vec3 e = normalize(u_eye - v_world);
  if (dot(n, e) < 0.0) discard;  // from below: no sun glint
  float re = max(dot(reflect(-e, n), -u_sun_direction), 0.0);
  o_color = vec4(pow(re, 200.0) * u_sun_color, 1.0);
}
