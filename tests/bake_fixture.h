#pragma once
// Bake a scene and load the bytes as the runtime does, for tests that render
// (the baker's and the loader's errors become test failures).

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>

#include "caustix/bake/bake.h"
#include "caustix/sample/renderer.h"
#include "caustix/runtime/scene_loader.h"

namespace caustix::test {

// The scene of `scene_path` baked with `options`; nothing on failure.
inline std::optional<runtime::RuntimeScene> bake_and_load(const std::string& scene_path,
                                                          const bake::BakeOptions& options = {}) {
  auto baked = bake::bake_scene(scene_path, options);
  if (!baked.ok()) {
    ADD_FAILURE() << baked.error().message;
    return std::nullopt;
  }
  auto loaded = runtime::load_scene(baked->cxb.data(), baked->cxb.size());
  if (!loaded.ok()) {
    ADD_FAILURE() << loaded.error().message;
    return std::nullopt;
  }
  return std::move(*loaded);
}

// A renderer of that scene (needs a current GL context); null on failure.
inline std::unique_ptr<sample::Renderer> bake_and_create(const std::string& scene_path,
                                                          const bake::BakeOptions& options = {}) {
  auto scene = bake_and_load(scene_path, options);
  if (!scene) return nullptr;
  auto r = sample::Renderer::create(*scene);
  if (!r.ok()) {
    ADD_FAILURE() << r.error().message;
    return nullptr;
  }
  return std::move(*r);
}

}  // namespace caustix::test
