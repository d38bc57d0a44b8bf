// The sky's environment prefiltered for glossy reflection (prefixed with
// #version): one face of one mip level of the prefiltered cube map, level
// k holding roughness k / (levels - 1). Karis 2013 ("Real Shading in
// Unreal Engine 4"), the split sum's first factor: the GGX lobe of
// roughness r about the reflected direction R, taking N = V = R,
// integrated over light directions L with weight N.L, importance-sampled
// by the Hammersley set; each sample reads the source at the mip level
// whose texel matches its solid angle (Colbert & Krivanek 2007's filtered
// importance sampling), so 64 samples leave no visible noise.
in vec2 v_uv;
layout(binding = 0) uniform samplerCube u_source;  // the environment, with mips
uniform mat4 u_inv_view_proj;  // the face's
uniform float u_roughness;
uniform float u_source_size;   // texels a side of the source's level 0
out vec4 o_color;

const float kPi = 3.14159265358979;
const int kSamples = 64;

vec2 hammersley(int i) {
  uint b = uint(i);
  b = (b << 16u) | (b >> 16u);
  b = ((b & 0x55555555u) << 1u) | ((b & 0xAAAAAAAAu) >> 1u);
  b = ((b & 0x33333333u) << 2u) | ((b & 0xCCCCCCCCu) >> 2u);
  b = ((b & 0x0F0F0F0Fu) << 4u) | ((b & 0xF0F0F0F0u) >> 4u);
  b = ((b & 0x00FF00FFu) << 8u) | ((b & 0xFF00FF00u) >> 8u);
  return vec2(float(i) / float(kSamples), float(b) * 2.3283064365386963e-10);
}

void main() {
  vec4 far = u_inv_view_proj * vec4(v_uv * 2.0 - 1.0, 1.0, 1.0);
  vec3 n = normalize(far.xyz / far.w);
  if (u_roughness <= 0.0) {
    o_color = vec4(textureLod(u_source, n, 0.0).rgb, 1.0);
    return;
  }
  float a = u_roughness * u_roughness, a2 = a * a;
  vec3 up = abs(n.y) < 0.999 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  vec3 tx = normalize(cross(up, n)), ty = cross(n, tx);
  float texel = 4.0 * kPi / (6.0 * u_source_size * u_source_size);  // a level-0 texel's solid angle
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    vec2 xi = hammersley(i);
    float phi = 2.0 * kPi * xi.x;
    float cos_t = sqrt((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y));  // GGX's D(h) cos(h) as a density
    float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    vec3 h = (tx * cos(phi) + ty * sin(phi)) * sin_t + n * cos_t;
    vec3 l = 2.0 * dot(n, h) * h - n;
    float nl = dot(n, l);
    if (nl <= 0.0) continue;
    // pdf(l) = D(h) cos(h) / (4 v.h) with v = n: D / 4.
    float denom = cos_t * cos_t * (a2 - 1.0) + 1.0;
    float pdf = a2 / (kPi * denom * denom) * 0.25;
    float lod = max(0.5 * log2(1.0 / (float(kSamples) * pdf * texel)) + 1.0, 0.0);
    sum += textureLod(u_source, l, lod).rgb * nl;
    weight += nl;
  }
  o_color = vec4(sum / max(weight, 1e-6), 1.0);
}
