// caustix-view: interactive viewer. Orbit camera (left drag: orbit, right
// drag: pan, wheel: zoom), Space pauses the waves, R resets the camera, Esc
// quits. Caustics: M cycles the method (levelmap, uniform, volumetric,
// none), +/- change the plane count, [ ] the acceptance epsilon, arrow keys
// move the first light (the level maps are re-derived on the GPU), W/S
// scale the waves, C toggles culling. Water surface (seed 001): T plain /
// textured surface, 1 refraction, 2 reflection, 3 water colour, 4 glow,
// F approximate / exact Fresnel, , and . fewer / more W/A steps. Display
// (docs/display.md): 9 / 0 exposure down / up half a stop, A auto exposure,
// O filmic / exponential tone curve, X supersampling 1x / 2x / 3x. Orbiting
// below the horizontal (or panning down) takes the camera under the water. The state and the frame time are in
// the title bar and printed once a second.
// --screenshot FILE --frames N renders N frames, saves the window and exits
// (used by the tests under Xvfb).

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "caustix/common/cli.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/runtime/image_output.h"
#include "caustix/runtime/renderer.h"
#include "caustix/runtime/scene_loader.h"

namespace {

using caustix::Camera;

// Spherical coordinates about a target; converts to and from a Camera.
struct Orbit {
  glm::vec3 target{0};
  float distance = 5, yaw = 0, pitch = 0.5f;

  static Orbit from(const Camera& c) {
    Orbit o;
    o.target = {c.target[0], c.target[1], c.target[2]};
    const glm::vec3 d = glm::vec3(c.position[0], c.position[1], c.position[2]) - o.target;
    o.distance = glm::length(d);
    o.yaw = std::atan2(d.x, d.z);
    o.pitch = std::asin(std::clamp(d.y / o.distance, -1.0f, 1.0f));
    return o;
  }
  Camera apply(Camera c) const {
    const glm::vec3 eye = target + distance * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                                                        std::cos(pitch) * std::cos(yaw));
    c.position = {eye.x, eye.y, eye.z};
    c.target = {target.x, target.y, target.z};
    c.up = {0, 1, 0};
    return c;
  }
};

struct ViewState {
  Orbit orbit, home;
  bool paused = false;
  double last_x = 0, last_y = 0;
  bool rotating = false, panning = false;
  caustix::runtime::CausticsOptions caustics;
  caustix::runtime::WaterLook look;
  float wave_scale = 1.0f;
  float light_azimuth = 0.0f, light_elevation = 0.0f;  // first light, degrees
  bool light_moved = false;
  caustix::runtime::DisplayOptions display;
  int supersample = 1;
};

}  // namespace

