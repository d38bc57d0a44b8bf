// The water surface seen by the camera (Mihalik 2008, ch. 6-7 and §9.1;
// prefixed with #version and caustix.glsl's optics). Drawn opaque over the scene.
//
// From above (§7.1-7.4): the refracted view ray is followed into the
// refraction texture (the underwater part seen from the refraction camera,
// §5.1) by the W/A iteration against that texture's depth; its colour is
// attenuated towards the water colour over the path |A - U| (eq. 4-5); the
// reflection texture (the part above, from the mirrored camera, §5.2) is
// read at U + c R (eq. 6); both are mixed by Fresnel (eq. 7-9).
// From below (§7.5): refraction by the approximation R1 = n(-N - E) + N
// (eq. 12), which never fails where refract() would beyond the critical
// angle, read at U + m R1 (eq. 13) in the texture of the part above; the
// reflection at U + m R2 (eq. 14-15) in the mirrored texture of the part
// below, which was fogged when it was drawn (eq. 10); attenuation over
// |U - C1| (eq. 5).
// Dispersion: the refraction and Fresnel run once per
// wavelength sample at the water's index there, and the pixel is the sum
// of each sample's colour times its bin's RGB weight (one sample (1, 1, 1)
// at n_d without). The sun's highlight is a reflection: once.
in vec3 v_world;
in vec3 v_normal;

uniform vec3 u_eye;
uniform int u_under;  // 1: the camera is under the water
uniform int u_wave_count;
uniform vec4 u_waves[32];  // xyz the sample's RGB weight, w the water's index at its wavelength
// Refraction camera: world -> its view space, its projection with FOV_ext,
// and that projection's depth terms (clip z = A z + B, clip w = -z).
uniform mat4 u_refr_view;
uniform mat4 u_refr_proj;
uniform vec2 u_refr_depth_ab;
uniform mat4 u_refl_view_proj;  // world -> the mirrored camera's clip space (with FOV_ext)
layout(binding = 0) uniform sampler2D u_refr_color;
layout(binding = 1) uniform sampler2D u_refr_depth;
layout(binding = 2) uniform sampler2D u_refl_color;

uniform int u_steps;
uniform int u_max_steps;  // W/A iterations past u_steps until converged
uniform int u_refraction;
uniform int u_reflection;
uniform int u_colour;
uniform int u_fresnel_exact;
uniform float u_q;
uniform float u_c;
uniform float u_m;
uniform vec3 u_k;
uniform vec3 u_water_color;  // radiance of deep water (C_water)
uniform vec3 u_sun_direction;  // direction of travel; zero if no sun
uniform vec3 u_sun_color;
uniform int u_debug;  // WaterDebug: 0 colour, 1 F, 2 W/A lookup, 3 exact lookup

out vec4 o_color;

vec2 refr_uv(vec3 v) {
  vec4 c = u_refr_proj * vec4(v, 1.0);
  return c.xy / c.w * 0.5 + 0.5;
}

// ConvertDepth of §9.1: a depth-buffer value -> view-space z (negative).
float view_z(vec2 uv) {
  float d = texture(u_refr_depth, uv).r;
  return -u_refr_depth_ab.y / ((2.0 * d - 1.0) + u_refr_depth_ab.x);
}

// How far the ray u + s r runs inside the refraction camera's frustum (its
// four sides and its far plane), beyond which the depth texture saw
// nothing: in clip space each bound is linear in s, f0 + s f1 >= 0.
float frustum_exit(vec3 u, vec3 r) {
  vec4 c0 = u_refr_proj * vec4(u, 1.0), c1 = u_refr_proj * vec4(r, 0.0);
  float s = 1e30;
  vec4 f0 = vec4(c0.w - c0.x, c0.w + c0.x, c0.w - c0.y, c0.w + c0.y);
  vec4 f1 = vec4(c1.w - c1.x, c1.w + c1.x, c1.w - c1.y, c1.w + c1.y);
  for (int k = 0; k < 4; ++k) {
    if (f1[k] < 0.0) s = min(s, max(f0[k], 0.0) / -f1[k]);
  }
  if (c1.w - c1.z < 0.0) s = min(s, max(c0.w - c0.z, 0.0) / (c1.z - c1.w));
  return s;
}

