// caustix-view: interactive viewer. A Dear ImGui panel (Tab hides it) holds
// every runtime knob: caustics method and its planes, epsilon, map sizes
// and culling; glass method, planes, texture size, smoothing and view;
// caustic maps; shadows; media; the water's look; the first light's
// direction, colour and irradiance; the display transform; the interactive
// water (docs/water-simulation.md) and the per-stage GPU times as a graph
// with the caustics counters, and a screenshot button.
// Mouse: left drag orbit, right drag pan, wheel zoom; with the interactive
// water on, Ctrl + click drops a ripple and Shift + drag moves the object
// chosen in the panel (Shift + wheel: up and down), pushing the water.
// Keys (as before the panel): Space pauses the waves, R resets the camera,
// Esc quits. Caustics: M cycles the method, +/- the plane count, [ ] the
// acceptance epsilon, arrow keys move the first light, W/S scale the
// waves, C toggles culling. Water surface (Mihalik 2008): T plain / textured,
// 1 refraction, 2 reflection, 3 water colour, 4 glow, F approximate /
// exact Fresnel, , and . fewer / more W/A steps. Display (docs/display.md):
// 9 / 0 exposure down / up half a stop, A auto exposure, O filmic /
// exponential tone curve, X supersampling 1x / 2x / 3x. I toggles the
// interactive water. Orbiting below the horizontal (or panning down) takes
// the camera under the water. The state and the frame time are in the
// title bar and printed once a second.
// --screenshot FILE --frames N renders N frames, saves the window (panel
// included unless --no-ui) and exits (used by the tests under Xvfb).

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>
#include <glm/gtc/matrix_transform.hpp>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <deque>
#include <optional>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "caustix/common/cli.h"
#include "open_scene.h"
#include "caustix/formats/spectrum.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/sample/image_output.h"
#include "caustix/sample/renderer.h"
#include "caustix/runtime/scene_loader.h"
#include "caustix/runtime/water_sim.h"

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
  bool flat_sky = false;  // the analytic sky unless asked
  double last_x = 0, last_y = 0;
  bool rotating = false, panning = false;
  caustix::runtime::CausticsOptions caustics;
  caustix::runtime::WaterLook look;
  float wave_scale = 1.0f;
  float light_azimuth = 0.0f, light_elevation = 0.0f;  // first light, degrees
  std::array<float, 3> light_color{1, 1, 1};
  float light_power = 1.0f;  // E0 (directional) or I (point)
  bool light_moved = false;
  caustix::runtime::GlassViewOptions glass_view;
  caustix::sample::DisplayOptions display;
  int supersample = 1;
  bool ui = true;
  // Interactive water.
  bool simulate = false, sim_reset = false;
  caustix::runtime::WaterSimOptions sim;
  float ripple_radius = 0.15f, ripple_amplitude = 0.02f;
  std::vector<glm::vec2> ripples;  // clicked, not yet dropped
  int selected = -1;               // the object Shift + drag moves
  float selected_y = 0.0f;         // its height: the drag plane
  float water_level = 0.0f;
  bool dragging = false;
  std::optional<glm::vec3> drag_from;
  glm::vec3 drag_delta{0.0f};      // accumulated, applied once per frame
  // The camera of the last frame, for picking.
  glm::mat4 view_proj{1.0f};
  int win_width = 1, win_height = 1;
};

// The world ray under the cursor (window coordinates).
std::pair<glm::vec3, glm::vec3> cursor_ray(const ViewState& s, double x, double y) {
  const float nx = 2.0f * static_cast<float>(x) / static_cast<float>(s.win_width) - 1.0f;
  const float ny = 1.0f - 2.0f * static_cast<float>(y) / static_cast<float>(s.win_height);
  const glm::mat4 inv = glm::inverse(s.view_proj);
  glm::vec4 a = inv * glm::vec4(nx, ny, -1.0f, 1.0f), b = inv * glm::vec4(nx, ny, 1.0f, 1.0f);
  const glm::vec3 p = glm::vec3(a) / a.w, q = glm::vec3(b) / b.w;
  return {p, glm::normalize(q - p)};
}

// Where the ray meets the horizontal plane y = level, if in front.
std::optional<glm::vec3> on_plane(const std::pair<glm::vec3, glm::vec3>& ray, float level) {
  if (std::abs(ray.second.y) < 1e-6f) return std::nullopt;
  const float t = (level - ray.first.y) / ray.second.y;
  if (t <= 0.0f) return std::nullopt;
  return ray.first + t * ray.second;
}