int main(int argc, char** argv) {
  using namespace caustix;
  using namespace caustix::runtime;
  std::string in_path, size = "1280x720", screenshot;
  int frames = 0;
  CLI::App app{"caustix-view: interactive viewer for a baked .cxb scene"};
  app.footer(
      "Controls: left drag orbit, right drag pan, wheel zoom, Space pause waves, R reset, Esc quit.\n"
      "Water: T plain/textured, 1 refraction, 2 reflection, 3 colour, 4 glow, F Fresnel, , . W/A steps.\n"
      "Display: 9 0 exposure -/+ 0.5 EV, A auto exposure, O filmic/exponential tone curve, X supersampling.\n"
      "Exit codes: 0 ok, 1 internal, 2 usage, 3 input unreadable, 4 invalid .cxb, 5 screenshot not\n"
      "            written, 6 no window or OpenGL 4.5 context (needs a display; try xvfb-run -a).");
  app.add_option("scene", in_path, "baked scene (.cxb)")->required();
  cli::add_size_option(app, "--size", size, "window size");
  app.add_option("--screenshot", screenshot, "save the window to this image after --frames frames, then exit");
  app.add_option("--frames", frames, "frames to render before the screenshot (with --screenshot)")
      ->check(CLI::Range(1, 100000))->capture_default_str();
  if (auto rc = cli::parse(app, "caustix-view", argc, argv)) return *rc;
  int width = 0, height = 0;
  cli::parse_size(size, width, height);
  if (!screenshot.empty() && frames == 0) frames = 1;
  auto fail = [](const Error& e) { return cli::fail("caustix-view", e); };

  auto scene = load_scene_file(in_path);
  if (!scene) return fail(scene.error());

  glfwSetErrorCallback([](int code, const char* msg) { std::cerr << "caustix-view: GLFW error " << code << ": " << msg << "\n"; });
  if (!glfwInit()) return fail(make_error(ErrorCode::kGraphics, "cannot initialise GLFW (no display? run under xvfb-run -a)"));
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(width, height, "caustix-view", nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    return fail(make_error(ErrorCode::kGraphics, "cannot open a window with an OpenGL 4.5 core context"));
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(screenshot.empty() ? 1 : 0);

  int rc = kExitOk;
  {
    auto renderer = Renderer::create(*scene);
    if (!renderer) {
      glfwDestroyWindow(window);
      glfwTerminate();
      return fail(renderer.error());
    }
    const std::string gl_name = current_renderer_description();
    ViewState state;
    state.caustics = default_caustics_options(scene->desc);
    state.orbit = state.home = Orbit::from((*renderer)->default_camera());
    glfwSetWindowUserPointer(window, &state);
    // The first light's direction as elevation above the horizon and azimuth.
    if (!(*renderer)->scene().lights.empty()) {
      const Light& l = (*renderer)->scene().lights[0];
      const glm::vec3 d = glm::normalize(glm::vec3(l.direction[0], l.direction[1], l.direction[2]));
      state.light_elevation = glm::degrees(std::asin(std::clamp(-d.y, -1.0f, 1.0f)));
      state.light_azimuth = glm::degrees(std::atan2(d.z, d.x));
    }
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
      auto* s = static_cast<ViewState*>(glfwGetWindowUserPointer(w));
      if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
      auto& c = s->caustics;
      switch (key) {
        case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
        case GLFW_KEY_SPACE: s->paused = !s->paused; break;
        case GLFW_KEY_R: s->orbit = s->home; break;
        case GLFW_KEY_M: c.method = static_cast<CausticsMethod>((static_cast<int>(c.method) + 1) % 5); break;
        case GLFW_KEY_T: s->look.textures = !s->look.textures; break;
        case GLFW_KEY_1: s->look.refraction = !s->look.refraction; break;
        case GLFW_KEY_2: s->look.reflection = !s->look.reflection; break;
        case GLFW_KEY_3: s->look.colour = !s->look.colour; break;
        case GLFW_KEY_4: s->look.glow = !s->look.glow; break;
        case GLFW_KEY_F:
          s->look.fresnel = s->look.fresnel == FresnelMode::kExact ? FresnelMode::kApprox : FresnelMode::kExact;
          break;
        case GLFW_KEY_COMMA: s->look.steps = std::max(1, s->look.steps - 1); break;
        case GLFW_KEY_PERIOD: s->look.steps = std::min(64, s->look.steps + 1); break;
        case GLFW_KEY_EQUAL:
        case GLFW_KEY_KP_ADD: c.planes = std::min(4096u, c.planes.value_or(32) + 4); break;
        case GLFW_KEY_MINUS:
        case GLFW_KEY_KP_SUBTRACT: c.planes = std::max(1u, c.planes.value_or(32) > 4 ? c.planes.value_or(32) - 4 : 1); break;
        case GLFW_KEY_LEFT_BRACKET: c.epsilon = c.epsilon.value_or(0.02f) / 1.25f; break;
        case GLFW_KEY_RIGHT_BRACKET: c.epsilon = c.epsilon.value_or(0.02f) * 1.25f; break;
        case GLFW_KEY_C: c.cull = !c.cull; break;
        case GLFW_KEY_W: s->wave_scale *= 1.25f; break;
        case GLFW_KEY_S: s->wave_scale /= 1.25f; break;
        case GLFW_KEY_LEFT: s->light_azimuth -= 5.0f; s->light_moved = true; break;
        case GLFW_KEY_RIGHT: s->light_azimuth += 5.0f; s->light_moved = true; break;
        case GLFW_KEY_9: s->display.exposure_ev = std::max(-16.0f, s->display.exposure_ev - 0.5f); break;
        case GLFW_KEY_0: s->display.exposure_ev = std::min(16.0f, s->display.exposure_ev + 0.5f); break;
        case GLFW_KEY_X: s->supersample = s->supersample % 3 + 1; break;
        case GLFW_KEY_A: s->display.auto_exposure = !s->display.auto_exposure; break;
        case GLFW_KEY_O:
          s->display.tone_map = s->display.tone_map == ToneMap::kFilmic ? ToneMap::kExponential : ToneMap::kFilmic;
          break;
        case GLFW_KEY_UP: s->light_elevation = std::min(90.0f, s->light_elevation + 2.0f); s->light_moved = true; break;
        case GLFW_KEY_DOWN: s->light_elevation = std::max(1.0f, s->light_elevation - 2.0f); s->light_moved = true; break;
        default: break;
      }
    });
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
      auto* s = static_cast<ViewState*>(glfwGetWindowUserPointer(w));
      glfwGetCursorPos(w, &s->last_x, &s->last_y);
      if (button == GLFW_MOUSE_BUTTON_LEFT) s->rotating = action == GLFW_PRESS;
      if (button == GLFW_MOUSE_BUTTON_RIGHT) s->panning = action == GLFW_PRESS;
    });
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
      auto* s = static_cast<ViewState*>(glfwGetWindowUserPointer(w));
      const auto dx = static_cast<float>(x - s->last_x), dy = static_cast<float>(y - s->last_y);
      s->last_x = x;
      s->last_y = y;
      if (s->rotating) {
        s->orbit.yaw -= 0.005f * dx;
        s->orbit.pitch = std::clamp(s->orbit.pitch + 0.005f * dy, -1.55f, 1.55f);
      } else if (s->panning) {
        const glm::vec3 right(std::cos(s->orbit.yaw), 0, -std::sin(s->orbit.yaw));
        s->orbit.target += s->orbit.distance * 0.0015f * (-dx * right + dy * glm::vec3(0, 1, 0));
      }
    });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
      auto* s = static_cast<ViewState*>(glfwGetWindowUserPointer(w));
      s->orbit.distance = std::max(1e-3f, s->orbit.distance * std::pow(0.9f, static_cast<float>(dy)));
    });

    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto last_report = start;
    double anim_time = 0, frame_ms_sum = 0, rederive_ms = 0;
    int frame_count = 0, rendered = 0;
    Camera base = (*renderer)->default_camera();
    while (!glfwWindowShouldClose(window)) {
      const auto t0 = Clock::now();
      glfwPollEvents();
      int fw = 0, fh = 0;
      glfwGetFramebufferSize(window, &fw, &fh);
      if (fw <= 0 || fh <= 0) continue;
      if (state.light_moved && !(*renderer)->scene().lights.empty()) {
        state.light_moved = false;
        Light l = (*renderer)->scene().lights[0];
        const float el = glm::radians(state.light_elevation), az = glm::radians(state.light_azimuth);
        if (l.type == LightType::kDirectional) {
          l.direction = {std::cos(el) * std::cos(az), -std::sin(el), std::cos(el) * std::sin(az)};
        }
        const auto r0 = Clock::now();
        if (Status st = (*renderer)->set_light(0, l); !st) {
          rc = fail(st.error());
          break;
        }
        (*renderer)->finish();
        rederive_ms = std::chrono::duration<double, std::milli>(Clock::now() - r0).count();
      }
      (*renderer)->set_wave_scale(state.wave_scale);
      FrameParams frame;
      frame.camera = state.orbit.apply(base);
      frame.time = static_cast<float>(anim_time);
      frame.width = fw;
      frame.height = fh;
      frame.caustics = state.caustics;
      frame.water = state.look;
      frame.display = state.display;
      frame.supersample = state.supersample;
      if (Status st = (*renderer)->render(frame); !st) {
        rc = fail(st.error());
        break;
      }
      (*renderer)->present(0, fw, fh);
      ++rendered;
      if (!screenshot.empty() && rendered >= frames) {
        std::vector<std::uint8_t> px(static_cast<std::size_t>(fw) * static_cast<std::size_t>(fh) * 3);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadBuffer(GL_BACK);
        glReadPixels(0, 0, fw, fh, GL_RGB, GL_UNSIGNED_BYTE, px.data());
        std::vector<std::uint8_t> flipped(px.size());
        const std::size_t row = static_cast<std::size_t>(fw) * 3;
        for (int y = 0; y < fh; ++y) {
          std::copy_n(px.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(fh - 1 - y) * row), row,
                      flipped.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row));
        }
        if (Status st = write_u8_image(screenshot, fw, fh, 3, flipped); !st) rc = fail(st.error());
        else std::printf("caustix-view: saved %s (%dx%d) after %d frames\n", screenshot.c_str(), fw, fh, rendered);
        break;
      }
      glfwSwapBuffers(window);
      const auto t1 = Clock::now();
      const double dt = std::chrono::duration<double>(t1 - t0).count();
      if (!state.paused) anim_time += dt;
      frame_ms_sum += dt * 1e3;
      ++frame_count;
      if (t1 - last_report > std::chrono::seconds(1)) {
        char title[512];
        const auto& c = state.caustics;
        char planes[16] = "baked", eps[16] = "baked";
        if (c.planes) std::snprintf(planes, sizeof planes, "%u", *c.planes);
        if (c.epsilon) std::snprintf(eps, sizeof eps, "%.4g m", *c.epsilon);
        const WaterLook& wl = state.look;
        char water[96] = "plain";
        if (wl.textures) {
          std::snprintf(water, sizeof water, "%s%s%s%s %s Fresnel, %d steps", wl.refraction ? "R" : "-",
                        wl.reflection ? "M" : "-", wl.colour ? "C" : "-", wl.glow ? "G" : "-",
                        wl.fresnel == FresnelMode::kExact ? "exact" : "approx.", wl.steps);
        }
        std::snprintf(title, sizeof title,
                      "caustix-view  %.2f ms/frame  | %s%s, planes %s, eps %s | light el %.0f az %.0f (re-derived in %.1f ms) | "
                      "waves x%.2f | water %s | %s %+.1f EV%s, %dx AA | %s",
                      frame_ms_sum / frame_count, to_string(c.method), c.cull ? "" : " (no culling)", planes, eps,
                      state.light_elevation, state.light_azimuth, rederive_ms, state.wave_scale, water,
                      to_string(state.display.tone_map), state.display.exposure_ev, state.display.auto_exposure ? " auto" : "",
                      state.supersample, gl_name.c_str());
        glfwSetWindowTitle(window, title);
        std::printf("%s\n", title + 14);
        std::fflush(stdout);
        frame_ms_sum = 0;
        frame_count = 0;
        last_report = t1;
      }
    }
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  return rc;
}