// The reference for the W/A iteration: march the same ray through the same
// depth texture in steps of 1/`divisions` of the depth under U (at most
// `limit` of them), then bisect `bisections` times. The W/A iteration falls
// back on a coarse one where it has not converged: `span` > 0 makes its
// steps at least 1/`span` of the ray's run inside the frustum and ends the
// march where the ray leaves it. (A ray that leaves the floor's edge for
// the empty background beyond, wavy_pool's water outside its floor, took
// up to 512 steps of a fifth of a metre; 90 % of the view's depth reads
// went to the quarter of its pixels that fell back.)
vec3 march_lookup(vec3 u, vec3 r, int divisions, int limit, int bisections, int span) {
  float dv = length(u * (view_z(refr_uv(u)) / u.z) - u);
  float ds = max(dv, 1e-4) / float(divisions);
  float run = span > 0 ? frustum_exit(u, r) : 1e30;
  if (run < 1e29) {
    ds = max(ds, run / float(span));
    limit = min(limit, int(ceil(run / ds)) + 1);
  }
  float s0 = 0.0, s1 = -1.0;
  for (int i = 1; i <= limit; ++i) {
    vec3 p = u + float(i) * ds * r;
    if (p.z > -1e-6) break;
    if (abs(p.z) >= abs(view_z(refr_uv(p)))) {
      s1 = float(i) * ds;
      break;
    }
    s0 = float(i) * ds;
  }
  if (s1 < 0.0) return u + s0 * r;
  for (int i = 0; i < bisections; ++i) {
    float sm = 0.5 * (s0 + s1);
    vec3 p = u + sm * r;
    if (abs(p.z) >= abs(view_z(refr_uv(p)))) s1 = sm; else s0 = sm;
  }
  return u + s1 * r;
}

vec3 exact_lookup(vec3 u, vec3 r) { return march_lookup(u, r, 256, 8192, 24, 0); }

// §7.1: where the ray u + s r (refraction-camera view space) meets the
// depth texture. Returns W (xyz) and |A - W| (w); a_out is A, the point of
// the depth texture on the camera ray through W.
//
// `steps` iterations always run (the paper's fixed count); with
// max_steps > steps they go on while the best miss |A - W| is over half a
// texel's footprint at W: at grazing angles (the far floor through waves)
// three iterations stop short, and where the last one switches between
// converged and not the floor jumps at a seam.
vec4 wa_iteration(vec3 u, vec3 r, int steps, int max_steps, out vec3 a_out) {
  vec3 w_best = u, a_best = u;
  float best = 1e30;
  vec3 wi = u, ai = u;  // W_0 = A_0 = U
  // A texel's footprint per metre of depth: 2 / (size * P[1][1]).
  float texel = 2.0 / (float(textureSize(u_refr_depth, 0).x) * u_refr_proj[1][1]);
  for (int i = 0; i < max(steps, max_steps); ++i) {
    if (i >= steps && best <= 0.5 * texel * abs(w_best.z)) break;
    if (wi.z > -1e-6) break;  // behind the refraction camera
    vec3 an = wi * (view_z(refr_uv(wi)) / wi.z);  // A_(i+1)
    float dist = length(an - wi);
    if (dist < best) {
      best = dist;
      w_best = wi;
      a_best = an;
    }
    // Eq. 3: the point of p (u + s r) nearest the line A_i A_(i+1) ...
    vec3 q = an - ai;
    vec3 rq = cross(r, q);
    float nn = dot(rq, rq);
    vec3 wn = wi;
    bool between = i > 0 && nn > 1e-12 * dot(q, q);
    if (between) {
      wn = u + max(dot(cross(ai - u, q), rq) / nn, 0.0) * r;
      // ... if it lies between them (§9.1's 10 % slack) ...
      between = length(q) * 1.1 >= length(wn - ai) + length(an - wn);
    }
    // ... else |A_(i+1) - W_i| along p, down if W_i is nearer the camera
    // than A_(i+1), back up towards U if it is beyond (figs. 11-12).
    if (!between) wn = wi + (abs(wi.z) > abs(an.z) ? -dist : dist) * r;
    ai = an;
    wi = wn;
  }
  // Not converged within max_steps (rays that graze the floor far away,
  // or pass a depth edge): a coarse march with bisection instead.
  if (max_steps > steps && best > 0.5 * texel * abs(w_best.z)) {
    vec3 w = march_lookup(u, r, 16, 512, 10, 64);
    if (w.z < -1e-6) {
      vec3 a = w * (view_z(refr_uv(w)) / w.z);
      float miss = length(a - w);
      if (miss < best) {
        best = miss;
        w_best = w;
        a_best = a;
      }
    }
  }
  a_out = a_best;
  return vec4(w_best, best);
}

