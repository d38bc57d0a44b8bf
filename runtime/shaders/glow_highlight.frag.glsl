#version 450 core
// Mihalik 2008 §9.3: only the water's specular highlight, pow(R.E, 200) times
// the sun's colour, into a low-resolution target that glow.frag spreads.
in vec3 v_world;
in vec3 v_normal;

uniform vec3 u_eye;
uniform vec3 u_sun_direction;  // direction of travel
uniform vec3 u_sun_color;  // divided by the glow's scale (glow.frag): the target holds half floats
// The scene's depth in the frame's pixels (Engine::draw_water's scene_depth): a glint
// the scene hides does not glow (thesis_teapot's pool wall).
layout(binding = 0) uniform sampler2D u_scene_depth;
uniform bool u_scene_depth_bound;
uniform vec2 u_glow_size;  // the quarter-size target's pixels
uniform vec4 u_viewport;   // the frame's viewport in u_scene_depth's pixels

out vec4 o_color;

void main() {
  if (u_scene_depth_bound) {
    // Same projection, so window depths compare; the farthest of the
    // full-size texels under this quarter-size one, so a glint the scene
    // hides only in part still glows.
    ivec2 size = textureSize(u_scene_depth, 0);
    ivec2 base = ivec2(u_viewport.xy + gl_FragCoord.xy * u_viewport.zw / u_glow_size);
    float farthest = 0.0;
    for (int k = 0; k < 4; ++k) {
      ivec2 t = clamp(base + ivec2(k & 1, k >> 1), ivec2(0), size - 1);
      farthest = max(farthest, texelFetch(u_scene_depth, t, 0).r);
    }
    if (gl_FragCoord.z > farthest + 1e-6) discard;
  }
  vec3 n = normalize(v_normal);
  vec3 e = normalize(u_eye - v_world);
  if (dot(n, e) < 0.0) discard;  // from below: no sun glint
  float re = max(dot(reflect(-e, n), -u_sun_direction), 0.0);
  o_color = vec4(pow(re, 200.0) * u_sun_color, 1.0);
}