// Panel history of the per-stage GPU times.
struct TimeHistory {
  static constexpr std::size_t kFrames = 240;
  std::array<std::deque<float>, caustix::sample::PassTimes::kCount + 1> series;  // + total
  void add(const caustix::sample::PassTimes& t) {
    for (int k = 0; k <= caustix::sample::PassTimes::kCount; ++k) {
      auto& d = series[static_cast<std::size_t>(k)];
      d.push_back(k < caustix::sample::PassTimes::kCount ? t.ms[k] : t.total_ms());
      if (d.size() > kFrames) d.pop_front();
    }
  }
};

template <typename T>
bool combo(const char* label, T& value, std::initializer_list<std::pair<T, const char*>> items) {
  const char* current = "?";
  for (const auto& [v, name] : items) {
    if (v == value) current = name;
  }
  bool changed = false;
  if (ImGui::BeginCombo(label, current)) {
    for (const auto& [v, name] : items) {
      if (ImGui::Selectable(name, v == value)) {
        value = v;
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

bool slider_u32(const char* label, std::uint32_t& v, int lo, int hi, ImGuiSliderFlags flags = 0) {
  int i = static_cast<int>(v);
  const bool changed = ImGui::SliderInt(label, &i, lo, hi, "%d", flags);
  if (changed) v = static_cast<std::uint32_t>(std::clamp(i, lo, hi));
  return changed;
}

bool pow2_combo(const char* label, std::uint32_t& v, std::uint32_t lo, std::uint32_t hi) {
  bool changed = false;
  const std::string current = std::to_string(v);
  if (ImGui::BeginCombo(label, current.c_str())) {
    for (std::uint32_t s = lo; s <= hi; s *= 2) {
      if (ImGui::Selectable(std::to_string(s).c_str(), s == v)) {
        v = s;
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

// The panel: every knob of ViewState, the times and counters. Returns true
// when the screenshot button was pressed.
bool draw_panel(ViewState& st, caustix::sample::Renderer& r, const TimeHistory& history, const std::string& gl_name,
                double frame_ms, const std::string& note) {
  using namespace caustix;
  using namespace caustix::runtime;
  using namespace caustix::sample;
  bool screenshot = false;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(390, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("caustix");
  ImGui::Text("%.2f ms/frame (CPU wall), %s", frame_ms, gl_name.c_str());
  if (ImGui::Button("Screenshot")) screenshot = true;
  ImGui::SameLine();
  if (ImGui::Button("Reset camera")) st.orbit = st.home;
  ImGui::SameLine();
  ImGui::Checkbox("Pause", &st.paused);
  if (!note.empty()) ImGui::TextWrapped("%s", note.c_str());

  if (ImGui::CollapsingHeader("GPU time per stage", ImGuiTreeNodeFlags_DefaultOpen)) {
    for (int k = 0; k <= PassTimes::kCount; ++k) {
      const auto& d = history.series[static_cast<std::size_t>(k)];
      const std::vector<float> values(d.begin(), d.end());
      const float last = values.empty() ? 0.0f : values.back();
      const char* name = k < PassTimes::kCount ? PassTimes::name(k) : "total";
      char overlay[64];
      std::snprintf(overlay, sizeof overlay, "%s %.2f ms", name, last);
      const float top = values.empty() ? 1.0f : std::max(1e-3f, *std::max_element(values.begin(), values.end()));
      ImGui::PlotLines(("##t" + std::to_string(k)).c_str(), values.data(), static_cast<int>(values.size()), 0, overlay, 0.0f,
                       top * 1.1f, ImVec2(0.0f, k < PassTimes::kCount ? 28.0f : 48.0f));
    }
    const CausticsStats cs = r.caustics_stats();
    for (const std::string& w : cs.warnings) std::fprintf(stderr, "caustix-view: warning: %s\n", w.c_str());
    auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
    ImGui::Text("water triangles %llu, volumes %llu of %llu, planes %llu%s", u(cs.water_triangles), u(cs.volumes_drawn),
                u(cs.volumes_total), u(cs.planes_drawn), cs.overflowed ? ", OVERFLOW (the list grows)" : "");
    if (cs.gl.counted) {
      ImGui::Text("engine GL calls %llu: %llu draws, %llu dispatches, %llu syncs, %llu B uploaded", u(cs.gl.calls), u(cs.gl.draws),
                  u(cs.gl.dispatches), u(cs.gl.syncs), u(cs.gl.upload_bytes));
    } else {
      ImGui::TextUnformatted("engine GL calls: not counted (build with -DCAUSTIX_COUNT_GL_CALLS=ON)");
    }
    const FrameWork& w = cs.work;
    auto work = [](const EffectWork& e) { return std::to_string(e.updated) + "/" + std::to_string(e.reused) + "/" + std::to_string(e.deferred); };
    ImGui::TextWrapped("remade/reused/deferred: shadows %s, level maps %s, glass %s, caustic maps %s, media %s%s",
                       work(w.shadow_maps).c_str(), work(w.level_maps).c_str(), work(w.glass).c_str(), work(w.caustic_maps).c_str(),
                       work(w.media).c_str(), w.water ? "; the water moved" : "");
    const GpuMemory& m = cs.memory;
    auto mb = [](std::uint64_t b) { return static_cast<double>(b) / 1e6; };
    ImGui::TextWrapped("engine GPU memory %.1f MB: level maps %.1f, shadows %.1f, glass %.1f, caustic maps %.1f, media %.1f, "
                       "water %.1f, views %.1f, meshes %.1f", mb(m.total()), mb(m.level_maps), mb(m.shadow_maps), mb(m.glass),
                       mb(m.caustic_maps), mb(m.media), mb(m.water), mb(m.views), mb(m.meshes));
    const CausticsTexels& tx = cs.texels;
    ImGui::TextWrapped("caustics maps %u (%.1f MB), finest texel %.2f mm, coarsened %.2fx by the budget, at least %u texels a side, "
                       "%u unreachable; light side %.1f of %.1f MB%s", tx.maps, mb(tx.map_bytes), tx.texel * 1e3, tx.coarsened,
                       tx.least_side, tx.unreachable,
                       mb(tx.light_side), mb(tx.budget), tx.over_budget ? " (OVER)" : "");
  }
  if (ImGui::CollapsingHeader("GPU time per engine pass")) {
    r.engine().set_gpu_timing(true, true);
    const GpuTimes t = r.engine().gpu_times();
    ImGui::Text("frame %llu: compute %.2f ms, raster %.2f ms", static_cast<unsigned long long>(t.frame), t.compute_ms, t.raster_ms);
    auto k = [](std::uint64_t v) { return static_cast<double>(v) / 1e3; };
    for (const GpuPassTime& p : t.passes) {
      if (!t.statistics) {
        ImGui::Text("%7.2f ms  %s  %s (x%u)", p.ms, p.compute ? "compute" : "raster ", p.name.c_str(), p.count);
      } else if (p.compute) {
        ImGui::Text("%7.2f ms  compute  %s (x%u): %.0fk invocations", p.ms, p.name.c_str(), p.count, k(p.compute_invocations));
      } else {
        ImGui::Text("%7.2f ms  raster   %s (x%u): %.0fk primitives, %.0fk vertex, %.0fk fragment invocations", p.ms, p.name.c_str(), p.count,
                    k(p.primitives), k(p.vertex_invocations), k(p.fragment_invocations));
      }
    }
  } else {
    r.engine().set_gpu_timing(false);
  }
  CausticsOptions& c = st.caustics;
  if (ImGui::CollapsingHeader("Caustics", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (ImGui::Button("Preset: as baked")) c = default_caustics_options(r.scene());
    ImGui::SameLine();
    if (ImGui::Button("Built-in defaults")) c = CausticsOptions{};
    combo("method", c.method, {{CausticsMethod::kLevelMap, "levelmap (smart slicing)"}, {CausticsMethod::kUniform, "uniform"},
                               {CausticsMethod::kVolumetric, "volumetric"}, {CausticsMethod::kSplat, "splat"},
                               {CausticsMethod::kNone, "none"}});
    bool baked_planes = !c.planes.has_value();
    if (ImGui::Checkbox("planes as baked", &baked_planes)) c.planes = baked_planes ? std::nullopt : std::optional<std::uint32_t>(32);
    if (c.planes) slider_u32("planes", *c.planes, 1, 256, ImGuiSliderFlags_Logarithmic);
    bool baked_eps = !c.epsilon.has_value();
    if (ImGui::Checkbox("epsilon as baked", &baked_eps)) c.epsilon = baked_eps ? std::nullopt : std::optional<float>(0.02f);
    if (c.epsilon) ImGui::SliderFloat("epsilon (m)", &*c.epsilon, 1e-4f, 0.5f, "%.4f", ImGuiSliderFlags_Logarithmic);
    pow2_combo("caustics map", c.map_size, 64, 4096);
    ImGui::SliderFloat("texel (m; 0: from the map)", &c.texel_size, 0.0f, 0.1f, "%.4f", ImGuiSliderFlags_Logarithmic);
    int budget_mib = static_cast<int>(c.memory_budget >> 20);
    if (ImGui::SliderInt("memory budget (MiB; 0: none)", &budget_mib, 0, 2048, "%d", ImGuiSliderFlags_Logarithmic)) {
      c.memory_budget = static_cast<std::uint64_t>(std::max(budget_mib, 0)) << 20;
    }
    ImGui::Checkbox("cull illumination volumes", &c.cull);
    ImGui::Checkbox("smooth water caustics", &c.water_smooth);
    slider_u32("photons (splat)", c.photons, 16, 4096, ImGuiSliderFlags_Logarithmic);
    slider_u32("wavelengths (dispersion)", c.wavelengths, 1, kMaxWavelengths);
    bool mono = c.wavelength_nm.has_value();
    if (ImGui::Checkbox("monochromatic", &mono)) c.wavelength_nm = mono ? std::optional<float>(kWavelengthD) : std::nullopt;
    if (c.wavelength_nm) ImGui::SliderFloat("wavelength (nm)", &*c.wavelength_nm, kMinWavelength, kMaxWavelength, "%.0f");
  }
  if (ImGui::CollapsingHeader("Glass and mirrors")) {
    combo("light through glass", c.glass_method, {{GlassMethod::kTable, "light-transport table"}, {GlassMethod::kCausticMap, "caustic map"}});
    slider_u32("glass planes", c.glass_planes, 1, 16);
    pow2_combo("illumination texture", c.glass_map_size, 64, 4096);
    ImGui::Checkbox("smooth glass caustics", &c.glass_smooth);
    ImGui::Checkbox("focus windows", &c.glass_focus);
    ImGui::Checkbox("focus windows by the tent (steadier in motion)", &c.glass_focus_tent);
    ImGui::Checkbox("dispersive windows at half texels", &c.glass_focus_spectral_coarse);
    combo("view through glass", st.glass_view.method, {{GlassView::kTable, "table"}, {GlassView::kNearby, "nearby geometry"}});
    CausticMapOptions& m = c.caustic_map;
    slider_u32("caustic map photons", m.photons, 16, 4096, ImGuiSliderFlags_Logarithmic);
    pow2_combo("caustic map size", m.map_size, 16, 4096);
    ImGui::SliderFloat("splat sigma (texels)", &m.splat_sigma, 0.0f, 8.0f);
    ImGui::Checkbox("two-pass splats", &m.two_pass);
    slider_u32("adaptive levels", m.adaptive_levels, 0, 8);
    slider_u32("mirror bounces", m.bounces, 1, 8);
  }
  if (ImGui::CollapsingHeader("Shadows and media")) {
    combo("shadow filter", c.shadows.filter, {{ShadowFilter::kPcf, "PCF 3x3"}, {ShadowFilter::kVsm, "variance shadow maps"}});
    ImGui::SliderFloat("VSM bleeding", &c.shadows.vsm_bleeding, 0.0f, 0.95f);
    ImGui::Checkbox("media (volume caustics, shafts)", &c.volume.enabled);
    slider_u32("media photons", c.volume.photons, 16, 2048, ImGuiSliderFlags_Logarithmic);
    slider_u32("radiance grid", c.volume.grid, 8, 256, ImGuiSliderFlags_Logarithmic);
    ImGui::Checkbox("octree steps", &c.volume.octree);
    ImGui::Checkbox("refraction at the surface (else curved paths)", &c.volume.surface_refraction);
  }
  if (ImGui::CollapsingHeader("Water surface")) {
    WaterLook& w = st.look;
    ImGui::Checkbox("textured (refraction, reflection)", &w.textures);
    ImGui::Checkbox("refraction", &w.refraction);
    ImGui::SameLine();
    ImGui::Checkbox("reflection", &w.reflection);
    ImGui::Checkbox("water colour", &w.colour);
    ImGui::SameLine();
    ImGui::Checkbox("glow", &w.glow);
    combo("Fresnel", w.fresnel, {{FresnelMode::kApprox, "approximate (eq. 7-8)"}, {FresnelMode::kExact, "exact"}});
    ImGui::SliderInt("W/A steps", &w.steps, 1, 16);
    ImGui::SliderInt("W/A steps at most", &w.max_steps, 1, 64);
    bool auto_size = w.texture_size == 0;
    if (ImGui::Checkbox("texture size: a texel per pixel", &auto_size)) w.texture_size = auto_size ? 0 : 512;
    if (!auto_size) ImGui::SliderInt("texture size", &w.texture_size, 64, 4096, "%d", ImGuiSliderFlags_Logarithmic);
    if (auto_size) {
      bool unlimited = w.max_texture_size == 0;
      if (ImGui::Checkbox("no size limit", &unlimited)) w.max_texture_size = unlimited ? 0 : 512;
      if (!unlimited) ImGui::SliderInt("size limit", &w.max_texture_size, 16, 4096, "%d", ImGuiSliderFlags_Logarithmic);
    }
    ImGui::SliderFloat("FOV extension", &w.fov_ext, 1.0f, 4.0f);
    ImGui::SliderFloat("wave scale", &st.wave_scale, 0.0f, 4.0f);
  }
  if (ImGui::CollapsingHeader("Interactive water", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Checkbox("simulate (I)", &st.simulate);
    ImGui::SameLine();
    if (ImGui::Button("Calm")) st.sim_reset = true;
    ImGui::SliderFloat("wave speed (m/s)", &st.sim.wave_speed, 0.05f, 5.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    ImGui::SliderFloat("damping (1/s)", &st.sim.damping, 0.0f, 5.0f);
    ImGui::SliderFloat("short-wave damping (1/s)", &st.sim.short_wave_damping, 0.0f, 10.0f);
    ImGui::SliderFloat("ripple radius (m)", &st.ripple_radius, 0.02f, 1.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    ImGui::SliderFloat("ripple amplitude (m)", &st.ripple_amplitude, -0.1f, 0.1f, "%.3f");
    const auto& objects = r.scene().objects;
    const char* current = st.selected >= 0 ? objects[static_cast<std::size_t>(st.selected)].name.c_str() : "(none)";
    if (ImGui::BeginCombo("Shift + drag moves", current)) {
      if (ImGui::Selectable("(none)", st.selected < 0)) st.selected = -1;
      for (std::size_t i = 0; i < objects.size(); ++i) {
        if (ImGui::Selectable(objects[i].name.c_str(), st.selected == static_cast<int>(i))) st.selected = static_cast<int>(i);
      }
      ImGui::EndCombo();
    }
    ImGui::TextWrapped("Ctrl + click drops a ripple; Shift + drag moves the object, Shift + wheel raises it.");
  }
  if (ImGui::CollapsingHeader("Light")) {
    st.light_moved |= ImGui::SliderFloat("elevation", &st.light_elevation, 1.0f, 90.0f, "%.0f deg");
    st.light_moved |= ImGui::SliderFloat("azimuth", &st.light_azimuth, -180.0f, 180.0f, "%.0f deg");
    st.light_moved |= ImGui::ColorEdit3("colour", st.light_color.data());
    st.light_moved |= ImGui::SliderFloat("irradiance / intensity", &st.light_power, 0.0f, 10.0f);
  }
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) {
    combo("tone curve", st.display.tone_map, {{ToneMap::kFilmic, "filmic (ACES fit)"}, {ToneMap::kExponential, "1 - e^-x"}});
    ImGui::SliderFloat("exposure (EV)", &st.display.exposure_ev, -8.0f, 8.0f, "%+.1f");
    ImGui::Checkbox("auto exposure", &st.display.auto_exposure);
    ImGui::Checkbox("flat sky", &st.flat_sky);
    ImGui::SliderInt("supersampling", &st.supersample, 1, 3, "%dx");
  }
  ImGui::End();
  return screenshot;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace caustix;
  using namespace caustix::runtime;
  using namespace caustix::sample;
  std::string size = "1280x720", screenshot;
  int frames = 0;
  CLI::App app{"caustix-view: interactive viewer for a scene: a baked .cxb, or a scene.json or glTF file"};
  app.footer(
      "Controls: left drag orbit, right drag pan, wheel zoom, Space pause waves, R reset, Esc quit.\n"
      "Water: T plain/textured, 1 refraction, 2 reflection, 3 colour, 4 glow, F Fresnel, , . W/A steps.\n"
      "Display: 9 0 exposure -/+ 0.5 EV, A auto exposure, O filmic/exponential tone curve, X supersampling.\n"
      "Panel: Tab hides/shows it. Interactive water: I toggles it, Ctrl + click drops a ripple,\n"
      "       Shift + drag moves the object chosen in the panel (Shift + wheel: up/down).\n"
      "Exit codes: 0 ok, 1 internal, 2 usage, 3 input unreadable (or a scene.json, glTF or mesh that does\n"
      "            not bake), 4 invalid .cxb, 5 screenshot (or the bake cache) not written, 6 no window or\n"
      "            OpenGL 4.5 context (needs a display; try xvfb-run -a).");
  tools::OpenOptions open_options;
  tools::add_open_options(app, open_options);
  cli::add_size_option(app, "--size", size, "window size");
  app.add_option("--screenshot", screenshot, "save the window to this image after --frames frames, then exit");
  app.add_option("--frames", frames, "frames to render before the screenshot (with --screenshot)")
      ->check(CLI::Range(1, 100000))->capture_default_str();
  bool no_ui = false, simulate = false;
  std::vector<std::string> ripples;
  app.add_flag("--no-ui", no_ui, "start without the panel (Tab shows it)");
  app.add_flag("--simulate", simulate, "start with the interactive water on (key I, docs/water-simulation.md)");
  app.add_option("--ripple", ripples, "with --simulate: drop a ripple at x,z at the start (repeatable)")->take_all();
  if (auto rc = cli::parse(app, "caustix-view", argc, argv)) return *rc;
  int width = 0, height = 0;
  cli::parse_size(size, width, height);
  if (!screenshot.empty() && frames == 0) frames = 1;
  auto fail = [](const Error& e) { return cli::fail("caustix-view", e); };
  std::vector<glm::vec2> start_ripples;
  for (const std::string& r : ripples) {
    float x = 0, z = 0;
    char extra = 0;
    if (std::sscanf(r.c_str(), "%f,%f%c", &x, &z, &extra) != 2 || !std::isfinite(x) || !std::isfinite(z)) {
      return fail(make_error(ErrorCode::kUsage, "--ripple '" + r + "' is not x,z"));
    }
    start_ripples.emplace_back(x, z);
  }

  auto scene = tools::open_scene("caustix-view", open_options);
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
    state.ui = !no_ui;
    state.simulate = simulate;
    state.ripples = start_ripples;
    state.caustics = default_caustics_options(scene->desc);
    state.look = default_water_look(scene->desc);
    state.orbit = state.home = Orbit::from((*renderer)->default_camera());
    state.display.exposure_ev = (*renderer)->default_exposure_ev();
    glfwSetWindowUserPointer(window, &state);
    // The first light's direction as elevation above the horizon and azimuth.
    if (!(*renderer)->scene().lights.empty()) {
      const Light& l = (*renderer)->scene().lights[0];
      const glm::vec3 d = glm::normalize(glm::vec3(l.direction[0], l.direction[1], l.direction[2]));
      state.light_elevation = glm::degrees(std::asin(std::clamp(-d.y, -1.0f, 1.0f)));
      state.light_azimuth = glm::degrees(std::atan2(d.z, d.x));
      state.light_color = {l.color[0], l.color[1], l.color[2]};
      state.light_power = l.type == LightType::kDirectional ? l.irradiance : l.intensity;
    }
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
      auto* s = static_cast<ViewState*>(glfwGetWindowUserPointer(w));
      if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
      if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureKeyboard) return;
      auto& c = s->caustics;
      switch (key) {
        case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
        case GLFW_KEY_SPACE: s->paused = !s->paused; break;
        case GLFW_KEY_TAB: s->ui = !s->ui; break;
        case GLFW_KEY_I: s->simulate = !s->simulate; break;
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
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
      auto* s = static_cast<ViewState*>(glfwGetWindowUserPointer(w));
      glfwGetCursorPos(w, &s->last_x, &s->last_y);
      if (action == GLFW_RELEASE) {
        s->rotating = s->panning = s->dragging = false;
        return;
      }
      if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) return;
      if (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_CONTROL) && s->simulate) {
        if (auto p = on_plane(cursor_ray(*s, s->last_x, s->last_y), s->water_level)) s->ripples.emplace_back(p->x, p->z);
      } else if (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_SHIFT) && s->selected >= 0) {
        s->dragging = true;
        s->drag_from = on_plane(cursor_ray(*s, s->last_x, s->last_y), s->selected_y);
      } else if (button == GLFW_MOUSE_BUTTON_LEFT) {
        s->rotating = true;
      } else if (button == GLFW_MOUSE_BUTTON_RIGHT) {
        s->panning = true;
      }
    });
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
      auto* s = static_cast<ViewState*>(glfwGetWindowUserPointer(w));
      const auto dx = static_cast<float>(x - s->last_x), dy = static_cast<float>(y - s->last_y);
      s->last_x = x;
      s->last_y = y;
      if (s->dragging) {
        const auto to = on_plane(cursor_ray(*s, x, y), s->selected_y);
        if (to && s->drag_from) s->drag_delta += *to - *s->drag_from;
        s->drag_from = to;
      } else if (s->rotating) {
        s->orbit.yaw -= 0.005f * dx;
        s->orbit.pitch = std::clamp(s->orbit.pitch + 0.005f * dy, -1.55f, 1.55f);
      } else if (s->panning) {
        const glm::vec3 right(std::cos(s->orbit.yaw), 0, -std::sin(s->orbit.yaw));
        s->orbit.target += s->orbit.distance * 0.0015f * (-dx * right + dy * glm::vec3(0, 1, 0));
      }
    });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
      auto* s = static_cast<ViewState*>(glfwGetWindowUserPointer(w));
      if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) return;
      if (s->selected >= 0 && (glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS)) {
        s->drag_delta.y += 0.05f * static_cast<float>(dy);
        return;
      }
      s->orbit.distance = std::max(1e-3f, s->orbit.distance * std::pow(0.9f, static_cast<float>(dy)));
    });
    // Dear ImGui after the viewer's callbacks: its GLFW back end chains to them.
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working directory
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    (*renderer)->set_pass_timing(true);
    TimeHistory history;
    std::unique_ptr<WaterSimulation> sim;
    std::vector<std::uint32_t> bodies((*renderer)->scene().objects.size());
    for (std::uint32_t i = 0; i < bodies.size(); ++i) bodies[i] = i;
    if (const auto grid = (*renderer)->engine().water_grid()) state.water_level = grid->level;
    std::string note;
    int screenshots = 0;

    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto last_report = start;
    double anim_time = 0, frame_ms_sum = 0, rederive_ms = 0, last_dt = 1.0 / 60.0;
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
          l.irradiance = state.light_power;
        } else {
          l.intensity = state.light_power;
        }
        l.color = {state.light_color[0], state.light_color[1], state.light_color[2]};
        const auto r0 = Clock::now();
        if (Status st = (*renderer)->set_light(0, l); !st) {
          rc = fail(st.error());
          break;
        }
        (*renderer)->finish();
        rederive_ms = std::chrono::duration<double, std::milli>(Clock::now() - r0).count();
      }
      (*renderer)->set_wave_scale(state.wave_scale);
      Engine& engine = (*renderer)->engine();
      // The object Shift + drag moves: its height picks the drag plane.
      if (state.selected >= 0) {
        Mat4f t = (*renderer)->scene().objects[static_cast<std::size_t>(state.selected)].transform;
        state.selected_y = t[13];
        if (state.drag_delta != glm::vec3(0.0f)) {
          t[12] += state.drag_delta.x;
          t[13] += state.drag_delta.y;
          t[14] += state.drag_delta.z;
          state.drag_delta = glm::vec3(0.0f);
          if (Status st = (*renderer)->set_object_transform(static_cast<std::uint32_t>(state.selected), t); !st) note = st.error().message;
        }
      }
      // The interactive water: ripples, bodies, a step of the frame's time.
      if (state.simulate && !sim) {
        if (const auto grid = engine.water_grid()) {
          auto created = WaterSimulation::create(*grid, state.sim);
          if (created) sim = std::move(*created);
          else note = created.error().message;
        } else {
          note = "interactive water: the scene has no water";
        }
        if (!sim) state.simulate = false;
      } else if (!state.simulate && sim) {
        sim.reset();
        engine.use_scene_waves();
      }
      if (sim) {
        if (state.sim_reset) sim->reset();
        if (Status st = sim->set_options(state.sim); !st) note = st.error().message;
        for (const glm::vec2& p : state.ripples) {
          if (Status st = sim->add_ripple(p.x, p.y, state.ripple_radius, state.ripple_amplitude); !st) note = st.error().message;
        }
        state.ripples.clear();
        Status st = sim->push(engine, bodies);
        if (st) st = sim->step(state.paused ? 0.0f : static_cast<float>(std::min(last_dt, 0.05)));
        if (st) st = sim->apply(engine);
        if (!st) {
          rc = fail(st.error());
          break;
        }
      }
      state.sim_reset = false;
      FrameParams frame;
      frame.camera = state.orbit.apply(base);
      frame.time = static_cast<float>(anim_time);
      frame.width = fw;
      frame.height = fh;
      // A monochromatic image the glass tables cannot make (dispersive
      // glass): said in the panel, not a failed frame.
      if (Status ok = check_wavelengths((*renderer)->scene(), state.caustics); !ok) {
        note = ok.error().message;
        state.caustics.wavelength_nm.reset();
      }
      frame.caustics = state.caustics;
      frame.water = state.look;
      frame.glass_view = state.glass_view;
      frame.display = state.display;
      frame.supersample = state.supersample;
      frame.sky = state.flat_sky ? SkyModel::kFlat : SkyModel::kAnalytic;
      if (Status st = (*renderer)->render(frame); !st) {
        rc = fail(st.error());
        break;
      }
      {  // the camera for picking, as the renderer built it
        glfwGetWindowSize(window, &state.win_width, &state.win_height);
        const glm::vec3 eye(frame.camera.position[0], frame.camera.position[1], frame.camera.position[2]);
        const glm::vec3 target(frame.camera.target[0], frame.camera.target[1], frame.camera.target[2]);
        View v;
        v.view = glm::lookAt(eye, target, glm::vec3(0, 1, 0));
        v.fov_y_deg = frame.camera.fov_y_deg;
        v.aspect = static_cast<float>(fw) / static_cast<float>(fh);
        v.near_plane = frame.camera.near_plane;
        v.far_plane = frame.camera.far_plane;
        state.view_proj = v.projection() * v.view;
      }
      (*renderer)->present(0, fw, fh);
      const PassTimes times = (*renderer)->pass_times();
      if (times.valid) history.add(times);
      bool shot = false;
      if (state.ui) {
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        shot = draw_panel(state, **renderer, history, gl_name, last_dt * 1e3, note);
        ImGui::Render();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, fw, fh);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      }
      ++rendered;
      const bool final_shot = !screenshot.empty() && rendered >= frames;
      if (shot || final_shot) {
        std::string path = final_shot ? screenshot : "caustix-view-" + std::to_string(++screenshots) + ".png";
        std::vector<std::uint8_t> px(static_cast<std::size_t>(fw) * static_cast<std::size_t>(fh) * 3);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadBuffer(GL_BACK);
        glReadPixels(0, 0, fw, fh, GL_RGB, GL_UNSIGNED_BYTE, px.data());
        std::vector<std::uint8_t> flipped(px.size());
        const std::size_t row = static_cast<std::size_t>(fw) * 3;
        for (int y = 0; y < fh; ++y) {
          std::copy_n(px.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(fh - 1 - y) * row), row,
                      flipped.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row));
        }
        if (Status st = write_u8_image(path, fw, fh, 3, flipped); !st) {
          if (final_shot) rc = fail(st.error());
          else note = st.error().message;
        } else {
          std::printf("caustix-view: saved %s (%dx%d) after %d frames\n", path.c_str(), fw, fh, rendered);
          if (!final_shot) note = "saved " + path;
        }
        if (final_shot) break;
      }
      glfwSwapBuffers(window);
      const auto t1 = Clock::now();
      const double dt = std::chrono::duration<double>(t1 - t0).count();
      last_dt = dt;
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
  if (ImGui::GetCurrentContext()) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  return rc;
}
