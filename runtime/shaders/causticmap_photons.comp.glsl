// causticmap_photons.comp (after #version and caustix.glsl's optics):
// image-space caustic maps (timofy 2009; Shah, Konttinen & Pattanaik 2007,
// "Caustics mapping: an image-space technique for real-time caustics",
// §3), one invocation per photon of one light. Each texel of the casters'
// maps seen from the light (positions and normals of their nearest and
// farthest surfaces) sends one photon:
//  - glass: refracted at the front surface (exact Fresnel), its exit point
//    found by iterating against the back faces (x + t T1 projected into the
//    back map; t from the tangent plane there, Wyman 2005's image-space
//    refraction made iterative), refracted out (exact Fresnel, absorption
//    e^(-sigma t)), or landed on a receiver inside the glass before the
//    exit; total internal reflection at the exit leaves the ray
//    unrefracted (the blog's one-sided refraction) or drops it;
//  - thin-walled glass: through its near sheet and, for a
//    closed surface, its far sheet, without bending, keeping each sheet's
//    transmittance;
//  - mirror: reflected (two-sided, per-channel reflectance); up to
//    u_bounces caster surfaces, the next mirror found by marching the ray
//    across the casters' nearest and farthest layers (a photon that meets
//    one more mirror than allowed ends there);
// (u_bounces counts the casters' surfaces met: glass, then mirrors) then landed on the receivers by iterating against the receivers seen
// from the light (the blog's ten iterations; each step takes the tangent
// plane of the receiver texel it projects into, exact on planes, where
// Shah et al. take the distance to it), and written with its flux for
// causticmap_splat. With adaptive caustic maps (causticmap_adaptive.comp)
// the photons are the traversal's leaves, one invocation each: a cell of
// 2^k x 2^k capture texels leaves from a covered texel found by descending
// the coverage pyramid, with the flux of the cell's covered area. Edge testing and bounded refraction deviation (the
// blog) and the catacaustics' travel limit are optional and counted.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D u_front_pos;  // world xyz, object + 1 (0: none)
layout(binding = 1) uniform sampler2D u_front_nrm;  // normal, V
layout(binding = 2) uniform sampler2D u_back_pos;
layout(binding = 3) uniform sampler2D u_back_nrm;
layout(binding = 4) uniform sampler2D u_receivers;  // normal (0: none), V of the first receiver surface
layout(std430, binding = 0) writeonly buffer Photons { vec4 photon[]; };  // 2 per photon
// Per object: (kind 1 glass / 2 mirror / 3 thin-walled, ior, 1 when a receiver's box meets the glass's, 0), (absorption or reflectance rgb, 0), (glass, thin: the tint at each crossing, Material::tint, 0).
layout(std430, binding = 1) readonly buffer Materials { vec4 material[]; };
// 0 emitted, 1 landed, 2 TIR, 3 edge-dropped, 4 deviation-dropped,
// 5 too far, 6 lost (no receiver where it lands, or outside the map),
// 7 mirror reflections, 8 TIR dropped, 9 out of bounces (met a mirror
// after the last reflection allowed).
layout(std430, binding = 2) buffer Counters { uint counter[]; };
// Adaptive (u_adaptive = 1): causticmap_adaptive.comp's pyramid, lists and state.
layout(std430, binding = 3) readonly buffer Pyramid { vec4 pyramid[]; };
layout(std430, binding = 4) readonly buffer Lists { uint cells[]; };
layout(std430, binding = 5) readonly buffer State { uint list_count[2]; uint leaves; };
uniform int u_adaptive;
uniform uint u_budget;
uniform int u_offset[9];

uniform int u_photons;         // grid side
uniform vec3 u_u, u_v, u_w;    // light frame (V towards the light)
uniform vec3 u_caster_origin;  // centre of the casters' rectangle
uniform vec2 u_caster_half;    // its half extents along U, W
uniform vec3 u_map_origin;     // centre of the caustic map's rectangle
uniform vec2 u_map_half;
uniform int u_light_type;      // 1 directional, 2 point
uniform vec3 u_light_dir;
uniform vec3 u_light_pos;
uniform float u_light_power;   // E0 or I
uniform vec3 u_spot;           // a spot's cone about u_light_dir (caustix_spot_factor)
uniform vec3 u_weight;         // the traced wavelength's RGB weights (dispersion); (1, 1, 1) without
uniform int u_iterations;
uniform int u_exit_iterations;
uniform int u_bounces;
uniform int u_mirrors;         // the scene has mirrors (else no march)
uniform int u_tir_one_sided;
uniform float u_edge_cos;
uniform float u_max_deviation_cos;
uniform float u_max_travel;
uniform float u_tolerance;     // landing: |V(x) - V(receiver)| allowed, metres

