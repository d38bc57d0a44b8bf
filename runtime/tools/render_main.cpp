// caustix-render: renders a .cxb headless (EGL, no X server) to an image.
// Exit codes: see --help.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <tuple>
#include <vector>

#include "caustix/common/cli.h"
#include "open_scene.h"
#include "caustix/runtime/gl_context.h"
#include "caustix/sample/image_output.h"
#include "caustix/sample/renderer.h"
#include "caustix/runtime/scene_loader.h"
#include "caustix/runtime/water_sim.h"

int main(int argc, char** argv) {
  using namespace caustix;
  using namespace caustix::runtime;
  using namespace caustix::sample;
  std::string out_path, size = "640x480", receiver, region = "-2,-2,2,2", method = "levelmap";
  float time = 0.0f, epsilon = 0.0f;
  std::uint32_t planes = 0, caustics_size = 0;
  bool quiet = false, verbose = false, no_cull = false;
  std::string map_batching = "auto";

  CLI::App app{"caustix-render: render a scene to an image, headless (EGL): a baked .cxb, or a scene.json or glTF file"};
  app.footer(
      "Output: .exr keeps linear float RGB; .png/.jpg/.tif get tone-mapped sRGB. With --irradiance, the\n"
      "        image is the receiver's irradiance / E0 seen from above (.exr).\n"
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 input file unreadable (or a scene.json, glTF or mesh that\n"
      "            does not bake), 4 invalid .cxb, 5 image (or the bake cache) could not be written,\n"
      "            6 no usable OpenGL 4.5 context.");
  tools::OpenOptions open_options;
  tools::add_open_options(app, open_options);
  app.add_option("-o,--output", out_path, "output image (.png, .exr, ...)")->required();
  cli::add_size_option(app, "--size", size, "image size");
  app.add_option("--time", time, "animation time in seconds (waves)")->capture_default_str()
      ->check(CLI::Range(-1e6f, 1e6f));
  auto* irradiance_option = app.add_option("--irradiance", receiver,
                 "write the irradiance image of this receiver (docs/architecture.md: top-down, linear, divided by E0, "
                 "no albedo or ambient) instead of the beauty image");
  bool inscatter = false;
  app.add_flag("--inscatter", inscatter,
               "write the in-scatter image (docs/architecture.md, Pfeuti: orthographic along -z, row 0 at y1, single "
               "scattering / E0; surfaces not drawn) instead of the beauty image (.exr)")
      ->excludes(irradiance_option);
  app.add_option("--region", region, "world rectangle x0,z0,x1,z1 of the irradiance image; x0,y0,x1,y1 of the in-scatter image")
      ->capture_default_str();
  int pixel_samples = IrradianceRequest{}.pixel_samples;
  app.add_option("--pixel-samples", pixel_samples,
                 "irradiance: S x S point samples per pixel, averaged (the pixel-box average; 1: the pixel centre; "
                 "16 for fold lines on curved receivers, docs/caustics.md)")
      ->check(CLI::Range(1, 16))->capture_default_str();
  std::string aux_path;
  app.add_option("--aux", aux_path,
                 "irradiance: also write the per-pixel receiver coverage, mean |n_y| and mean cosine towards the "
                 "first light (R, G, B; .exr) for caustix-compare --split")
      ->needs(irradiance_option);
  app.add_option("--method", method, "caustics: levelmap (smart slicing), uniform, volumetric, splat (photon splatting, Mihalik 2008 ch. 8) for water; any but none also draws glass caustics (illumination textures); none: flat water, glass casts a plain shadow")
      ->check(CLI::IsMember({"levelmap", "uniform", "volumetric", "splat", "none"}))->capture_default_str();
  std::uint32_t photons = 0;
  app.add_option("--photons", photons, "splat: photon texture P (P x P photons per map); default " + std::to_string(CausticsOptions{}.photons))
      ->check(CLI::Range(1, 8192));
  app.add_option("--planes", planes, "re-slice: uniform n pieces; smart eps = h/(2n) (default: as baked)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--epsilon", epsilon, "re-slice smart planes with this acceptance half-width, metres")
      ->check(CLI::Range(1e-9, 1e9));
  // Defaults: the preset's recorded in the .cxb (RNDR), else CausticsOptions'.
  const CausticsOptions built_in;
  app.add_option("--caustics-size", caustics_size,
                 "caustics map size S (S x S); default: the bake preset's, else " + std::to_string(built_in.map_size))
      ->check(CLI::Range(1, 8192));
  float texel = 0.0f;
  app.add_option("--texel", texel,
                 "caustics maps' texel, metres, for every receiver (default: the light's largest lit extent / the map size)")
      ->check(CLI::Range(1e-6, 1e3));
  double budget_mb = -1.0;
  app.add_option("--memory-budget", budget_mb,
                 "GPU memory the light side may hold, MB (MiB); the caustics maps' texels are coarsened to fit; 0: none "
                 "(default: the bake preset's, 128 at balanced)")
      ->check(CLI::Range(0.0, 1.0e7));
  std::uint32_t glass_planes = 0, glass_size = 0;
  app.add_option("--glass-planes", glass_planes,
                 "glass: virtual planes per target (Iwasaki et al. §4.2); default: the bake preset's, else " +
                     std::to_string(built_in.glass_planes))
      ->check(CLI::Range(1, 16));
  app.add_option("--glass-size", glass_size,
                 "glass: illumination texture size (S x S); default: the bake preset's, else " +
                     std::to_string(built_in.glass_map_size))
      ->check(CLI::Range(1, 8192));
  bool glass_flat = false;
  app.add_flag("--glass-flat", glass_flat,
               "glass (table): one intensity per intersection triangle, as Iwasaki et al.'s eq. 3 (default: interpolated from the corners; docs/glass.md)");
  bool glass_no_focus = false;
  app.add_flag("--glass-no-focus", glass_no_focus,
               "glass (table): no focus windows, one illumination texture per plane over each whole receiver, as Iwasaki et al. (docs/glass-focus.md)");
  bool glass_focus_box = false;
  app.add_flag("--glass-focus-box", glass_focus_box,
               "glass (table): a focus window's texels take the light inside them (the box) instead of by the tent: a focus a "
               "little sharper that steps from texel to texel as it moves (docs/temporal.md)");
  float glass_focus_wide = runtime::CausticsOptions{}.glass_focus_wide;
  app.add_option("--glass-focus-wide", glass_focus_wide,
                 "glass (table): in a focus window, triangles at least this many of its texels high are drawn by a second program that "
                 "covers the texels along one edge in closed form (0: every triangle clipped; docs/glass-focus.md)")
      ->check(CLI::Range(0.0f, 1e6f))->capture_default_str();
  std::string glass_focus_spectral;
  app.add_option("--glass-focus-spectral", glass_focus_spectral,
                 "glass (table): where glass disperses, focus windows drawn per wavelength at half their texels a side and interpolated "
                 "(coarse) or at their own (full); default: the bake preset's (accurate: full), else coarse (docs/glass-focus.md)")
      ->check(CLI::IsMember({"coarse", "full"}));
  bool caustics_flat = false;
  app.add_flag("--caustics-flat", caustics_flat,
               "water caustics: one irradiance per water triangle, as Tipprasert 2006's eq. 4-18 (default: interpolated from the corners; docs/caustics.md)");
  app.add_flag("--no-cull", no_cull, "draw every illumination volume (measures what culling saves)");
  app.add_option("--map-batching", map_batching, "level maps in batches: auto, always or never (CausticsOptions::map_batching)")
      ->check(CLI::IsMember({"auto", "always", "never"}));
  // Dispersion (docs/dispersion.md).
  std::uint32_t wavelengths = built_in.wavelengths;
  app.add_option("--wavelengths", wavelengths,
                 "dispersion: wavelengths traced wherever something disperses: caustic maps, glass tables, the water's caustics, "
                 "media, the views through water and glass (--glass-view nearby) (equal bins of 380-780 nm; 1: the d line only)")
      ->check(CLI::Range(1u, kMaxWavelengths))->capture_default_str();
  float wavelength = 0;
  app.add_option("--wavelength", wavelength,
                 "dispersion: a monochromatic image, every index at this wavelength in nm (the light's own colour, weight 1)")
      ->check(CLI::Range(kMinWavelength, kMaxWavelength));
  // Image-space caustic maps (timofy 2009; docs/caustic-maps.md).
  std::string glass_method = to_string(built_in.glass_method);
  CausticMapOptions cmap;
  bool cmap_two_pass = false, cmap_drop_tir = false, cmap_no_focus = false;
  app.add_option("--glass-method", glass_method,
                 "light through glass: table (light-transport tables, Iwasaki et al.) or caustic-map (image-space caustic maps, timofy 2009); mirrors always use caustic maps")
      ->check(CLI::IsMember({"table", "caustic-map"}))->capture_default_str();
  std::string glass_view = to_string(GlassView::kTable);
  GlassViewOptions view_options;
  app.add_option("--glass-view", glass_view,
                 "the view through glass: table (view rays through the light-transport table, Iwasaki et al. §3) or nearby (nearby-geometry refraction, timofy 2009: per pixel against the glass's back faces and the scene's depth)")
      ->check(CLI::IsMember({"table", "nearby"}))->capture_default_str();
  app.add_option("--glass-view-iterations", view_options.iterations, "nearby glass view: landing iterations against the scene's depth")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("--glass-view-exit-iterations", view_options.exit_iterations,
                 "nearby glass view: exit-point iterations against the glass's back faces")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("--cmap-photons", cmap.photons, "caustic maps: photon grid side over the casters (P x P photons per light)")
      ->check(CLI::Range(1, 4096))->capture_default_str();
  app.add_option("--cmap-size", cmap.map_size, "caustic maps: caustic map side")->check(CLI::Range(16, 4096))->capture_default_str();
  app.add_option("--cmap-sigma", cmap.splat_sigma, "caustic maps: Gaussian splat standard deviation, texels (0: one texel)")
      ->check(CLI::Range(0.0f, 8.0f))->capture_default_str();
  app.add_flag("--cmap-two-pass", cmap_two_pass, "caustic maps: one-texel splats, then a separable blur (instead of one-pass Gaussian splats)");
  app.add_option("--cmap-iterations", cmap.iterations, "caustic maps: landing iterations against the receivers")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("--cmap-exit-iterations", cmap.exit_iterations, "caustic maps: exit-point iterations against the glass's back faces")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("--cmap-bounces", cmap.bounces, "caustic maps: caster surfaces (mirror reflections) followed per photon")
      ->check(CLI::Range(1, 8))->capture_default_str();
  app.add_flag("--cmap-no-focus", cmap_no_focus,
               "caustic maps: no focus window, the map alone over the whole scene (default: a finer window where the photons concentrate; docs/caustic-maps.md)");
  app.add_flag("--cmap-drop-tir", cmap_drop_tir, "caustic maps: drop photons totally reflected at the glass's exit (default: leave them unrefracted)");
  app.add_option("--cmap-edge-cos", cmap.edge_cos, "caustic maps: edge testing, drop photons entering glass where |n.l| is below this (0: off)")
      ->check(CLI::Range(0.0f, 1.0f))->capture_default_str();
  app.add_option("--cmap-max-deviation", cmap.max_deviation_deg, "caustic maps: bounded refraction deviation, degrees (180: off)")
      ->check(CLI::Range(0.0f, 180.0f))->capture_default_str();
  app.add_option("--cmap-max-travel", cmap.max_travel, "caustic maps: drop photons that travel farther after a mirror, metres (0: the scene's diagonal)")
      ->check(CLI::Range(0.0f, 1e6f))->capture_default_str();
  app.add_option("--cmap-adaptive", cmap.adaptive_levels,
                 "caustic maps: adaptive traversal levels (Wyman & Nichols 2009): start from cells of 2^n x 2^n grid texels, refine those over a caster (0: the uniform grid)")
      ->check(CLI::Range(0, 8))->capture_default_str();
  app.add_option("--cmap-budget", cmap.photon_budget, "caustic maps, adaptive: most photons traced per light")
      ->check(CLI::Range(1, 1 << 24))->capture_default_str();
  std::string sky = "analytic";
  app.add_option("--sky", sky, "the background and what the water reflects: analytic (Preetham's daylight for the scene's sun) or flat")
      ->check(CLI::IsMember({"analytic", "flat"}))->capture_default_str();
  // Display images (docs/display.md); EXR output stays linear.
  DisplayOptions display;
  std::string tone_map = to_string(display.tone_map);
  app.add_option("--tone-map", tone_map, "display images (PNG, ...): filmic (ACES fit) or exponential (1 - e^-x); EXR stays linear")
      ->check(CLI::IsMember({"filmic", "exponential"}))->capture_default_str();
  app.add_option("--exposure", display.exposure_ev,
                 "display images: exposure, stops (EV) added to the auto exposure's when both; default -1 EV relative to the scene's "
                 "sun, or to its brightest point light at the scene's centre")
      ->check(CLI::Range(-16.0f, 16.0f))->capture_default_str();
  app.add_flag("--auto-exposure", display.auto_exposure, "display images: scale the log-average luminance to 0.18 first");
  int supersample = 2;
  app.add_option("--supersample", supersample, "antialiasing: render N x N samples per pixel and box-filter them (1: off)")
      ->check(CLI::Range(1, 4))->capture_default_str();
  // Shadows (variance shadow maps, timofy 2009).
  ShadowOptions shadow_options;
  std::string shadow_filter = to_string(shadow_options.filter);
  app.add_option("--shadow-filter", shadow_filter, "shadows of directional lights: pcf (3x3) or vsm (variance shadow maps, Donnelly & Lauritzen 2006)")
      ->check(CLI::IsMember({"pcf", "vsm"}))->capture_default_str();
  app.add_option("--vsm-filter", shadow_options.vsm_filter, "variance shadow maps: box filter width, texels (odd)")
      ->check(CLI::Range(1, 63))->capture_default_str();
  app.add_option("--vsm-bleeding", shadow_options.vsm_bleeding, "variance shadow maps: light-bleeding reduction in [0, 0.95]")
      ->check(CLI::Range(0.0f, 0.95f))->capture_default_str();
  // Media (Pfeuti; docs/volume.md).
  VolumeOptions volume;
  bool no_media = false, no_octree = false;
  std::uint32_t volume_photons = 0, volume_grid = 0;
  app.add_option("--volume-photons", volume_photons,
                 "media: P x P photons per light; default: the bake preset's, else " + std::to_string(built_in.volume.photons))
      ->check(CLI::Range(1, 8192));
  app.add_option("--volume-grid", volume_grid,
                 "media: radiance-grid voxels along the media's longest side; default: the bake preset's, else " +
                     std::to_string(built_in.volume.grid))
      ->check(CLI::Range(2, 1024));
  app.add_option("--volume-focus", volume.focus_grid,
                 "media: focus-grid voxels a side, over where light through glass concentrates (a ball's focal line); 0: none")
      ->check(CLI::Range(0, 128))->capture_default_str();
  app.add_option("--volume-step", volume.step, "media: photon and view steps where an object's index varies, index-grid voxels")
      ->check(CLI::Range(0.05f, 16.0f))->capture_default_str();
  app.add_option("--view-step", volume.view_step, "media: viewing-pass steps, radiance-grid voxels")
      ->check(CLI::Range(0.05f, 16.0f))->capture_default_str();
  app.add_flag("--no-octree", no_octree, "media: uniform steps inside index grids (measures what the octree saves)");
  std::string volume_refraction = volume.surface_refraction ? "surface" : "gradient";
  app.add_option("--volume-refraction", volume_refraction,
                 "media: how rays cross an object's surface in its index grid: surface (Snell where the coverage crosses 1/2) "
                 "or gradient (the seed's curved path through the blurred index)")
      ->check(CLI::IsMember({"surface", "gradient"}))->capture_default_str();
  app.add_flag("--no-media", no_media, "media: no volume caustics or single scattering");
  // The water surface (Mihalik 2008).
  WaterLook look;
  std::string fresnel = "approx", camera_pos, camera_target;
  bool plain_water = false, no_refraction = false, no_reflection = false, no_colour = false, no_glow = false;
  app.add_flag("--plain-water", plain_water, "water without refraction/reflection textures (sky reflection over the scene)");
  app.add_flag("--no-refraction", no_refraction, "water: look straight through (no bending, §7.1 off)");
  app.add_flag("--no-reflection", no_reflection, "water: no reflection (F = 0)");
  app.add_flag("--no-water-colour", no_colour, "water: no attenuation towards the water colour (eq. 4-5, 10)");
  app.add_flag("--no-glow", no_glow, "water: no glow on the sun's highlight (§9.3)");
  app.add_option("--fresnel", fresnel, "water: approx (eq. 7-8, q = --fresnel-q) or exact (unpolarised, with TIR)")
      ->check(CLI::IsMember({"approx", "exact"}))->capture_default_str();
  app.add_option("--fresnel-q", look.fresnel_q, "water: q of eq. 7")->check(CLI::Range(0.1f, 100.0f))->capture_default_str();
  app.add_option("--water-steps", look.steps, "water: W/A iterations of the refracted lookup (§7.1)")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("--water-texture", look.texture_size,
                 "water: refraction/reflection texture size (N x N); 0: a texel per pixel over the extended field of view, "
                 "at most --water-texture-limit")
      ->check(CLI::Range(0, 8192))->capture_default_str();
  int water_limit = -1;
  app.add_option("--water-texture-limit", water_limit,
                 "water: the largest automatic texture size (16..8192; 0: none); default: the bake preset's (fast 256, "
                 "balanced 512, accurate none), else 512")
      ->check(CLI::Range(0, 8192));
  app.add_option("--water-max-steps", look.max_steps,
                 "water: W/A iterations continue past --water-steps up to this many until converged (<= steps: the paper's fixed count)")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("--fov-ext", look.fov_ext, "water: field-of-view extension of the textures (fig. 5)")
      ->check(CLI::Range(1.0f, 4.0f))->capture_default_str();
  // Interactive water (docs/water-simulation.md): the height field instead of the wave list.
  std::vector<std::string> ripples;
  float simulate = 0.0f;
  WaterSimOptions sim_options;
  app.add_option("--ripple", ripples,
                 "simulated water: drop a ripple x,z[,radius[,amplitude]] (metres; default radius 0.15, amplitude "
                 "0.02) at the start; repeatable")
      ->take_all();
  app.add_option("--simulate", simulate,
                 "simulated water: run the height-field simulation this many seconds (60 steps/s) from rest plus the "
                 "ripples, and render its water instead of the scene's waves")
      ->check(CLI::Range(0.0f, 600.0f));
  app.add_option("--wave-speed", sim_options.wave_speed, "simulated water: wave speed c, m/s")
      ->check(CLI::Range(0.01f, 100.0f))->capture_default_str();
  app.add_option("--damping", sim_options.damping, "simulated water: damping gamma, 1/s (amplitudes fall as e^(-gamma t/2))")
      ->check(CLI::Range(0.0f, 999.0f))->capture_default_str();
  app.add_option("--camera", camera_pos, "camera position x,y,z (default: the scene's camera)");
  app.add_option("--target", camera_target, "camera target x,y,z (with --camera; default: the scene's)");
  app.add_flag("-q,--quiet", quiet, "print errors only");
  app.add_flag("-v,--verbose", verbose, "print the renderer and timings");
  if (auto rc = cli::parse(app, "caustix-render", argc, argv)) return *rc;
  int width = 0, height = 0;
  cli::parse_size(size, width, height);
  auto fail = [](const Error& e) { return cli::fail("caustix-render", e); };
  // A file type no writer knows is refused before the render that would fill it.
  if (Status s = check_image_writer(out_path); !s.ok()) return fail(s.error());

  open_options.quiet = quiet;
  open_options.verbose = verbose;
  auto scene = tools::open_scene("caustix-render", open_options);
  if (!scene) return fail(scene.error());
  auto context = HeadlessContext::create();
  if (!context) return fail(context.error());
  auto renderer = Renderer::create(*scene);
  if (!renderer) return fail(renderer.error());

  CausticsOptions caustics = default_caustics_options(scene->desc);
  caustics.method = *parse_method(method);
  if (planes > 0) caustics.planes = planes;
  if (epsilon > 0) caustics.epsilon = epsilon;
  if (caustics_size > 0) caustics.map_size = caustics_size;
  caustics.texel_size = texel;
  if (budget_mb >= 0) caustics.memory_budget = static_cast<std::uint64_t>(budget_mb * 1048576.0);
  if (glass_planes > 0) caustics.glass_planes = glass_planes;
  if (glass_size > 0) caustics.glass_map_size = glass_size;
  caustics.glass_smooth = !glass_flat;
  caustics.glass_focus = !glass_no_focus;
  caustics.glass_focus_wide = glass_focus_wide;
  caustics.glass_focus_tent = !glass_focus_box;
  if (!glass_focus_spectral.empty()) caustics.glass_focus_spectral_coarse = glass_focus_spectral == "coarse";
  caustics.water_smooth = !caustics_flat;
  caustics.cull = !no_cull;
  caustics.map_batching = map_batching == "always" ? runtime::MapBatching::kAlways
                        : map_batching == "never"  ? runtime::MapBatching::kNever
                                                   : runtime::MapBatching::kAuto;
  caustics.wavelengths = wavelengths;
  if (app.count("--wavelength") != 0) caustics.wavelength_nm = wavelength;
  caustics.glass_method = *parse_glass_method(glass_method);
  view_options.method = *parse_glass_view(glass_view);
  display.tone_map = *parse_tone_map(tone_map);
  const SkyModel sky_model = sky == "flat" ? SkyModel::kFlat : SkyModel::kAnalytic;
  if (app.count("--exposure") == 0 && !display.auto_exposure) display.exposure_ev = (*renderer)->default_exposure_ev();
  // The bake preset's caustic-map defaults unless given here.
  if (app.count("--cmap-photons") == 0) cmap.photons = caustics.caustic_map.photons;
  if (app.count("--cmap-size") == 0) cmap.map_size = caustics.caustic_map.map_size;
  if (app.count("--cmap-adaptive") == 0) cmap.adaptive_levels = caustics.caustic_map.adaptive_levels;
  if (app.count("--cmap-budget") == 0) cmap.photon_budget = caustics.caustic_map.photon_budget;
  cmap.two_pass = cmap_two_pass;
  cmap.tir_one_sided = !cmap_drop_tir;
  cmap.focus = !cmap_no_focus;
  caustics.caustic_map = cmap;
  shadow_options.filter = *parse_shadow_filter(shadow_filter);
  caustics.shadows = shadow_options;
  if (photons > 0) caustics.photons = photons;
  caustics.volume.octree = !no_octree;
  caustics.volume.surface_refraction = volume_refraction == "surface";
  caustics.volume.enabled = !no_media;
  caustics.volume.step = volume.step;
  caustics.volume.view_step = volume.view_step;
  caustics.volume.focus_grid = volume.focus_grid;
  if (volume_photons > 0) caustics.volume.photons = volume_photons;
  if (volume_grid > 0) caustics.volume.grid = volume_grid;
  look.max_texture_size = water_limit >= 0 ? water_limit : default_water_look(scene->desc).max_texture_size;
  look.textures = !plain_water;
  look.refraction = !no_refraction;
  look.reflection = !no_reflection;
  look.colour = !no_colour;
  look.glow = !no_glow;
  look.fresnel = fresnel == "exact" ? FresnelMode::kExact : FresnelMode::kApprox;
  Camera camera = (*renderer)->default_camera();
  for (auto [text, name, out] : {std::tuple{&camera_pos, "--camera", &camera.position},
                                 std::tuple{&camera_target, "--target", &camera.target}}) {
    if (text->empty()) continue;
    float x = 0, y = 0, z = 0;
    char extra = 0;
    if (std::sscanf(text->c_str(), "%f,%f,%f%c", &x, &y, &z, &extra) != 3 || !std::isfinite(x) || !std::isfinite(y) ||
        !std::isfinite(z)) {
      return fail(make_error(ErrorCode::kUsage, std::string(name) + " '" + *text + "' is not x,y,z"));
    }
    *out = {x, y, z};
  }

  if (!ripples.empty() || simulate > 0.0f) {
    Engine& engine = (*renderer)->engine();
    const auto grid = engine.water_grid();
    if (!grid) return fail(make_error(ErrorCode::kUsage, "--ripple/--simulate: the scene has no water"));
    auto sim = WaterSimulation::create(*grid, sim_options);
    if (!sim) return fail(sim.error());
    for (const std::string& r : ripples) {
      float x = 0, z = 0, radius = 0.15f, amplitude = 0.02f;
      char extra = 0;
      const int n = std::sscanf(r.c_str(), "%f,%f,%f,%f%c", &x, &z, &radius, &amplitude, &extra);
      if (n < 2 || n > 4) return fail(make_error(ErrorCode::kUsage, "--ripple '" + r + "' is not x,z[,radius[,amplitude]]"));
      if (Status st = (*sim)->add_ripple(x, z, radius, amplitude); !st) return fail(make_error(ErrorCode::kUsage, "--ripple '" + r + "': " + st.error().message));
    }
    const int steps = static_cast<int>(std::lround(simulate * 60.0f));
    for (int i = 0; i < steps; ++i) {
      if (Status st = (*sim)->step(1.0f / 60.0f); !st) return fail(st.error());
    }
    if (Status st = (*sim)->apply(engine); !st) return fail(st.error());
    if (verbose) {
      const WaterSimStats ws = (*sim)->stats();
      std::printf("simulated water: %.3f s in %llu substeps, max |h| %.4f m, volume %.3g m^3, energy %.4g\n", ws.time,
                  static_cast<unsigned long long>(ws.substeps), ws.max_abs_height, ws.volume, ws.energy);
    }
  }

  const auto t0 = std::chrono::steady_clock::now();
  Status written;
  if (inscatter) {
    InscatterRequest q;
    char extra = 0;
    if (std::sscanf(region.c_str(), "%f,%f,%f,%f%c", &q.x0, &q.y0, &q.x1, &q.y1, &extra) != 4) {
      return fail(make_error(ErrorCode::kUsage, "--region '" + region + "' is not x0,y0,x1,y1"));
    }
    if (no_media) return fail(make_error(ErrorCode::kUsage, "--inscatter needs the media (drop --no-media)"));
    q.width = width;
    q.height = height;
    q.time = time;
    q.caustics = caustics;
    q.pixel_samples = app.count("--pixel-samples") > 0 ? pixel_samples : InscatterRequest{}.pixel_samples;
    auto img = (*renderer)->render_inscatter(q);
    if (!img) return fail(img.error());
    for (float v : img->rgb) {
      if (!std::isfinite(v)) return fail(make_error(ErrorCode::kInternal, "non-finite in-scatter rendered"));
    }
    char rect[160];
    std::snprintf(rect, sizeof rect, "%.9g,%.9g,%.9g,%.9g", q.x0, q.y0, q.x1, q.y1);
    const std::vector<std::pair<std::string, std::string>> attributes{
        {"caustix:region", rect}, {"caustix:image", "inscatter"}, {"caustix:e0", std::to_string(img->e0)},
        {"caustix:time", std::to_string(q.time)}, {"caustix:pixel_samples", std::to_string(q.pixel_samples)}};
    written = write_float_image(out_path, width, height, 3, img->rgb, attributes);
    if (verbose) {
      const VolumeStats& v = img->stats;
      std::printf("media: %llu photons (%llu over the glass), %llu steps (%llu in index grids), grid %ux%ux%u, %.1f MB; march %.2f ms, resolve %.2f ms (GPU)\n",
                  static_cast<unsigned long long>(v.photons), static_cast<unsigned long long>(v.glass_photons), static_cast<unsigned long long>(v.steps),
                  static_cast<unsigned long long>(v.grid_steps), v.grid_size[0], v.grid_size[1], v.grid_size[2],
                  static_cast<double>(v.grid_bytes) / 1e6, v.march_ms, v.resolve_ms);
      std::printf("energy / E0 (m^2): in %.6g = scattered %.6g + absorbed %.6g + leaving %.6g + reflected %.6g + truncated %.6g; grid holds %.6g\n",
                  v.power_in, v.scattered, v.absorbed, v.leaving, v.reflected, v.truncated, v.deposited);
    }
  } else if (!receiver.empty()) {
    IrradianceRequest q;
    q.receiver = receiver;
    char extra = 0;
    if (std::sscanf(region.c_str(), "%f,%f,%f,%f%c", &q.x0, &q.z0, &q.x1, &q.z1, &extra) != 4) {
      return fail(make_error(ErrorCode::kUsage, "--region '" + region + "' is not x0,z0,x1,z1"));
    }
    q.width = width;
    q.height = height;
    q.time = time;
    q.caustics = caustics;
    q.pixel_samples = pixel_samples;
    auto img = (*renderer)->render_irradiance(q);
    if (!img) return fail(img.error());
    for (float v : img->rgb) {
      if (!std::isfinite(v)) return fail(make_error(ErrorCode::kInternal, "non-finite irradiance rendered"));
    }
    // The world rectangle and normalisation travel with the image, so that
    // caustix-compare can state positions in metres.
    char rect[160];
    std::snprintf(rect, sizeof rect, "%.9g,%.9g,%.9g,%.9g", q.x0, q.z0, q.x1, q.z1);
    const std::vector<std::pair<std::string, std::string>> attributes{
        {"caustix:region", rect}, {"caustix:receiver", receiver}, {"caustix:e0", std::to_string(img->e0)},
        {"caustix:method", method}, {"caustix:time", std::to_string(q.time)},
        {"caustix:pixel_samples", std::to_string(q.pixel_samples)},
        {"caustix:wavelength", caustics.wavelength_nm ? std::to_string(*caustics.wavelength_nm) : "rgb"}};
    written = write_float_image(out_path, width, height, 3, img->rgb, attributes);
    if (written && !aux_path.empty()) written = write_float_image(aux_path, width, height, 3, img->aux, attributes);
  } else if (is_float_image_path(out_path)) {
    const FrameParams frame{camera, time, width, height, caustics, look, view_options, display, supersample, sky_model};
    if (Status st = (*renderer)->render(frame); !st) return fail(st.error());
    const std::vector<float> rgba = (*renderer)->read_hdr();
    std::vector<float> rgb;
    rgb.reserve(rgba.size() / 4 * 3);
    std::size_t non_finite = 0;
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
      for (std::size_t k = 0; k < 3; ++k) {
        non_finite += std::isfinite(rgba[i + k]) ? 0 : 1;
        rgb.push_back(rgba[i + k]);
      }
    }
    if (non_finite > 0) {
      return fail(make_error(ErrorCode::kInternal, std::to_string(non_finite) + " non-finite pixel values rendered"));
    }
    written = write_float_image(out_path, width, height, 3, rgb);
  } else {
    const FrameParams frame{camera, time, width, height, caustics, look, view_options, display, supersample, sky_model};
    if (Status st = (*renderer)->render(frame); !st) return fail(st.error());
    const std::vector<std::uint8_t> rgba = (*renderer)->read_display();
    std::vector<std::uint8_t> rgb;
    rgb.reserve(rgba.size() / 4 * 3);
    for (std::size_t i = 0; i < rgba.size(); i += 4) rgb.insert(rgb.end(), {rgba[i], rgba[i + 1], rgba[i + 2]});
    written = write_u8_image(out_path, width, height, 3, rgb);
  }
  if (!written) return fail(written.error());
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const CausticsStats cs = (*renderer)->caustics_stats(verbose);
  for (const std::string& w : cs.warnings) std::fprintf(stderr, "caustix-render: warning: %s\n", w.c_str());
  if (verbose) {
    std::printf("renderer: %s\n", (*context)->description().c_str());
    std::printf("caustics map %u^2, glass textures %u^2, %u glass planes (%s)\n", caustics.map_size,
                caustics.glass_map_size, caustics.glass_planes,
                scene->desc.render ? ("preset '" + scene->desc.render->preset + "' recorded in the file").c_str()
                                   : "built-in defaults");
    std::printf("caustics (%s): %llu planes drawn, %llu of %llu illumination volumes after culling\n", method.c_str(),
                static_cast<unsigned long long>(cs.planes_drawn), static_cast<unsigned long long>(cs.volumes_drawn),
                static_cast<unsigned long long>(cs.volumes_total));
    const CausticsTexels& tx = cs.texels;
    std::printf("caustics maps: %u, %.1f MB, finest texel %.2f mm (coarsened %.2fx by the budget), at least %u texels a side, "
                "%u unreachable; light side %.1f MB of a %.1f MB budget%s\n",
                tx.maps, static_cast<double>(tx.map_bytes) / 1e6, tx.texel * 1e3, tx.coarsened, tx.least_side, tx.unreachable,
                static_cast<double>(tx.light_side) / 1e6, static_cast<double>(tx.budget) / 1e6, tx.over_budget ? " (over)" : "");
    const GpuMemory& m = cs.memory;
    auto mb = [](std::uint64_t b) { return static_cast<double>(b) / 1e6; };
    std::printf("engine GPU memory %.1f MB: level maps %.1f, shadow maps %.1f, glass %.1f, caustic maps %.1f, media %.1f, "
                "water %.1f, views %.1f, meshes %.1f, other %.2f\n",
                mb(m.total()), mb(m.level_maps), mb(m.shadow_maps), mb(m.glass), mb(m.caustic_maps), mb(m.media), mb(m.water),
                mb(m.views), mb(m.meshes), mb(m.other));
    const CausticMapStats cm = (*renderer)->engine().caustic_map_stats(true);
    if (cm.active) {
      std::printf("caustic maps (glass: %s): %llu photons, %llu landed (%.6g W), %llu reflections, %llu TIR one-sided, %llu TIR dropped, "
                  "%llu edge, %llu deviation, %llu too far, %llu lost, %llu out of bounces; capture %.2f ms, photons %.2f ms, splat %.2f ms (GPU, last light)\n",
                  glass_method.c_str(), static_cast<unsigned long long>(cm.photons), static_cast<unsigned long long>(cm.landed), cm.landed_power,
                  static_cast<unsigned long long>(cm.reflections), static_cast<unsigned long long>(cm.tir),
                  static_cast<unsigned long long>(cm.tir_dropped), static_cast<unsigned long long>(cm.edge_dropped),
                  static_cast<unsigned long long>(cm.deviation_dropped), static_cast<unsigned long long>(cm.too_far),
                  static_cast<unsigned long long>(cm.lost), static_cast<unsigned long long>(cm.out_of_bounces), cm.capture_ms, cm.photon_ms, cm.splat_ms);
      if (cmap.adaptive_levels > 0) {
        std::printf("adaptive caustic maps: photons per level (cell side in grid texels)");
        for (std::uint32_t k = 0; k <= cmap.adaptive_levels; ++k) {
          std::printf(" %u: %llu", 1u << k, static_cast<unsigned long long>(cm.photons_per_level[k]));
        }
        std::printf("\n");
      }
    }
  }
  if (!quiet) std::printf("caustix-render: wrote %s (%dx%d, t = %g s, %.1f ms)\n", out_path.c_str(), width, height, time, ms);
  return kExitOk;
}
