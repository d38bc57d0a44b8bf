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
// uniform grid then 0.0290; docs/caustic-maps.md). The radius is capped at u_max_radius
// (the implementation's point size); the normalisation keeps the flux
// whole there too.
//
// The focus window (u_focus = 1): where the photons land
// concentrated, their light goes into the window's finer texels (u_window
// = 1: u_window_size a side over the square of Focus.window, placed by
// causticmap_focus.comp, drawn in the framebuffer's region from u_origin)
// instead of the main map's; caustix.glsl adds the two inside the square.
// The window's share of a photon follows where it lands, not the photon:
// from causticmap_focus.comp's cells' counts, bilinear between the cells'
// centres, it is the product of three ramps: the count over u_min_count
// (1 where the photons land at kFocusConcentration times the light's own
// density) from 1/2 to 1; the photons per window texel from kSparse to
// kDense; and the distance to the window's edge, from the widest splat's
// radius in, over a cell. So the share changes over a cell or more (3 cm
// on a 4 m floor), several of the main map's splats wide: where it changed
// within a splat, the main map's blur of its part against the window's
// sharp part moved light across the change (a bright square edge, 25 % on
// glass_ball).
// The window's sigma is u_window_sigma window texels, or the photons' own
// spacing where that is wider, so that they print no lattice (moire):
// - the uniform grid (u_grid > 0): kSpread times the distance to the
//   photon's grid neighbours' landing points, the nearer along each grid
//   axis and the farther of the two axes (the spacing behind a lens
//   differs along and across the radius, several times near a focus);
// - adaptive leaves: twice d0 = u_block / sqrt(count) window texels times
//   the leaf's spacing, from causticmap_density's count over the window
//   (u_window_density), as the main map's leaves above;
// never wider than kMaxSpread times u_window_sigma. Both passes compute
// the same share: the main map gets the rest, and every photon's flux
// stays whole.
layout(std430, binding = 0) readonly buffer Photons { vec4 photon[]; };  // 2 per photon: (s, t, spacing, -), (flux rgb, alive)
layout(std430, binding = 6) readonly buffer Focus { vec4 focus; uint bins[]; };  // (centre s, centre t, half-size, 1), the cells' counts
const int kBins = 128;  // causticmap_focus.comp's (gl/focus_window.h)
layout(binding = 1) uniform sampler2D u_density;  // finest-grid photons per block (causticmap_density)
layout(binding = 2) uniform sampler2D u_window_density;  // the same over the window (adaptive leaves)
uniform float u_size;        // caustic map texels a side
uniform float u_sigma;       // texels
uniform float u_window_sigma;  // the window's least sigma, its texels (the option's, also with the main map's two-pass blur)
uniform float u_max_radius;  // texels
uniform int u_variable;      // adaptive leaves: sigma from the spacing and density
uniform float u_block;       // texels a side of one density texel
uniform int u_focus;         // 1: a focus window takes its share of each photon
uniform int u_window;        // 1: this pass draws the window (u_size = u_window_size)
uniform float u_main_size;   // the main map's texels a side
uniform float u_window_size; // the window's texels a side
uniform vec2 u_origin;       // the drawn region's lower-left corner in the framebuffer, texels
uniform int u_grid;          // the uniform grid's side (0: adaptive leaves)
uniform float u_min_count;   // causticmap_focus.comp's: a concentrated cell's count
// A Gaussian of half the photons' spacing leaves e^(-2 pi^2 / 4), 0.7 %,
// of their lattice's ripple.
const float kSpread = 0.5;
const float kMinSigma = 0.1;
// The window's widest splat, times its least sigma: photons the window
// takes land concentrated, and a wider splat would cost its square in
// fragments (up to the main map's sigma, some 8-30 window texels, made
// glass_teapot's splats 5 times and mirror_ring's 4 times as slow on an
// H200) for light the main map's texels resolve nearly as well.
const float kMaxSpread = 4.0;
// Photons per window texel from which the window takes their whole light
// (their spacing 2 texels: sigma about u_window_sigma) and below which none
// (spacing 4 texels): sparser photons, even where concentrated, would print
// their grain into the finer texels (mirror_ring's nephroid, lit by few
// photons off its thin wall), which the main map's wider splats smooth.
const float kDense = 1.0 / 4.0, kSparse = 1.0 / 16.0;
out vec3 v_flux;
out vec2 v_centre;      // landing point, framebuffer texels
out float v_norm;       // 1 / sum of the weights over the covered texels
out float v_sigma;      // this photon's sigma, texels
flat out vec3 v_map;    // framebuffer texel -> main map texel: (q - u_origin) * z + xy
float gauss(float d) { return v_sigma > 0.0 ? exp(-0.5 * d * d / (v_sigma * v_sigma)) : 1.0; }
float radius_of(float sigma) { return sigma > 0.0 ? min(ceil(3.0 * sigma), u_max_radius) : 0.0; }

