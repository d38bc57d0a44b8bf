#version 450 core
// causticmap_density.vert: the adaptive caustic map's landed photons
// counted into a coarse map (one texel per u_block x u_block texels of the
// caustic map), each as the number of finest-grid photons it stands for
// (its spacing squared). causticmap_splat.vert reads the count back as the
// local density of the finest grid's photons: Wyman & Dachsbacher 2008's
// density-driven splat size ("Reducing noise in image-space caustics with
// variable-sized splatting", their photon-count mip map). u_window = 1:
// the same count over the focus window's square (causticmap_focus.comp),
// one texel per u_block x u_block of its texels, which sizes its splats.
layout(std430, binding = 0) readonly buffer Photons { vec4 photon[]; };  // (s, t, spacing, -), (flux rgb, alive)
layout(std430, binding = 6) readonly buffer Focus { vec4 focus; };  // (centre s, centre t, half-size, 1)
uniform int u_window;
out float v_weight;
void main() {
  vec4 a = photon[2 * gl_VertexID], b = photon[2 * gl_VertexID + 1];
  v_weight = a.z * a.z;
  gl_PointSize = 1.0;
  vec2 st = a.xy;
  bool drawn = b.w > 0.0;
  if (u_window != 0) {
    drawn = drawn && focus.z > 0.0;
    st = (st - (focus.xy - focus.z)) / (2.0 * max(focus.z, 1e-30));
  }
  gl_Position = drawn ? vec4(st * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
}
