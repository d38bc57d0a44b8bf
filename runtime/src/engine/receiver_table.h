#pragma once
// The all-receivers table behind Engine::bind_all(): every
// (receiver, light) pair's LightBlock in one shader-storage buffer, and the
// pairs' textures copied on the GPU into one texture array per kind (the
// twelve of Bindings), each pair's or light's texture a layer with its
// texels in the layer's corner. caustix.glsl's CAUSTIX_ALL_RECEIVERS mode
// reads it. Internal to the runtime.

#include <epoxy/gl.h>

#include <array>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "caustix/common/status.h"
#include "caustix/runtime/engine.h"
#include "gl_objects.h"

namespace caustix::runtime {

class ReceiverTable {
 public:
  static constexpr int kKinds = 12;  // Bindings' texture units, in their order

  // One (object, light) pair as the engine filled it: its block and its
  // textures in Bindings order; `receiver` false for transparent objects.
  struct Pair {
    const ReceiverLighting* lighting = nullptr;
    bool receiver = false;
  };

  // A light's products whose textures the table holds, by the effect that
  // makes them.
  enum Product : int {
    kShadowMaps,    // shadow_2d, shadow_cube, the glass's, the moments
    kLevelMaps,     // caustics, caustics_color
    kGlass,         // glass_illumination, glass_target
    kCausticMaps,   // caustic_map
    kPositionMaps,  // position: re-derived when the light or a transform moved (not with the water)
    kProducts,
  };
  // Per product, a version that changes exactly when the effect making it
  // replaces its texels (LightEffect::product_versions): the table copies
  // again what moved since it last copied.
  using Versions = std::array<std::uint64_t, kProducts>;
  // Brings the table up to date with `pairs` (objects x lights, object
  // major) and `versions` (one per light). Copies the textures of the
  // products whose versions moved since the last refresh, or every one
  // with `everything` (new options may reallocate any product, and GL may
  // hand a freed texture's name to its successor). Lays the arrays out
  // anew when a texture appears, goes or changes size (then copies every
  // layer); otherwise copies only what moved and uploads only the entries
  // that differ. No GPU -> CPU synchronisation.
  Status refresh(std::span<const Pair> pairs, std::span<const Versions> versions, bool everything);
  // Binds the buffer at `b.table` and the arrays at the units (multi-bind:
  // the generic GL_SHADER_STORAGE_BUFFER binding stays).
  void bind(const Bindings& b) const;
  bool built() const { return built_; }
  std::uint64_t gpu_bytes() const;
  // What the last refresh copied and uploaded.
  std::uint32_t copies = 0;
  std::uint64_t copied_bytes = 0;

 private:
  struct Source {
    GLuint texture = 0;
    GLint width = 0, height = 0, layers = 0;  // layers: array layers, or 6 for a cube map
    GLenum format = 0;
  };
  struct Kind {
    gl::Texture array;  // the layers, or a 1 x 1 stand-in
    GLint width = 0, height = 0, layers = 0;
    GLenum format = 0;
    std::vector<GLuint> order;  // the sources in layer order
  };
  Source describe(int kind, GLuint texture) const;

  bool built_ = false;
  std::array<Kind, kKinds> kinds_{};
  std::unordered_map<GLuint, Source> sources_;  // what each source texture was when last described
  std::vector<Versions> copied_;                // per light, the versions of the last refresh
  gl::Buffer buffer_;
  std::vector<ReceiverTableEntry> uploaded_;
};

}  // namespace caustix::runtime
