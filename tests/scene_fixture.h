#pragma once
// Canonical scenes for tests that edit them: the scene's JSON with absolute
// mesh and texture paths, so an edited copy can be written anywhere and still bake.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace caustix::test {

inline const std::string kScenes = std::string(CAUSTIX_SOURCE_DIR) + "/assets/scenes/";

inline nlohmann::json canonical_scene(const std::string& name) {
  std::ifstream f(kScenes + name + ".json");
  nlohmann::json j = nlohmann::json::parse(f);
  for (auto& o : j["objects"]) {
    o["mesh"] = kScenes + o["mesh"].get<std::string>();
    if (!o.contains("material") || !o["material"].contains("albedo_texture")) continue;
    auto& t = o["material"]["albedo_texture"];  // a file name, or an object naming one
    auto& file = t.is_string() ? t : t["file"];
    file = kScenes + file.get<std::string>();
  }
  return j;
}

// Writes `j` as <temp>/caustix_<tag>.json and returns the path.
inline std::string write_scene(const nlohmann::json& j, const std::string& tag) {
  const auto path = std::filesystem::temp_directory_path() / ("caustix_" + tag + ".json");
  std::ofstream(path) << j.dump();
  return path.string();
}

}  // namespace caustix::test
