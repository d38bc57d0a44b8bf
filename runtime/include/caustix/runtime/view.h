#pragma once
// The view side of caustix::runtime::Engine (declared in engine.h): what
// draw_water(), draw_glass() and draw_media() read of the caller's scene,
// what each draws and writes, and their inputs below -- the caller's
// camera, what draw_water() asks the caller to draw into its textures, and
// the water as a camera sees it. Each draw is optional.
//
// Scene textures. Engine::draw_water(), draw_glass() and draw_media() read the
// caller's scene as its framebuffer has it, 2D or 2D multisample (GL 4.5
// textures, not renderbuffers):
//  - colour in any floating-point or normalised format: GL_RGBA16F,
//    GL_R11F_G11F_B10F, GL_RGBA8, GL_SRGB8_ALPHA8, GL_RGB10_A2,
//    GL_RGBA32F and the like (not integer formats);
//  - depth in any depth or depth-stencil format: GL_DEPTH_COMPONENT16,
//    _24, _32, _32F, GL_DEPTH24_STENCIL8, GL_DEPTH32F_STENCIL8, read as
//    depth (GL_DEPTH_STENCIL_TEXTURE_MODE left at GL_DEPTH_COMPONENT).
// They are sampled texel by texel through the engine's own sampler
// objects, whatever the textures' filtering or comparison modes. A
// multisampled texture is resolved into a copy the engine holds (colour
// averaged over the samples, depth the nearest sample; in
// stats().memory.views) before it is read; the engine then draws into
// the caller's multisampled framebuffer as into any other. Colour is
// written linear; into a framebuffer object whose draw buffer is
// sRGB-encoded it is written with GL_FRAMEBUFFER_SRGB on, so that it is
// stored encoded as it is decoded when read. Any other texture is kUsage
// naming the format it has and those accepted.
//
// Engine::draw_water(view, look, draw_scene, scene_depth): the water
// surface (Mihalik 2008) into the framebuffer bound to
// GL_DRAW_FRAMEBUFFER with the current viewport, depth-tested against
// its depth buffer (without writing it). `draw_scene` renders the
// reflection texture, then the refraction texture (see WaterPass: the
// two share one depth buffer, sized by look.texture_size or, automatic,
// a texel per pixel up to look.max_texture_size); with
// look.textures false, or no callback, the plain surface (sky
// reflection, Fresnel) is drawn instead. With look.glow the glow of §9.3
// is added to the bound framebuffer's colour; given `scene_depth` (a
// depth texture, see "Scene textures" above, holding the depth the
// surface is tested against, in the framebuffer's pixels: typically its
// depth attachment, read at the viewport's pixels while the glow's own
// target is bound) it comes only from glints the scene does not hide,
// else also from glints behind objects. Dispersive water refracts the view once per
// wavelength the last update() traced (CausticsOptions::wavelengths, or
// wavelength_nm's alone), each at the water's index there, adding the
// results with the bins' RGB weights (the plain surface: n_d). kUsage
// without water in the scene or with a bad look.
//
// Engine::water_medium(view, look): the water as that camera sees it
// (WaterMedium below).
//
// Engine::draw_glass(view, scene_color, scene_depth, sky, options): the
// transparent objects as glass into the bound framebuffer: what is
// seen through them by `options.method` (GlassView: view rays through the
// light-transport table, Iwasaki et al. §3, or nearby-geometry refraction, seed
// 003), with the Fresnel reflection of the sky. `scene_color` and
// `scene_depth` (see "Scene textures" above) are the opaque scene as the
// caller rendered it with `view`, the size of the viewport; they may be
// attached to the bound framebuffer (the glass is drawn into a target
// over its rectangle of the frame, reading them, and then copied in).
// Dispersive glass seen through the nearby view refracts once
// per wavelength the last update() traced, as draw_water(); the table
// view refracts at n_d. Thin-walled glass (Role::kThin) is
// drawn in either view as sheets seen straight through (what is behind
// them times each sheet's transmittance and tint, plus the sky it
// reflects), after the solid glass, without writing depth. Rays that
// leave the scene (and reflections) see `options.environment`, the
// caller's cube map of its sky, where given, else the flat `sky`. Writes
// colour and depth (solid glass's depth only). No-op without transparent
// objects; kUsage for options out of range (naming the knob) and for an
// environment that is not a cube-map texture.
//
// Engine::draw_media(view_proj, scene_color, scene_depth, scale): single
// scattering in the media (Pfeuti "Viewing Pass"), seen through
// `view_proj` (any camera: perspective or orthographic; GL clip
// conventions), into the framebuffer bound to GL_DRAW_FRAMEBUFFER over
// the current viewport. Every pixel's ray is marched through the
// radiance grid of the last update(), bent inside transparent objects,
// and stops where it passes behind `scene_depth` (a depth texture of the
// viewport's size, see "Scene textures" above: the opaque scene as the
// caller rendered it, without the glass). With `scene_color` (a colour
// texture, same size) each pixel becomes colour x T + scale x L, T
// the extinction e^(-sum sigma_t ds) of the fog box and the glass along
// the ray (the glass's Fresnel is draw_glass()'s; the
// water's own attenuation is the water surface's, draw_water()); with 0
// it adds scale x L (additive blending) to what is bound, for images of
// the in-scatter alone. L is radiance in the lights' units (E0 or I
// times their colour). Both may be attached to the bound framebuffer:
// a colour it draws into alone is composited over by blending (dual
// source), another is copied; so is an attached depth texture. Textures
// not attached are read in place. Writes colour only. No-op without
// media.

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
// (Mihalik 2008 §5.1-5.2). When the callback runs, the engine has bound the
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
// by exp(-fog_k d), d the distance from `eye` (Mihalik 2008 eq. 10). It may
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
