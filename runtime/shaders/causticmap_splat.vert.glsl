#version 450 core
// causticmap_splat.vert: one point per photon of causticmap_photons.comp at
// its landing texel of the caustic map. One-pass Gaussian splats (Wyman &
// Dachsbacher 2008, "Reducing noise in image-space caustics with
// variable-sized splatting"; the blog's one-pass blur): the point covers
// the texels within 3 sigma, and the weights are normalised over exactly
// the texel centres the point covers, so a photon's flux is kept whole
// wherever it lands within a texel. sigma = 0: the one texel it lands in.
layout(std430, binding = 0) readonly buffer Photons { vec4 photon[]; };  // 2 per photon: (s, t, -, -), (flux rgb, alive)
uniform float u_size;   // caustic map texels a side
uniform float u_sigma;  // texels
out vec3 v_flux;
out vec2 v_centre;      // landing point, texels
out float v_norm;       // 1 / sum of the weights over the covered texels
float gauss(float d) { return u_sigma > 0.0 ? exp(-0.5 * d * d / (u_sigma * u_sigma)) : 1.0; }
void main() {
  vec4 a = photon[2 * gl_VertexID], b = photon[2 * gl_VertexID + 1];
  v_flux = b.rgb;
  v_centre = a.xy * u_size;
  float radius = u_sigma > 0.0 ? ceil(3.0 * u_sigma) : 0.0;
  // A point of odd size 2r + 1 centred on the texel the photon is in
  // covers the texels within r of it on each axis.
  vec2 texel = floor(v_centre);
  float sx = 0.0, sy = 0.0;
  for (float k = -radius; k <= radius; k += 1.0) {
    sx += gauss(texel.x + 0.5 + k - v_centre.x);
    sy += gauss(texel.y + 0.5 + k - v_centre.y);
  }
  v_norm = 1.0 / max(sx * sy, 1e-30);
  gl_PointSize = 2.0 * radius + 1.0;
  gl_Position = b.w > 0.0 ? vec4((texel + 0.5) / u_size * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
}
