#pragma once
// Shadow maps per light, for the casting of every light mode (the GLSL
// include's caustix_shadow_visibility): a 2048^2 depth map along the light's
// direction below the water (directional lights) or a 1024^2 distance cube
// (point lights), of the opaque objects, and with transparent objects in the
// scene a second one of the glass alone (the direct light it takes away;
// its light comes back through the illumination textures). Created only for
// the light kinds and objects the scene has. With variance shadow maps
// (ShadowOptions::filter kVsm, directional lights) each depth map also
// gives a map of its filtered moments (shadow_vsm.comp), made the first
// time they are asked for. Internal to the runtime.

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "caustix/common/status.h"
#include "caustix/formats/scene.h"
#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"
#include "gl_objects.h"
#include "made_from.h"

namespace caustix::runtime {

class ShadowMaps {
 public:
  static constexpr int kSize = 2048;
  static constexpr int kCubeSize = 1024;

  // draw_object(i) issues object i's draw call with u_model set by the caller of draw_casters.
  static Result<ShadowMaps> create(const SceneDesc& scene, std::function<void(std::uint32_t)> draw_object);
  // The options' ranges (a usage error naming the field).
  static Status check(const ShadowOptions& options);

  // Renders light `li`'s maps; `center`, `radius` bound the scene. Only
  // when the light, the transforms (`versions`) or the options changed
  // since they were last rendered, or when `due` is false and they exist
  //; counted into `work`.
  void render(const SceneDesc& scene, std::uint32_t li, const glm::vec3& center, float radius, const ShadowOptions& options,
              const SceneVersions& versions, bool due, EffectWork& work);

  struct Maps {
    GLuint opaque_2d, opaque_cube, glass_2d, glass_cube;  // valid textures (1x1 where unused)
    GLuint opaque_vsm, glass_vsm;                         // RG32F moments (1x1 where unused)
    bool vsm = false;                                     // the moments are this light's shadows
    glm::mat4 world_to_shadow{1.0f};                      // directional
    float far = 1.0f;                                     // point: distance / far is stored
    float texel = 0.0f;                                   // directional: world size of a texel
  };
  Maps maps(std::uint32_t li) const;

  // The direction light travels when it reaches underwater receivers.
  static glm::vec3 travel_direction(const SceneDesc& scene, const Light& l);

  std::uint64_t gpu_bytes() const;
  // How many times light li's maps were made (the receiver table's version).
  std::uint64_t times_made(std::uint32_t li) const { return made_.times_made(li); }

 private:
  struct PerLight {
    gl::Texture opaque, glass;
    gl::Texture opaque_vsm, glass_vsm;
    bool vsm = false;
    glm::mat4 world_to_shadow{1.0f};
    float far = 1.0f, texel = 0.0f;
    bool point = false;
  };
  glm::mat4 render_directional(const SceneDesc& scene, const glm::vec3& dir, GLuint target, bool glass_only,
                               const glm::vec3& center, float radius);
  float render_point(const SceneDesc& scene, const Light& light, GLuint target, bool glass_only, const glm::vec3& center,
                     float radius);
  void draw_casters(const SceneDesc& scene, bool glass_only) const;
  // The moments of `depth` into `moments`, box-filtered `width` texels.
  void filter_moments(GLuint depth, GLuint moments, std::uint32_t width);

  std::function<void(std::uint32_t)> draw_object_;
  gl::Program program_, vsm_program_;
  gl::Texture vsm_scratch_, dummy_vsm_;
  gl::Framebuffer fbo_;
  std::vector<PerLight> lights_;
  struct Key {
    SceneVersions versions;
    ShadowOptions options;
    bool operator==(const Key&) const = default;
  };
  MadeFrom<Key> made_;
  gl::Texture dummy_2d_, dummy_cube_;
  bool glass_ = false;
  std::uint64_t bytes_ = 0;
};

}  // namespace caustix::runtime
