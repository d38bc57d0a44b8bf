#version 450 core
// causticmap_density.vert: the adaptive caustic map's landed photons
// counted into a coarse map (one texel per u_block x u_block texels of the
// caustic map), each as the number of finest-grid photons it stands for
// (its spacing squared). causticmap_splat.vert reads the count back as the
// local density of the finest grid's photons: Wyman & Dachsbacher 2008's
// density-driven splat size ("Reducing noise in image-space caustics with
// variable-sized splatting", their photon-count mip map).
layout(std430, binding = 0) readonly buffer Photons { vec4 photon[]; };  // (s, t, spacing, -), (flux rgb, alive)
out float v_weight;
void main() {
  vec4 a = photon[2 * gl_VertexID], b = photon[2 * gl_VertexID + 1];
  v_weight = a.z * a.z;
  gl_PointSize = 1.0;
  gl_Position = b.w > 0.0 ? vec4(a.xy * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
}
