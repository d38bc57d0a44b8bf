// An application with its own renderer that adds caustix's light to its
// floor (docs/embedding.md, "A first integration"):
//   1. its own OpenGL 4.5 context (headless EGL here; a window's elsewhere),
//   2. caustix::runtime::Engine from the .cxb its build baked,
//   3. per frame: engine->update(), then for each light engine->bind() and
//      its own floor shader, which includes caustix.glsl and calls
//      caustix_irradiance(world position, normal).
// The test: the floor under flat water lit at 30 degrees reads
// E/E0 = T(30 deg) cos(30 deg) (docs/architecture.md, flat_pool) to 1 %.
// Exit status 0 when it does, 1 when it does not, 2 on any error.

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "caustix/runtime/engine.h"
#include "caustix/runtime/scene_loader.h"
#include "caustix/runtime/version.h"

namespace {

int fail(const std::string& what) {
  std::fprintf(stderr, "pool_floor: %s\n", what.c_str());
  return 2;
}

// Mesa's surfaceless platform (no X server), else the first EGL device (a GPU).
bool make_context() {
  EGLDisplay dpy = EGL_NO_DISPLAY;
  EGLint major = 0, minor = 0;
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
    dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (dpy != EGL_NO_DISPLAY && !eglInitialize(dpy, &major, &minor)) dpy = EGL_NO_DISPLAY;
  }
  if (dpy == EGL_NO_DISPLAY && epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device")) {
    EGLDeviceEXT device = nullptr;
    EGLint n = 0;
    if (eglQueryDevicesEXT(1, &device, &n) && n > 0) {
      dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
      if (dpy != EGL_NO_DISPLAY && !eglInitialize(dpy, &major, &minor)) dpy = EGL_NO_DISPLAY;
    }
  }
  if (dpy == EGL_NO_DISPLAY || !eglBindAPI(EGL_OPENGL_API)) return false;
  const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext ctx = eglCreateContext(dpy, nullptr, EGL_NO_CONTEXT, attribs);  // EGL_KHR_no_config_context
  return ctx != EGL_NO_CONTEXT && eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx);
}

GLuint compile(GLenum type, const std::string& src) {
  GLuint s = glCreateShader(type);
  const char* p = src.c_str();
  glShaderSource(s, 1, &p, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    std::fprintf(stderr, "pool_floor: shader: %s\n", log);
  }
  return s;
}

// The application's floor shader: its own vertex layout and camera, and
// caustix's light through the include.
const char* kVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_model;
uniform mat4 u_view_proj;
out vec3 v_world;
void main() {
  v_world = (u_model * vec4(a_position, 1.0)).xyz;
  gl_Position = u_view_proj * vec4(v_world, 1.0);
})";
const char* kFragmentMain = R"(
in vec3 v_world;
uniform vec3 u_albedo;
out vec4 o_color;
void main() {
  // E: W/m^2 from this light; a diffuse floor's radiance would be albedo E / pi.
  o_color = vec4(u_albedo * caustix_irradiance(v_world, vec3(0.0, 1.0, 0.0)), 1.0);
})";

// Unpolarised Fresnel transmittance from air into n2 (the physics, on the CPU).
double fresnel_t(double cos_i, double n2) {
  const double sin_t2 = (1 - cos_i * cos_i) / (n2 * n2);
  const double cos_t = std::sqrt(1 - sin_t2);
  const double rs = (cos_i - n2 * cos_t) / (cos_i + n2 * cos_t);
  const double rp = (n2 * cos_i - cos_t) / (n2 * cos_i + cos_t);
  return 1 - 0.5 * (rs * rs + rp * rp);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return fail("usage: pool_floor <scene.cxb>");
  if (!make_context()) return fail("no headless OpenGL 4.5 context");
  std::printf("pool_floor: caustix %s (headers %d.%d.%d), %s\n", caustix::version(), CAUSTIX_VERSION_MAJOR,
              CAUSTIX_VERSION_MINOR, CAUSTIX_VERSION_PATCH, reinterpret_cast<const char*>(glGetString(GL_RENDERER)));

  auto scene = caustix::runtime::load_scene_file(argv[1]);
  if (!scene) return fail(scene.error().message);
  auto created = caustix::runtime::Engine::create(*scene);
  if (!created) return fail(created.error().message);
  caustix::runtime::Engine& engine = **created;

  // The application's program, with caustix.glsl after its #version.
  const std::string fs = "#version 450 core\n" + engine.glsl_include() + kFragmentMain;
  GLuint program = glCreateProgram();
  glAttachShader(program, compile(GL_VERTEX_SHADER, kVertex));
  glAttachShader(program, compile(GL_FRAGMENT_SHADER, fs));
  glLinkProgram(program);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) return fail("the floor program does not link");

  // The application's own target: a top view of [-1.5, 1.5]^2 on the floor.
  const int n = 64;
  const float half = 1.5f;
  GLuint color = 0, fbo = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &color);
  glTextureStorage2D(color, 1, GL_RGBA32F, n, n);
  glCreateFramebuffers(1, &fbo);
  glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, color, 0);

  // One frame: the light side, then the application's pass per light.
  caustix::runtime::FrameUpdate frame;
  frame.time = 0.0f;
  frame.caustics = engine.default_options();
  if (auto st = engine.update(frame); !st) return fail(st.error().message);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, n, n);
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);  // lights add up (Tipprasert 2006 eq. 4-20)
  glUseProgram(program);
  // Orthographic, straight down: clip x = x / half, clip y = z / half.
  const float view_proj[16] = {1 / half, 0, 0, 0, 0, 0, -0.1f, 0, 0, 1 / half, 0, 0, 0, 0, 0, 1};
  glUniformMatrix4fv(glGetUniformLocation(program, "u_view_proj"), 1, GL_FALSE, view_proj);
  glUniform3f(glGetUniformLocation(program, "u_albedo"), 1.0f, 1.0f, 1.0f);
  const caustix::SceneDesc& desc = engine.scene();
  for (std::uint32_t li = 0; li < desc.lights.size(); ++li) {
    for (std::uint32_t oi = 0; oi < desc.objects.size(); ++oi) {
      glUniformMatrix4fv(glGetUniformLocation(program, "u_model"), 1, GL_FALSE, desc.objects[oi].transform.data());
      if (auto st = engine.bind(oi, li); !st) return fail(st.error().message);
      if (auto st = engine.draw_object(oi); !st) return fail(st.error().message);
    }
  }
  std::vector<float> px(std::size_t{n} * n * 4);
  glGetTextureImage(color, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  if (glGetError() != GL_NO_ERROR) return fail("a GL error in the application's pass");

  const double cos_i = std::cos(30.0 * 3.14159265358979 / 180.0);
  const double expected = fresnel_t(cos_i, desc.water->ior) * cos_i * desc.lights[0].irradiance;
  double worst = 0, sum = 0;
  for (std::size_t i = 0; i < px.size(); i += 4) {
    worst = std::max(worst, std::fabs(px[i] / expected - 1));
    sum += px[i];
  }
  std::printf("pool_floor: floor E/E0 mean %.5f, physics T(30) cos 30 = %.5f, worst pixel off by %.3f %%\n",
              sum / (px.size() / 4), expected, 100 * worst);
  return worst < 0.01 ? 0 : 1;
}