vec2 to_uv(vec3 p, vec3 origin, vec2 half_extent) {
  vec3 r = p - origin;
  return 0.5 * (vec2(dot(r, u_u), dot(r, u_w)) / half_extent + 1.0);
}
bool inside(vec2 uv) { return all(greaterThanEqual(uv, vec2(0.0))) && all(lessThan(uv, vec2(1.0))); }
float v_of(vec3 p) { return dot(p - u_map_origin, u_v); }

// The receiver point of the map under uv: the texel's line along V at the
// stored coordinate.
vec3 receiver_point(vec2 uv, float v) {
  vec2 c = (2.0 * uv - 1.0) * u_map_half;
  return u_map_origin + c.x * u_u + c.y * u_w + v * u_v;
}

// Landing on the receivers: t along d from x. Returns false if lost.
bool land(vec3 x, vec3 d, out float t_out) {
  // From the receiver under x itself: with the tangent-plane step, a flat
  // receiver is met in one iteration whichever way the ray goes.
  vec2 uv;
  vec4 r;
  float t = 0.0;
  for (int k = 0; k < u_iterations; ++k) {
    vec3 q = x + t * d;
    uv = to_uv(q, u_map_origin, u_map_half);
    if (!inside(uv)) return false;
    r = texture(u_receivers, uv);
    if (length(r.xyz) < 0.5) break;  // no receiver under this texel: lost
    vec3 n = normalize(r.xyz);
    vec3 qr = receiver_point(uv, r.w);
    float dn = dot(d, n);
    t = abs(dn) > 1e-3 ? dot(qr - x, n) / dn : length(qr - x);
    t = max(t, 0.0);
  }
  vec3 q = x + t * d;
  uv = to_uv(q, u_map_origin, u_map_half);
  if (!inside(uv)) return false;
  r = texture(u_receivers, uv);
  if (length(r.xyz) < 0.5 || abs(v_of(q) - r.w) > u_tolerance) return false;
  if (dot(normalize(r.xyz), d) > 0.0) return false;  // arriving from behind the surface
  t_out = t;
  return true;
}

// The first mirror the ray x + t d (0 < t < t_max) meets, marching across
// the casters' nearest and farthest layers seen from the light.
bool next_mirror(vec3 x, vec3 d, float t_max, int self, out vec3 hit, out vec3 n_hit, out int object) {
  // Steps of two casters' texels across the light (at most 256; the
  // bisection finds the crossing between two steps).
  vec2 texel = 2.0 * u_caster_half / float(u_photons);
  float across = length(d - dot(d, u_v) * u_v);
  float dt = 2.0 * min(texel.x, texel.y) / max(across, 0.05);
  int steps = int(min(ceil(t_max / dt), 256.0));
  dt = t_max / float(max(steps, 1));
  float prev_front = 0.0, prev_back = 0.0;
  bool have_prev = false;
  for (int s = 1; s <= steps; ++s) {
    float t = dt * float(s);
    vec3 q = x + t * d;
    vec2 uv = to_uv(q, u_caster_origin, u_caster_half);
    if (!inside(uv)) { have_prev = false; continue; }
    vec4 f = texture(u_front_pos, uv), b = texture(u_back_pos, uv);
    if (f.w < 0.5) { have_prev = false; continue; }
    float vq = v_of(q);
    float df = vq - v_of(f.xyz), db = vq - v_of(b.xyz);
    // Crossing a layer of a mirror: the ray's coordinate along V passes
    // the layer's between two steps (not the surface it leaves).
    for (int layer = 0; layer < 2; ++layer) {
      float cur = layer == 0 ? df : db, prev = layer == 0 ? prev_front : prev_back;
      vec4 pos = layer == 0 ? f : b;
      int obj = int(pos.w + 0.5) - 1;
      if (!have_prev || sign(cur) == sign(prev) || material[3 * obj].x != 2.0) continue;
      if (obj == self && t < 2.0 * dt) continue;
      // Bisection between the two steps.
      float lo = t - dt, hi = t;
      for (int k = 0; k < 8; ++k) {
        float mid = 0.5 * (lo + hi);
        vec3 qm = x + mid * d;
        vec2 um = to_uv(qm, u_caster_origin, u_caster_half);
        vec4 pm = layer == 0 ? texture(u_front_pos, um) : texture(u_back_pos, um);
        float dm = v_of(qm) - v_of(pm.xyz);
        if (sign(dm) == sign(prev)) lo = mid; else hi = mid;
      }
      hit = x + 0.5 * (lo + hi) * d;
      vec2 uh = to_uv(hit, u_caster_origin, u_caster_half);
      n_hit = normalize((layer == 0 ? texture(u_front_nrm, uh) : texture(u_back_nrm, uh)).xyz);
      object = obj;
      return true;
    }
    prev_front = df;
    prev_back = db;
    have_prev = true;
  }
  return false;
}

