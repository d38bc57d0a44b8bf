#pragma once
// The view side's inputs (engine.h: draw_water, draw_glass, draw_media):
// the caller's camera, what draw_water() asks the caller to draw into its
// textures, and the water as a camera sees it.

#include <glm/glm.hpp>

namespace caustix::runtime {

// A perspective camera of the caller (GL conventions: right-handed view,
// clip z in [-1, 1]).
struct View {
  glm::mat4 view{1.0f};
  float fov_y_deg = 45.0f;
  float aspect = 1.0f;
  float near_plane = 0.1f, far_plane = 100.0f;
  glm::mat4 projection() const;
  glm::vec3 eye() const;
};

// What draw_water() asks the application to draw into one of its textures
// (seed 001 §5.1-5.2). When the callback runs, the engine has bound the
// texture's framebuffer (GL_FRAMEBUFFER, both draw and read), set the
// viewport to (0, 0, size, size), cleared colour and depth, enabled depth
// testing (GL_LESS, depth writes on), disabled blending and face culling,
// enabled GL_CLIP_DISTANCE0 and set the front face (GL_CW when
// `mirrored`, else GL_CCW). Everything else is the caller's state as it
// was when it called draw_water(): its program, VAO, buffer
// bindings, textures and sampler objects on every unit, active texture
// unit, blend function, colour mask, scissor, stencil, multisampling and
// other capabilities. The callback draws its opaque scene with
// `view_proj`, writing gl_ClipDistance[0] = dot(clip_plane, vec4(world,
// 1)), and where `fog` is set attenuates each colour towards `water_color`
// by exp(-fog_k d), d the distance from `eye` (seed 001 eq. 10). It may
// change any state; the engine restores the caller's afterwards.
struct WaterPass {
  unsigned framebuffer = 0;  // bound when the callback runs; size x size pixels
  int size = 0;
  glm::mat4 view_proj{1.0f};
  glm::vec4 clip_plane{0.0f};
  bool mirrored = false;
  bool fog = false;
  glm::vec3 eye{0.0f};
  glm::vec3 fog_k{0.0f};
  glm::vec3 water_color{0.0f};
};

// The water seen from a camera: whether the camera is under it, the
// water's colour (radiance) and attenuation, for an application that fogs
// its own underwater view the way the surface does.
struct WaterMedium {
  bool camera_under = false;
  glm::vec3 color{0.0f};
  glm::vec3 k{0.0f};
};

}  // namespace caustix::runtime
