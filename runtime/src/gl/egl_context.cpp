#include "caustix/runtime/gl_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <vector>

namespace caustix::runtime {
namespace {

Error gfx_error(const std::string& msg) {
  return make_error(ErrorCode::kGraphics, msg + " (EGL error 0x" + [] {
                      char b[16];
                      std::snprintf(b, sizeof b, "%04X", static_cast<unsigned>(eglGetError()));
                      return std::string(b);
                    }() + ")");
}

// libepoxy: use eglGetPlatformDisplayEXT; the core eglGetPlatformDisplay
// aborts ("No provider") before a display exists.
EGLDisplay open_display() {
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint maj = 0, min = 0;
    if (d != EGL_NO_DISPLAY && eglInitialize(d, &maj, &min)) return d;
  }
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device")) {
    EGLint n = 0;
    EGLDeviceEXT devices[16];
    if (eglQueryDevicesEXT(16, devices, &n)) {
      for (EGLint i = 0; i < n; ++i) {
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        EGLint maj = 0, min = 0;
        if (d != EGL_NO_DISPLAY && eglInitialize(d, &maj, &min)) return d;
      }
    }
  }
  return EGL_NO_DISPLAY;
}

}  // namespace

std::string current_renderer_description() {
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return std::string(renderer ? renderer : "?") + ", OpenGL " + (version ? version : "?");
}

Result<std::unique_ptr<HeadlessContext>> HeadlessContext::create(int major, int minor) {
  std::unique_ptr<HeadlessContext> ctx(new HeadlessContext());
  EGLDisplay dpy = open_display();
  if (dpy == EGL_NO_DISPLAY) {
    return gfx_error("no EGL display: neither Mesa's surfaceless platform nor an EGL device is available");
  }
  ctx->display_ = dpy;
  if (!eglBindAPI(EGL_OPENGL_API)) return gfx_error("eglBindAPI(EGL_OPENGL_API) failed");

  const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                   EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint num = 0;
  if (!eglChooseConfig(dpy, config_attribs, &config, 1, &num) || num == 0) {
    config = nullptr;  // EGL_KHR_no_config_context: surfaceless contexts need none
    if (!epoxy_has_egl_extension(dpy, "EGL_KHR_no_config_context")) {
      return gfx_error("no EGL config for desktop OpenGL");
    }
  }
  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, major, EGL_CONTEXT_MINOR_VERSION, minor,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                    EGL_NONE};
  EGLContext c = eglCreateContext(dpy, config, EGL_NO_CONTEXT, context_attribs);
  if (c == EGL_NO_CONTEXT) {
    return gfx_error("cannot create an OpenGL " + std::to_string(major) + "." + std::to_string(minor) +
                     " core context");
  }
  ctx->context_ = c;
  if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c)) {
    return gfx_error("eglMakeCurrent without a surface failed (EGL_KHR_surfaceless_context missing?)");
  }
  return ctx;
}

HeadlessContext::~HeadlessContext() {
  if (display_) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_) eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
}

std::string HeadlessContext::description() const { return current_renderer_description(); }

}  // namespace caustix::runtime