// A cell's count (clamped to the grid's edge cells).
float cell_count(ivec2 c) {
  c = clamp(c, ivec2(0), ivec2(kBins - 1));
  return float(bins[c.y * kBins + c.x]);
}

// The window's share of a photon landing at main-map coordinate st, whose
// window texel is w.
float window_share(vec2 st, vec2 w) {
  vec2 g = st * float(kBins) - 0.5;
  ivec2 c = ivec2(floor(g));
  vec2 f = g - vec2(c);
  float n = mix(mix(cell_count(c), cell_count(c + ivec2(1, 0)), f.x), mix(cell_count(c + ivec2(0, 1)), cell_count(c + ivec2(1, 1)), f.x), f.y);
  float cell = u_window_size / (2.0 * focus.z * float(kBins));  // window texels a cell's side
  float per_texel = n / (cell * cell);  // photons per window texel
  // From the widest splat's radius in: no splat is cut at the edge.
  float edge = min(min(w.x, w.y), u_window_size - max(w.x, w.y)) - radius_of(kMaxSpread * max(u_window_sigma, 1.0)) - 1.0;
  return clamp(2.0 * n / u_min_count - 1.0, 0.0, 1.0) * clamp((per_texel - kSparse) / (kDense - kSparse), 0.0, 1.0) *
         clamp(edge / cell, 0.0, 1.0);
}

// The photon's sigma in the window's texels.
float window_sigma(vec4 a, vec2 w, float scale) {
  float spread;
  if (u_grid > 0) {
    // Along each grid axis the nearer of the two neighbours (a fold, the
    // glass's rim or a TIR photon on one side sends the other far), then
    // the farther axis.
    ivec2 ij = ivec2(gl_VertexID % u_grid, gl_VertexID / u_grid);
    float along[2] = float[2](1e30, 1e30);
    for (int k = 0; k < 4; ++k) {
      ivec2 q = ij + ivec2(k == 0 ? 1 : k == 1 ? -1 : 0, k == 2 ? 1 : k == 3 ? -1 : 0);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(u_grid)))) continue;
      int n = q.y * u_grid + q.x;
      if (photon[2 * n + 1].w > 0.0) along[k >> 1] = min(along[k >> 1], length(photon[2 * n].xy - a.xy));
    }
    float far = max(along[0] < 1e29 ? along[0] : 0.0, along[1] < 1e29 ? along[1] : 0.0);
    spread = kSpread * far * u_main_size * scale;
  } else {
    spread = 2.0 * a.z * u_block / sqrt(max(texture(u_window_density, w / u_window_size).r, 1e-6));
  }
  return clamp(spread, u_window_sigma, kMaxSpread * max(u_window_sigma, 1.0));
}

void main() {
  vec4 a = photon[2 * gl_VertexID], b = photon[2 * gl_VertexID + 1];
  v_flux = b.rgb;
  bool drawn = b.w > 0.0;
  // Window texels per main texel, where the window's corner lies in main
  // texels, and the photon in the window's texels.
  bool windowed = u_focus != 0 && focus.z > 0.0;
  float scale = windowed ? u_window_size / (2.0 * focus.z * u_main_size) : 1.0;
  vec2 corner = windowed ? (focus.xy - focus.z) * u_main_size : vec2(0.0);
  vec2 w = (a.xy * u_main_size - corner) * scale;
  float share = windowed && drawn ? window_share(a.xy, w) : 0.0;
  if (u_window != 0) {
    v_flux *= share;
    drawn = drawn && share > 0.0;
    v_map = vec3(corner, 1.0 / scale);
    v_centre = w;
    v_sigma = drawn ? window_sigma(a, w, scale) : 0.0;
  } else {
    v_flux *= 1.0 - share;
    drawn = drawn && share < 1.0;
    v_map = vec3(0.0, 0.0, 1.0);
    v_centre = a.xy * u_main_size;
    v_sigma = u_sigma;
    if (u_variable != 0 && a.z > 1.0) {
      float d0 = u_block / sqrt(max(texture(u_density, a.xy).r, 1e-6));
      v_sigma = clamp(2.0 * a.z * d0, u_sigma, a.z * u_sigma);
    }
  }
  // Below a tenth of a texel the Gaussian is the texel the photon lands in
  // (and narrower ones underflow at every texel centre, losing the flux).
  if (v_sigma < kMinSigma) v_sigma = 0.0;
  float radius = radius_of(v_sigma);
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
  gl_Position = drawn ? vec4((texel + 0.5) / u_size * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
  v_centre += u_origin;  // the fragments' gl_FragCoord is the framebuffer's
}
