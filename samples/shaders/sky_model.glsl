// The sky as the sample renderer draws it, shared by the background
// (sky.frag) and the surfaces' image-based light (receiver.frag); the CPU
// twin that projects it onto spherical harmonics is renderer.cpp's
// SkyModelCpu. Flat (u_sky_analytic 0): u_sky_flat above the horizon.
// Analytic: the daylight sky of Preetham, Shirley & Smits (1999, "A
// Practical Analytic Model for Daylight", §3 and appendix A.2): each of
// luminance Y and chromaticities x, y is its zenith value times Perez's
// distribution F(theta, gamma) / F(0, theta_s), with
//   F(theta, gamma) = (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma),
// theta the view direction's angle from the zenith, gamma its angle from
// the sun and A..E linear in the turbidity (computed on the CPU:
// renderer.cpp, sky_terms()). Yxy -> CIE XYZ -> linear sRGB (IEC 61966-2-1),
// scaled so that the zenith has the luminance of the flat sky it replaces.
// Below the horizon the model has no meaning: the horizon's value.
uniform int u_sky_analytic;
uniform vec3 u_sky_flat;
uniform vec3 u_to_sun;                 // unit, towards the sun
uniform vec3 u_perez[5];               // A..E, each (Y, x, y)
uniform vec3 u_zenith_over_f0;         // (Y_z, x_z, y_z) / F(0, theta_s)
uniform float u_scale;                 // radiance per unit of Y

vec3 sky_perez(float cos_theta, float gamma, float cos_gamma) {
  return (1.0 + u_perez[0] * exp(u_perez[1] / cos_theta)) *
         (1.0 + u_perez[2] * exp(u_perez[3] * gamma) + u_perez[4] * cos_gamma * cos_gamma);
}

vec3 sky_radiance(vec3 d) {
  if (u_sky_analytic == 0) return u_sky_flat;
  d = normalize(vec3(d.x, max(d.y, 0.0), d.z));
  float cos_theta = max(d.y, 0.02);
  float cos_gamma = clamp(dot(d, u_to_sun), -1.0, 1.0);
  vec3 yxy = u_zenith_over_f0 * sky_perez(cos_theta, acos(cos_gamma), cos_gamma);
  float Y = yxy.x, x = yxy.y, y = max(yxy.z, 1e-4);
  vec3 xyz = vec3(x / y * Y, Y, (1.0 - x - y) / y * Y);
  vec3 rgb = mat3(3.2406, -0.9689, 0.0557, -1.5372, 1.8758, -0.2040, -0.4986, 0.0415, 1.0570) * xyz;
  return max(rgb, vec3(0.0)) * u_scale;
}