// Where the ray x + t d (x on the caster under texel ij) meets the casters'
// farthest surface: iterated against the back faces (x + t d projected into
// the back map; t from the tangent plane there). ne: the normal there.
float far_side(vec3 x, vec3 d, ivec2 ij, out vec3 ne) {
  vec4 bn = texelFetch(u_back_nrm, ij, 0);
  float along = max(-dot(d, u_v), 0.1);
  float t = max((v_of(x) - bn.w) / along, 0.0);
  ne = normalize(bn.xyz);
  for (int k = 0; k < u_exit_iterations; ++k) {
    vec2 uv = to_uv(x + t * d, u_caster_origin, u_caster_half);
    if (!inside(uv)) break;
    vec4 bp = texture(u_back_pos, uv);
    vec3 nb = texture(u_back_nrm, uv).xyz;
    if (bp.w < 0.5 || length(nb) < 0.5) break;
    ne = normalize(nb);
    float dn = dot(d, ne);
    if (abs(dn) > 1e-3) t = max(dot(bp.xyz - x, ne) / dn, 0.0);
  }
  return t;
}

// A thin-walled sheet (Role::kThin) met at cosine cos_i with
// the given index and tint: what it transmits, tint (1 - r) / (1 + r)
// (its inner reflections summed; formats/scene.h Role::kThin), the light
// going on without bending.
vec3 thin_sheet(float cos_i, float ior, vec3 tint) {
  float r = caustix_fresnel_reflectance(cos_i, 1.0 / ior);
  return tint * ((1.0 - r) / (1.0 + r));
}

// Writes photon `id` landed at q with its flux. z: its spacing on the
// casters' grid (2^level texels), by which its splat widens
// (causticmap_splat.vert).
void land_photon(int id, vec3 q, int level, vec3 flux) {
  photon[2 * id] = vec4(to_uv(q, u_map_origin, u_map_half), float(1 << level), 0.0);
  photon[2 * id + 1] = vec4(flux, 1.0);
  atomicAdd(counter[1], 1u);
}

