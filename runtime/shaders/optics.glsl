// Optics shared by the shaders that need it (prefixed after #version).

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

// Exact Fresnel transmittance, unpolarised, from air (n = 1) into n2.
float fresnel_transmittance(float cos_i, float n2) { return 1.0 - fresnel_reflectance(cos_i, 1.0 / n2); }
