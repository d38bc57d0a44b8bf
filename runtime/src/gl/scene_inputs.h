#pragma once
// The caller's scene colour and depth as the view-side draws (draw_water's
// glow, draw_glass, draw_media) read them: whatever formats an engine's
// framebuffer has -- colour in any floating-point or normalised format
// (RGBA16F, R11G11B10F, RGBA8 and its sRGB form, RGB10_A2, RGBA32F, ...),
// depth in any depth or depth-stencil format (D16, D24, D32, D32F, D24S8,
// D32FS8), 2D or 2D multisample -- and the checks that tell when a pass
// must read a copy instead of the texture itself.
// Internal to the runtime.

#include <epoxy/gl.h>

#include <cstdint>
#include <string>

#include "caustix/common/status.h"
#include "gl_objects.h"

namespace caustix::runtime::gl {

// What a draw knows of one of the caller's scene textures.
struct SceneTexture {
  GLuint name = 0;  // 0: none given
  GLenum target = GL_TEXTURE_2D;  // or GL_TEXTURE_2D_MULTISAMPLE
  GLenum format = GL_NONE;        // internal format of level 0
  int width = 0, height = 0;
  bool multisampled() const { return target == GL_TEXTURE_2D_MULTISAMPLE; }
  explicit operator bool() const { return name != 0; }
};

enum class SceneTextureKind { kColor, kDepth };

// Checks `texture` for `call` (the Engine call's name, for the message):
// a GL texture, 2D or 2D multisample, with storage at level 0; a colour
// texture's format is not an integer, depth or stencil format; a depth
// texture's has depth bits and, when it also has stencil, is read as depth
// (GL_DEPTH_STENCIL_TEXTURE_MODE GL_DEPTH_COMPONENT, the default). kUsage
// naming the texture, what it is and what is accepted otherwise.
Result<SceneTexture> describe_scene_texture(const char* call, GLuint texture, SceneTextureKind kind, const char* what);

// The GL name of an internal format ("GL_RGBA16F"), or its number in hex.
std::string format_name(GLenum format);

// Reads the caller's scene textures for the passes that sample them.
// Programs are built on first use; the copies are kept between calls and
// remade when the size changes.
class SceneReader {
 public:
  SceneReader();
  ~SceneReader();
  SceneReader(const SceneReader&) = delete;
  SceneReader& operator=(const SceneReader&) = delete;

  // Makes single-sampled 2D textures that a pass can sample with sampler2D
  // at the caller's pixels: the caller's own texture where it is
  // single-sampled and not `copy_*`, else a copy made by a full-screen pass
  // (colour GL_RGBA32F, depth GL_DEPTH_COMPONENT32F; a multisampled colour
  // is averaged over its samples, a multisampled depth takes the nearest of
  // its samples). Either texture may be empty. Binds its own framebuffer,
  // program, VAO, units 0-3 and their samplers, and sets the depth test and
  // mask; the caller's StateGuard restores them.
  Status read(const SceneTexture& color, const SceneTexture& depth, bool copy_color, bool copy_depth);
  GLuint color() const { return color_; }
  GLuint depth() const { return depth_; }

  // Draws the rectangle from (x0, y0) of `color` and `depth` (either may be
  // empty; any accepted format, multisampled or not, resolved as read()
  // does) into the bound draw framebuffer's [0, w) x [0, h): the colour to
  // its first draw buffer, the depth to its depth attachment (through
  // gl_FragDepth: the depth test is set to GL_ALWAYS with writes on; with
  // no depth given, off). Sets the viewport, program, VAO and units 0-3.
  Status copy_region(const SceneTexture& color, const SceneTexture& depth, int x0, int y0, int w, int h);

  // GPU bytes of the copies it holds.
  std::uint64_t gpu_bytes() const;

 private:
  struct Impl;
  Impl* impl_;
  GLuint color_ = 0, depth_ = 0;
};

// Whether `texture` is attached to the framebuffer bound for drawing (a
// pass that samples it while drawing there needs a copy of it).
bool attached_to_draw_framebuffer(GLuint texture);

// Whether the bound draw framebuffer draws into `texture` alone: one draw
// buffer, with `texture` attached to it (what dual-source blending can
// composite over in place).
bool draws_only_into(GLuint texture);

// Turns GL_FRAMEBUFFER_SRGB on when the bound draw framebuffer is a
// framebuffer object whose first draw buffer is sRGB-encoded (an
// GL_SRGB8_ALPHA8 attachment), so that the linear colour the passes write
// is stored encoded, as the same texture is decoded when read (the
// StateGuard switches it off for the call and restores the caller's).
// The default framebuffer is written as before: unencoded.
void encode_srgb_if_the_target_is_srgb();

}  // namespace caustix::runtime::gl
