#pragma once
// What each light's light-side product was made from (docs/embedding.md,
// "What a frame costs"): every effect keeps one record per light and
// remakes a product only when what it depends on changed -- its light, the
// objects' transforms, the water's surface, the options it reads -- or
// never made it. The Engine numbers the changes (versions); each effect
// says which it depends on through its own Key. Each record also counts
// how many times its product was made: the version the receiver table
// reads to know which textures to copy again. Internal to the runtime.

#include <cstdint>
#include <optional>
#include <vector>

#include "caustix/runtime/caustics_options.h"
#include "caustix/runtime/stats.h"

namespace caustix::runtime {

// Versions of what can change between frames, bumped by the Engine.
struct SceneVersions {
  std::uint64_t light = 0;       // this light (Engine::set_light)
  std::uint64_t transforms = 0;  // any object's transform (Engine::set_object_transform)
  std::uint64_t water = 0;       // the water's surface (WaterSurface::version)
  bool operator==(const SceneVersions&) const = default;
};

// What most products depend on: the versions (those of them the effect
// reads) and the options.
struct LightInputs {
  SceneVersions versions;
  CausticsOptions options;
  bool operator==(const LightInputs&) const = default;
};

// What update() does with one light's product this frame.
enum class Refresh {
  kRemake,  // out of date (or never made), and due
  kReuse,   // made from what is current
  kDefer,   // out of date, but not due (FrameUpdate::light_side_interval): kept
};

template <typename Key>
class MadeFrom {
 public:
  void resize(std::size_t lights) {
    keys_.resize(lights);
    times_made_.resize(lights);
  }
  // Decides light li's refresh and counts it into `work`; kRemake expects
  // the caller to remake it and then call made(li, key).
  Refresh decide(std::uint32_t li, const Key& key, bool due, EffectWork& work) const {
    if (keys_[li] == key) {
      ++work.reused;
      return Refresh::kReuse;
    }
    if (!due && keys_[li]) {
      ++work.deferred;
      return Refresh::kDefer;
    }
    ++work.updated;
    return Refresh::kRemake;
  }
  void made(std::uint32_t li, const Key& key) {
    keys_[li] = key;
    ++times_made_[li];
  }
  // How many times light li's product was made: it changes exactly when
  // the product's texels were replaced.
  std::uint64_t times_made(std::uint32_t li) const { return li < times_made_.size() ? times_made_[li] : 0; }
  void forget(std::uint32_t li) { keys_[li].reset(); }
  void forget_all() {
    for (auto& k : keys_) k.reset();
  }

 private:
  std::vector<std::optional<Key>> keys_;
  std::vector<std::uint64_t> times_made_;
};

}  // namespace caustix::runtime
