#pragma once
// How the water surface looks when Engine::draw_water draws it (Mihalik 2008,
// Mihálik, ch. 5-9). Each effect can be switched off on its own, for a
// viewer's toggles and for measuring what it costs.

#include <optional>

#include <glm/glm.hpp>

namespace caustix::runtime {

enum class FresnelMode {
  kApprox,  // eq. 7-8: F = f + (1 - f)(1 - E.N)^q
  kExact,   // unpolarised Fresnel reflectance, total internal reflection included
};

// Diagnostic outputs of the water surface instead of its colour (tests and
// the iteration study of docs/water.md). The water's pixels get alpha 2 in
// the caller's colour target; the others keep the scene's colour.
enum class WaterDebug {
  kNone,
  kFresnel,      // r: the reflected fraction F used for the pixel
  kLookup,       // rg: refraction-texture coordinates the W/A iteration found, b: its |A - W|
  kExactLookup,  // rg: where the refracted ray meets the same depth texture, by an exact march
};

struct WaterLook {
  bool textures = true;    // false: the plain surface (sky reflection, no refraction textures)
  bool refraction = true;  // §7.1: bend the view ray; off: look straight through
  bool reflection = true;  // §5.2/§7.3: reflection texture; off: no reflection
  bool colour = true;      // eq. 4-5 (and eq. 10 under water): attenuation towards the water colour
  bool glow = true;        // §9.3
  // The glow's 13 taps on the two diagonals of a 7x7 grid, as §9.3 has
  // them: every isolated glint glows as an X. false: on a disc (round).
  bool glow_star = false;
  FresnelMode fresnel = FresnelMode::kApprox;
  int steps = 3;              // W/A iterations (§7.1; the paper could afford 3)
  // W/A iterations go on past `steps`, up to this many (1..64), while the
  // best miss |A - W| exceeds half a refraction texel at W. At grazing
  // angles three stop short and the floor seen through waves jumps at a
  // seam where the iteration switches between converged and not (issue
  // 21; docs/water.md). <= steps: the paper's fixed count.
  int max_steps = 16;
  // Refraction and reflection textures, square (table 3: 256..1024). 0:
  // as many texels as the viewport has pixels across the extended field of
  // view (fov_ext x its larger side, rounded up to a multiple of 64), at
  // most max_texture_size: the floor's edges seen through the water are
  // not stair-stepped by texels bigger than the pixels up to
  // that size.
  int texture_size = 0;
  // The automatic size's limit (16..8192; 0: 4096): what the textures may
  // cost, 36 bytes a texel for the two (colour in 32-bit floats, one depth
  // buffer). A bake preset records its own (RenderDefaults::water_texture;
  // Engine::default_water_look): fast 256, balanced 512 (9.4 MB), accurate
  // none. Measured in docs/runtime-speed.md.
  int max_texture_size = 512;
  float fov_ext = 1.5f;       // FOV_ext (fig. 5, table 1)
  float fresnel_q = 5.0f;     // q of eq. 7 (table 1)
  float reflect_scale = 1.0f; // c of eq. 6 (table 1; metres)
  float under_scale = 1.5f;   // m of eq. 13/15 (§7.5)
  // Water colour as a reflectance; its radiance is this times the light
  // entering the water (docs/water.md). Table 1: (0, 0.2, 0.1).
  glm::vec3 water_color{0.0f, 0.2f, 0.1f};
  // k of eq. 4, per metre and channel; unset: the scene's absorption.
  std::optional<glm::vec3> attenuation;
  WaterDebug debug = WaterDebug::kNone;
  // The sky's linear radiance (what the water reflects where no scene is
  // behind the reflection, and the plain surface's reflection) and the
  // fraction of it that reaches the scene as ambient light: with the lights
  // it sets the light entering the water, and so the water's colour.
  glm::vec3 sky{0.42f, 0.58f, 0.78f};
  float ambient = 0.12f;
};

}  // namespace caustix::runtime
