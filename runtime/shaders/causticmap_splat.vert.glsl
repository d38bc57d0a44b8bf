#version 450 core
// causticmap_splat.vert: one point per photon of causticmap_photons.comp at
// its landing texel of the caustic map. One-pass Gaussian splats (Wyman &
// Dachsbacher 2008, "Reducing noise in image-space caustics with
// variable-sized splatting"; the blog's one-pass blur): the point covers
// the texels within 3 sigma, and the weights are normalised over exactly
// the texel centres the point covers, so a photon's flux is kept whole
// wherever it lands within a texel. sigma = 0: the one texel it lands in.
//
// Adaptive leaves (u_variable = 1): a leaf of spacing s = 2^level on the
// casters' grid stands for s^2 photons of the finest grid, which would
// have landed spread over s times their own spacing there. That spacing,
// d0 = u_block / sqrt(count), comes from causticmap_density's count of
// finest-grid photons around the landing point (Wyman & Dachsbacher's
// density-driven size). The leaf's sigma is twice that spread, 2 s d0,
// kept within [u_sigma, s u_sigma]: u_sigma where the photons converge
// (the focus keeps its sharpness) and at level 0 (the uniform grid's
// splat), wider where they diverge, so coarse leaves do not print their
// lattice into the caustic as ring bands. Twice, not half: the count is
// isotropic, while the lattice spreads along the direction the photons
// diverge in (radially behind a ball lens), so the spacing there is
// several times d0. The factor is measured (caustic_map_test's ring-band
// spread on glass_ball: 0.0855 at 0.5, 0.0474 at 1, 0.0231 at 2; the
// uniform grid 0.0290; docs/caustic-maps.md). The radius is capped at u_max_radius
// (the implementation's point size); the normalisation keeps the flux
// whole there too.
layout(std430, binding = 0) readonly buffer Photons { vec4 photon[]; };  // 2 per photon: (s, t, spacing, -), (flux rgb, alive)
layout(binding = 1) uniform sampler2D u_density;  // finest-grid photons per block (causticmap_density)
uniform float u_size;        // caustic map texels a side
uniform float u_sigma;       // texels
uniform float u_max_radius;  // texels
uniform int u_variable;      // adaptive leaves: sigma from the spacing and density
uniform float u_block;       // caustic map texels a side of one density texel
out vec3 v_flux;
out vec2 v_centre;      // landing point, texels
out float v_norm;       // 1 / sum of the weights over the covered texels
out float v_sigma;      // this photon's sigma, texels
float gauss(float d) { return v_sigma > 0.0 ? exp(-0.5 * d * d / (v_sigma * v_sigma)) : 1.0; }
void main() {
  vec4 a = photon[2 * gl_VertexID], b = photon[2 * gl_VertexID + 1];
  v_flux = b.rgb;
  v_centre = a.xy * u_size;
  v_sigma = u_sigma;
  if (u_variable != 0 && a.z > 1.0) {
    float d0 = u_block / sqrt(max(texture(u_density, a.xy).r, 1e-6));
    v_sigma = clamp(2.0 * a.z * d0, u_sigma, a.z * u_sigma);
  }
  float radius = v_sigma > 0.0 ? min(ceil(3.0 * v_sigma), u_max_radius) : 0.0;
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
