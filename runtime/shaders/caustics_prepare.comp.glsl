// Per light, per frame (Tipprasert 2006 §4.3; prefixed with #version and caustix.glsl's optics): mode 0 refracts the light at every
// water vertex with its normal (eq. 2-8, GLSL refract); mode 1 computes the
// flux each water triangle transmits, E_in T(theta_i) A_w cos(theta_i)
// (the numerator of eq. 4-18), with the exact unpolarised Fresnel
// transmittance at the triangle's face normal, and the beam's cross-section
// A_w cos(theta_i) (for the magnification clamp).
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 2) readonly buffer Indices { uint indices[]; };
layout(std430, binding = 3) writeonly buffer Refracted { vec4 refracted[]; };  // xyz: T, w: 1 valid / 0 not
layout(std430, binding = 4) writeonly buffer Flux { vec2 flux[]; };          // flux, beam cross-section

uniform int u_mode;
uniform uint u_count;
uniform int u_light_type;  // 1 directional, 2 point
uniform vec3 u_light_direction;
uniform vec3 u_light_position;
uniform float u_light_power;  // E0 (W/m^2) or I (W/sr)
uniform vec3 u_spot;          // a spot's cone about u_light_direction (caustix_spot_factor)
uniform float u_ior;
// Mode 0 also bounds, for caustics_rects.comp, the rays' horizontal travel
// per metre of descent, g = (d.x, d.z) / -d.y, and the water's height:
// order-preserving codes of min gx, min gz, min y, min -gx, min -gz,
// min -y, cleared to 0xffffffff before.
layout(std430, binding = 12) buffer Rects { uint bounds[8]; };

vec3 incident(vec3 p) { return u_light_type == 1 ? u_light_direction : normalize(p - u_light_position); }

uint encode(float f) {
  uint u = floatBitsToUint(f);
  return f >= 0.0 ? u | 0x80000000u : ~u;
}

shared vec3 s_lo[64], s_hi[64];

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (u_mode == 0) {
    vec3 lo = vec3(1e38), hi = vec3(-1e38);  // gx, gz, y
    if (i < u_count) {
      vec3 p = positions[i].xyz;
      vec3 n = normals[i].xyz;
      vec3 l = incident(p);
      lo.z = hi.z = p.y;
      // Light from below the local surface (a steep wave's far side) or a
      // point light under water: no transmitted ray from this vertex.
      if (dot(l, n) >= 0.0 || (u_light_type == 2 && u_light_position.y <= p.y)) {
        refracted[i] = vec4(0.0);
      } else {
        vec3 d = refract(l, n, 1.0 / u_ior);  // eq. 2-8
        refracted[i] = vec4(d, 1.0);
        // A ray not heading down has no bound (the grid is taken).
        bool down = d.y < -1e-6;
        lo.xy = down ? d.xz / -d.y : vec2(-3e38);
        hi.xy = down ? d.xz / -d.y : vec2(3e38);
      }
    }
    uint l = gl_LocalInvocationIndex;
    s_lo[l] = lo;
    s_hi[l] = hi;
    barrier();
    for (uint s = 32u; s > 0u; s >>= 1u) {
      if (l < s) {
        s_lo[l] = min(s_lo[l], s_lo[l + s]);
        s_hi[l] = max(s_hi[l], s_hi[l + s]);
      }
      barrier();
    }
    if (l == 0u) {
      lo = s_lo[0];
      hi = s_hi[0];
      if (lo.x <= hi.x) {  // some ray
        atomicMin(bounds[0], encode(lo.x));
        atomicMin(bounds[1], encode(lo.y));
        atomicMin(bounds[3], encode(-hi.x));
        atomicMin(bounds[4], encode(-hi.y));
      }
      if (lo.z <= hi.z) {
        atomicMin(bounds[2], encode(lo.z));
        atomicMin(bounds[5], encode(-hi.z));
      }
    }
    return;
  }
  if (i >= u_count) return;
  vec3 p0 = positions[indices[3u * i]].xyz;
  vec3 p1 = positions[indices[3u * i + 1u]].xyz;
  vec3 p2 = positions[indices[3u * i + 2u]].xyz;
  vec3 c = cross(p1 - p0, p2 - p0);
  float twice_area = length(c);
  vec3 nf = c / max(twice_area, 1e-30);
  if (nf.y < 0.0) nf = -nf;
  vec3 centre = (p0 + p1 + p2) / 3.0;
  vec3 l = incident(centre);
  float cos_i = max(0.0, -dot(l, nf));
  float e_in = u_light_type == 1 ? u_light_power : u_light_power / max(dot(centre - u_light_position, centre - u_light_position), 1e-12);
  float beam = 0.5 * twice_area * cos_i;
  if (u_light_type == 2 && u_spot.z != 0.0) {
    // A spot's transmitted flux integrated over the triangle, at the
    // centroids of its 8 x 8 equal sub-triangles (falloff, 1 / r^2, cosine
    // and Fresnel at each): one value at the centre would lose a cone
    // narrower than the water's cells (wavy_pool's 3 m cells across its
    // waves put every centre outside a 0.7 m cone, and the floor went
    // dark), as the level map spreads each triangle's flux over its
    // footprint anyway.
    const int kN = 8;
    float sum = 0.0;
    for (int a = 0; a < kN; ++a) {
      for (int b = 0; a + b < kN; ++b) {
        for (int k = 0; k < 2; ++k) {
          if (k == 1 && a + b == kN - 1) break;
          vec2 w = (vec2(a, b) + (k == 0 ? 1.0 : 2.0) / 3.0) / float(kN);
          vec3 d = p0 + w.x * (p1 - p0) + w.y * (p2 - p0) - u_light_position;
          vec3 ld = normalize(d);
          float cs = max(0.0, -dot(ld, nf));
          sum += caustix_spot_factor(ld, u_light_direction, u_spot) / max(dot(d, d), 1e-12) * cs * caustix_fresnel_transmittance(cs, u_ior);
        }
      }
    }
    flux[i] = vec2(u_light_power * sum / float(kN * kN) * 0.5 * twice_area, beam);
    return;
  }
  flux[i] = vec2(e_in * caustix_fresnel_transmittance(cos_i, u_ior) * beam, beam);
}