// The reflected colour (eq. 6 above the water, eq. 14-15 below): the same
// at every wavelength.
vec3 reflected(vec3 n, vec3 e) {
  vec4 c;
  if (u_under == 0) {
    vec3 rr = reflect(-e, n);
    c = u_refl_view_proj * vec4(v_world + u_c * rr, 1.0);  // eq. 6
  } else {
    vec3 r2 = 2.0 * dot(-n, e) * -n - e;  // eq. 14, with the normal facing the camera
    c = u_refl_view_proj * vec4(v_world + u_m * r2, 1.0);  // eq. 15
  }
  return texture(u_refl_color, c.xy / c.w * 0.5 + 0.5).rgb;
}

// Eq. 4-9 at index `ior` with the reflected colour `refl_color`: the
// pixel's colour at one wavelength, with the Fresnel factor and the lookup
// (and its residual) for the debug views.
vec3 shade(vec3 n, vec3 e, float ior, vec3 refl_color, out float fresnel, out vec2 lookup, out float residual) {
  vec3 to_cam_n = u_under != 0 ? -n : n;
  float cos_e = clamp(dot(e, to_cam_n), 0.0, 1.0);

  // Fresnel (eq. 7-8; f is the same from either side).
  float f = (ior - 1.0) / (ior + 1.0);
  f *= f;
  fresnel = u_fresnel_exact != 0 ? caustix_fresnel_reflectance(cos_e, u_under != 0 ? ior : 1.0 / ior)
                                 : f + (1.0 - f) * pow(1.0 - cos_e, u_q);
  if (u_reflection == 0) fresnel = 0.0;

  vec3 refr_color;
  float d;  // path length in water for eq. 4
  lookup = vec2(0.0);
  residual = 0.0;
  vec3 u1 = (u_refr_view * vec4(v_world, 1.0)).xyz;
  if (u_under == 0) {
    vec3 r = u_refraction != 0 ? refract(-e, n, 1.0 / ior) : -e;
    vec3 r1 = normalize(mat3(u_refr_view) * r);
    vec3 a;
    vec4 w = wa_iteration(u1, r1, u_steps, u_max_steps, a);
    lookup = refr_uv(w.xyz);
    residual = w.w;
#ifdef CAUSTIX_EXACT_LOOKUP
    // Only in the program built for WaterDebug::kExactLookup: behind a
    // uniform test the exact march still cost llvmpipe, which runs every
    // branch for all its SIMD lanes, 8-20 % of the surface view.
    lookup = refr_uv(exact_lookup(u1, r1));
#endif
    refr_color = texture(u_refr_color, lookup).rgb;
    d = length(a - u1);
  } else {
    vec3 r1 = u_refraction != 0 ? ior * (-n - e) + n : -e;  // eq. 12
    lookup = refr_uv(u1 + u_m * normalize(mat3(u_refr_view) * r1));  // eq. 13
    refr_color = texture(u_refr_color, lookup).rgb;
    d = length(u_eye - v_world);
  }
  vec3 a = u_colour != 0 ? exp(-u_k * d) : vec3(1.0);       // eq. 4
  vec3 refr_new = u_water_color + a * (refr_color - u_water_color);  // eq. 5
  return refr_new + fresnel * (refl_color - refr_new);       // eq. 9
}

void main() {
  vec3 n = normalize(v_normal);  // up, towards the sky
  vec3 e = normalize(u_eye - v_world);
  vec3 color = vec3(0.0);
  float fresnel = 0.0, residual = 0.0;
  vec2 lookup = vec2(0.0);
  vec3 refl_color = reflected(n, e);
  for (int k = 0; k < u_wave_count; ++k) {
    float fk, rk;
    vec2 lk;
    color += u_waves[k].xyz * shade(n, e, u_waves[k].w, refl_color, fk, lk, rk);
    if (k == 0) {  // the debug views show the first sample
      fresnel = fk;
      lookup = lk;
      residual = rk;
    }
  }
  if (u_under == 0) {
    // The sun's highlight (the reflection texture holds no sun).
    float spec = pow(max(dot(reflect(-e, n), -u_sun_direction), 0.0), 600.0) * 30.0;
    if (u_reflection != 0) color += spec * u_sun_color;
  }

  if (u_debug == 1) color = vec3(fresnel, 0.0, 0.0);
  if (u_debug == 2 || u_debug == 3) color = vec3(lookup, residual);
  o_color = vec4(color, u_debug != 0 ? 2.0 : 1.0);  // alpha 2 marks the water's pixels in diagnostic images
}
