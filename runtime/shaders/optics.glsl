// Optics shared by the shaders that need it (prefixed after #version).

// Exact Fresnel transmittance, unpolarised, from air (n = 1) into n2.
float fresnel_transmittance(float cos_i, float n2) {
  float sin2_t = (1.0 - cos_i * cos_i) / (n2 * n2);
  float cos_t = sqrt(max(0.0, 1.0 - sin2_t));
  float rs = (cos_i - n2 * cos_t) / (cos_i + n2 * cos_t);
  float rp = (n2 * cos_i - cos_t) / (n2 * cos_i + cos_t);
  return 1.0 - 0.5 * (rs * rs + rp * rp);
}
