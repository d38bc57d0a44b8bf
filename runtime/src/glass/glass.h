#pragma once
// Caustics from transparent objects on the GPU (Iwasaki et al. §4): per light,
// the outgoing rays of every transparent vertex from its light-transport
// table (glass_rays.comp), the mean transmitted direction, and per target
// (every opaque receiver, for each light) a virtual camera along it with n virtual planes
// across the target's depth; the target's normal/depth map from that
// camera; and per plane an illumination texture, the intersection triangles
// of the illumination volumes accumulated with eq. 3 (glass_geometry.comp,
// glass_illumination.frag, exact-coverage splatting as for water).
// Internal to the runtime.

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/formats/level_map.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"
#include "gl_objects.h"
#include "exit_ray.h"
#include "made_from.h"
#include "scene_inputs.h"
#include "view_spectrum.h"
#include "gpu_mesh.h"

namespace caustix::runtime {

class GlassEngine {
 public:
  // `meshes` are the scene's GPU meshes (by mesh index) and must outlive the
  // engine; `cpu_meshes` the same on the CPU (read during the call). draw_object(i) issues object i's draw call. `lighting_prefix`
  // is #version plus caustix.glsl with the engine's bindings (the rays read
  // the light's block and shadow maps).
  // `spectral` are dispersive objects' tables at other wavelengths (LTTS).
  static Result<std::unique_ptr<GlassEngine>> create(const SceneDesc& scene,
                                                     const std::vector<LightTransportTable>& tables,
                                                     const std::vector<LightTransportTable>& spectral,
                                                     const std::vector<GpuMesh>& meshes,
                                                     const std::vector<TriangleMesh>& cpu_meshes,
                                                     std::function<void(std::uint32_t)> draw_object,
                                                     const std::string& lighting_prefix);
  ~GlassEngine();

  // Illumination textures of `light` for every target, for the current
  // transforms. set_light(p) must bind the light's block and shadow maps
  // and set its u_light_* uniforms on p: the rays use them for the glass
  // vertices' visibility. world_vertices[i] are object i's vertices in
  // world space. Dispersive glass with tables at other wavelengths traces
  // options.wavelengths bins (or options.wavelength_nm), each between the
  // two tables whose indices bracket its own (glass_rays_blend.comp), into
  // the same illumination textures with the bin's RGB weights; else the
  // d line at n_d.
  // Remade only when the light, the transforms or the options changed
  // since (`versions`), and only when `due` unless none exist;
  // counted into `work`. A glass whose `by_caustic_maps[object]` is set
  // sends no light here (the caustic maps carry it: a receiver inside it,
  // CausticMapEngine::casters()).
  Status update_light(const SceneDesc& scene, std::uint32_t light, const CausticsOptions& options,
                      const std::vector<std::vector<std::array<double, 3>>>& world_vertices,
                      const std::vector<bool>& by_caustic_maps,
                      const std::function<void(const gl::Program&)>& set_light_uniforms, const SceneVersions& versions, bool due,
                      EffectWork& work);

  struct Binding {
    BoundingFrame frame;       // virtual camera: V points back along the mean transmitted direction
    std::vector<float> plane_v;  // plane coordinates along V, decreasing
    GLuint illumination;       // RGBA32F 2D array, one layer per plane
    GLuint target;             // RGBA32F: normal + frame V of the first surface
    float tolerance;           // self-shadow tolerance along V
    // The focus window: centre u, v and half-size in texture
    // coordinates (0: none); its planes are layers plane_v.size() + k.
    std::array<float, 3> focus;
  };
  // The target's textures of `light` from its last update_light(), if any.
  std::optional<Binding> binding(std::uint32_t object, std::uint32_t light) const;

  // A sample of the rays of `light` leaving the glass (the n_d table's
  // rows of every k-th vertex, on the CPU: no GPU work, no wait): what
  // orients the planes and places the focus windows, and the media's
  // focus grids.
  std::vector<ExitRay> exit_sample(const SceneDesc& scene, std::uint32_t light) const;

  // Draws the transparent objects as glass over the opaque scene's colour
  // and depth into the bound draw framebuffer: view rays through the table
  // (Iwasaki et al. §3) or nearby-geometry refraction (GlassView::kNearby), the
  // latter once per wavelength of `spectrum` for dispersive glass.
  // `scene_color` and `scene_depth` in any format gl/scene_inputs.h
  // accepts; `reader` resolves them where they are multisampled.
  // `object_boxes`: every object's world box, for the table view to look
  // for receivers inside a glass object.
  Status draw_glass(const SceneDesc& scene, const glm::mat4& view_proj, const glm::vec3& eye, const glm::vec3& sky,
                    const gl::SceneTexture& scene_color, const gl::SceneTexture& scene_depth, gl::SceneReader& reader,
                    float march_length, const GlassViewOptions& options, const ViewSpectrum& spectrum,
                    const std::vector<std::array<glm::vec3, 2>>& object_boxes);

  // The light side's GPU memory: tables, rays, one-rings, targets,
  // illumination textures, primitives.
  std::uint64_t gpu_bytes() const;
  // How many times light li's illumination textures were made (the
  // receiver table's version).
  std::uint64_t times_made(std::uint32_t li) const;
  // The view's: the back faces (nearby view) and the window over the
  // glass's rectangle of the frame (draw_glass).
  std::uint64_t view_bytes() const;
  // Wavelengths the last update_light() traced (1 without spectral tables).
  std::uint32_t wavelengths() const;

 private:
  GlassEngine() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustix::runtime
