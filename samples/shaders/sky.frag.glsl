// The background sky (prefixed with #version and sky_model.glsl): drawn
// behind the receivers (depth 1 where nothing was drawn), so that the
// background, the water's reflection and the view up through the water
// show the same sky.
in vec2 v_uv;
uniform mat4 u_inv_view_proj;
out vec4 o_color;

void main() {
  vec2 ndc = v_uv * 2.0 - 1.0;
  vec4 a = u_inv_view_proj * vec4(ndc, -1.0, 1.0);
  vec4 b = u_inv_view_proj * vec4(ndc, 1.0, 1.0);
  o_color = vec4(sky_radiance(normalize(b.xyz / b.w - a.xyz / a.w)), 0.0);
  gl_FragDepth = 1.0;
}