void main() {
  ivec2 ij;
  int id;
  // One texel of the casters' map, across the light: its flux.
  float area = 4.0 * u_caster_half.x * u_caster_half.y / float(u_photons * u_photons);
  int level = 0;
  if (u_adaptive != 0) {
    id = int(gl_WorkGroupID.x * 64u + gl_LocalInvocationIndex);
    if (uint(id) >= leaves) return;
    uint c = cells[2u * u_budget + uint(id)];
    ij = ivec2(int(c & 0xfffu), int((c >> 12) & 0xfffu));
    int k = int(c >> 24);
    level = k;
    // The cell's covered area; it leaves from the covered texel reached by
    // taking the most covered child at each level (the first on ties).
    area *= float(1 << (2 * k)) * pyramid[u_offset[k] + ij.y * (u_photons >> k) + ij.x].w;
    for (; k > 0; --k) {
      ivec2 best = 2 * ij;
      float cov = -1.0;
      for (int j = 0; j < 4; ++j) {
        ivec2 q = 2 * ij + ivec2(j & 1, j >> 1);
        float w = pyramid[u_offset[k - 1] + q.y * (u_photons >> (k - 1)) + q.x].w;
        if (w > cov) { cov = w; best = q; }
      }
      ij = best;
    }
  } else {
    ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= u_photons || ij.y >= u_photons) return;
    id = ij.y * u_photons + ij.x;
  }
  photon[2 * id] = vec4(0.0);
  photon[2 * id + 1] = vec4(0.0);
  vec4 fp = texelFetch(u_front_pos, ij, 0);
  if (fp.w < 0.5) return;
  atomicAdd(counter[0], 1u);
  vec3 x = fp.xyz;
  vec3 n = normalize(texelFetch(u_front_nrm, ij, 0).xyz);
  int object = int(fp.w + 0.5) - 1;
  vec3 d;
  float power;
  if (u_light_type == 1) {
    d = normalize(u_light_dir);
    power = u_light_power * area;
  } else {
    vec3 to = x - u_light_pos;
    d = normalize(to);
    power = u_light_power * area * abs(dot(d, u_v)) / max(dot(to, to), 1e-12) * caustix_spot_factor(d, u_light_dir, u_spot);
  }
  vec3 flux = power * u_weight;
  vec3 d0 = d;
  bool after_mirror = false;
  float travelled = 0.0;
  for (int bounce = 1; bounce <= u_bounces; ++bounce) {
    vec4 m0 = material[3 * object], m1 = material[3 * object + 1], m2 = material[3 * object + 2];
    if (m0.x == 1.0) {
      // Glass: into it at the front surface.
      vec3 nf = dot(n, d) > 0.0 ? -n : n;
      float cos_i = -dot(d, nf);
      if (cos_i < u_edge_cos) { atomicAdd(counter[3], 1u); return; }
      float ior = m0.y;
      vec3 t1 = refract(d, nf, 1.0 / ior);
      flux *= (1.0 - caustix_fresnel_reflectance(cos_i, 1.0 / ior)) * m2.rgb;
      // The exit point: iterate against the back faces.
      vec3 ne;
      float t = far_side(x, t1, ij, ne);
      // A receiver inside the glass (an insect in amber) meets
      // the light before its exit: it lands there, having crossed one
      // surface. The receivers seen from the light are the nearest, so the
      // one under the path is found as for landing; 1e-3 of the path keeps
      // a floor the glass stands on outside it. Only glass whose box meets
      // a receiver's looks (m0.z), in the pass built for such scenes.
#ifdef CAUSTIX_RECEIVERS_INSIDE
      float t_in = 0.0;
      if (m0.z > 0.0 && land(x, t1, t_in) && t_in < t * (1.0 - 1e-3)) {
        land_photon(id, x + t_in * t1, level, flux * exp(-m1.rgb * t_in));
        return;
      }
#endif
      x += t * t1;
      flux *= exp(-m1.rgb * t);
      // Out at the back surface (ne outward).
      vec3 nin = dot(ne, t1) > 0.0 ? -ne : ne;  // facing the ray inside
      float cos_e = -dot(t1, nin);
      vec3 t2 = refract(t1, nin, ior);
      if (dot(t2, t2) == 0.0) {
        if (u_tir_one_sided == 0) { atomicAdd(counter[8], 1u); return; }
        atomicAdd(counter[2], 1u);
        t2 = t1;
      } else {
        flux *= (1.0 - caustix_fresnel_reflectance(cos_e, ior)) * m2.rgb;
      }
      d = normalize(t2);
      if (dot(d, d0) < u_max_deviation_cos) { atomicAdd(counter[4], 1u); return; }
    } else if (m0.x == 3.0) {
      // Thin-walled: through the near sheet without bending,
      // then through the same surface's far sheet if the casters' farthest
      // layer there is its own and lies ahead (a closed shade or bulb; an
      // open pane is its own farthest layer), unless a receiver inside
      // meets the light first.
      flux *= thin_sheet(abs(dot(d, n)), m0.y, m2.rgb);
      vec4 bp = texelFetch(u_back_pos, ij, 0);
      if (int(bp.w + 0.5) - 1 == object) {
        vec3 ne;
        float t = far_side(x, d, ij, ne);
        float t_in = 0.0;
        if (t > 1e-3 * max(u_caster_half.x, u_caster_half.y)) {
          if (land(x, d, t_in) && t_in < t) {
            land_photon(id, x + t_in * d, level, flux);
            return;
          }
          x += t * d;
          flux *= thin_sheet(abs(dot(d, ne)), m0.y, m2.rgb);
        }
      }
    } else {
      // Mirror: two-sided, the normal turned to face the photon.
      vec3 nf = dot(n, d) > 0.0 ? -n : n;
      d = reflect(d, nf);
      flux *= m1.rgb;
      after_mirror = true;
      atomicAdd(counter[7], 1u);
    }
    float t_land = 0.0;
    bool landed = land(x, d, t_land);
    float t_max = landed ? t_land : 4.0 * length(u_map_half);
    vec3 hit, n_hit;
    int next = -1;
    if (u_mirrors != 0 && next_mirror(x, d, t_max, object, hit, n_hit, next)) {
      // A mirror before the receiver: reflect again, or, out of bounces,
      // the photon ends there (dropped, never landed beyond the mirror).
      if (bounce == u_bounces) { atomicAdd(counter[9], 1u); return; }
      travelled += length(hit - x);
      x = hit;
      n = n_hit;
      object = next;
      continue;
    }
    if (!landed) { atomicAdd(counter[6], 1u); return; }
    travelled += t_land;
    if (after_mirror && u_max_travel > 0.0 && travelled > u_max_travel) { atomicAdd(counter[5], 1u); return; }
    land_photon(id, x + t_land * d, level, flux);
    return;
  }
  // Out of bounces on a mirror found by the march: nothing lands.
  atomicAdd(counter[6], 1u);
}
