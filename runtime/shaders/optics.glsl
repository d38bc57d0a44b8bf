// Optics shared by the shaders that need it (prefixed after #version).

// Exact Fresnel transmittance, unpolarised, from air (n = 1) into n2.
float fresnel_transmittance(float cos_i, float n2) {
  float sin2_t = (1.0 - cos_i * cos_i) / (n2 * n2);
  float cos_t = sqrt(max(0.0, 1.0 - sin2_t));
  float rs = (cos_i - n2 * cos_t) / (cos_i + n2 * cos_t);
  float rp = (n2 * cos_i - cos_t) / (n2 * cos_i + cos_t);
  return 1.0 - 0.5 * (rs * rs + rp * rp);
}

// Exact unpolarised Fresnel reflectance at an interface, eta = n1/n2 (n1 on
// the incident side); 1 beyond the critical angle (total internal reflection).
float fresnel_reflectance(float cos_i, float eta) {
  float sin2_t = eta * eta * (1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) return 1.0;
  float cos_t = sqrt(1.0 - sin2_t);
  float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}
