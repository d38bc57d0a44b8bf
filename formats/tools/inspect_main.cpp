// caustix-inspect: prints a .cxb's header, chunk table and validation result.
// Exit codes: 0 valid, 2 usage, 3 file unreadable, 4 file invalid.

#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "caustix/common/cli.h"
#include "caustix/formats/container.h"
#include "caustix/formats/file_io.h"
#include "caustix/formats/scene.h"

namespace {

const char* role_name(caustix::Role r) {
  switch (r) {
    case caustix::Role::kReceiver: return "receiver";
    case caustix::Role::kTransparent: return "transparent";
    case caustix::Role::kBoth: return "both";
    case caustix::Role::kMirror: return "mirror";
    case caustix::Role::kThin: return "thin";
  }
  return "?";
}

// A receiver's textures and alpha mode (TEXR, TEXM), e.g. "albedo 256x256
// (alpha), normal 512x512; alpha mask 0.5"; empty for none.
std::vector<std::string> texture_list(const caustix::SceneDesc& s, const caustix::Material& m) {
  std::vector<std::string> out;
  const auto add = [&](const char* slot, const std::optional<caustix::MapTexture>& t) {
    if (!t || t->image >= s.images.size()) return;
    const caustix::TextureImage& im = s.images[t->image];
    out.push_back(std::string(slot) + " " + std::to_string(im.width) + "x" + std::to_string(im.height) + (im.alpha.empty() ? "" : " (alpha)"));
  };
  add("albedo", m.albedo_texture);
  if (m.maps) {
    add("metallic-roughness", m.maps->metallic_roughness);
    add("normal", m.maps->normal);
    add("occlusion", m.maps->occlusion);
    add("emissive", m.maps->emissive);
    if (m.maps->alpha_mode == caustix::AlphaMode::kMask) out.push_back("alpha mask " + std::to_string(m.maps->alpha_cutoff).substr(0, 4));
    if (m.maps->alpha_mode == caustix::AlphaMode::kBlend) out.push_back("alpha blend " + std::to_string(m.maps->alpha).substr(0, 4));
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace caustix;
  CLI::App app{"caustix-inspect: print and validate a .cxb file"};
  std::string path;
  bool as_json = false;
  app.add_option("file", path, "the .cxb file")->required();
  app.add_flag("--json", as_json, "machine-readable output on stdout");
  if (auto rc = cli::parse(app, "caustix-inspect", argc, argv)) return *rc;

  auto bytes = read_file(path);
  if (!bytes) {
    return cli::fail("caustix-inspect", bytes.error());
  }
  cxb::ReadFailure failure = cxb::ReadFailure::kNone;
  auto container = cxb::read_container(bytes->data(), bytes->size(), &failure);
  Result<DecodedScene> scene = container ? decode_scene(*container)
                                         : Result<DecodedScene>(container.error());
  const bool valid = container && scene;
  const std::string error = valid ? "" : (container ? scene.error().message : container.error().message);

  nlohmann::ordered_json j;
  j["file"] = path;
  j["size"] = bytes->size();
  j["valid"] = valid;
  if (!valid) {
    j["error"] = error;
    j["failure"] = cxb::to_string(failure);
  }
  if (container) {
    j["version"] = container->header().version;
    j["chunks"] = nlohmann::json::array();
    for (const auto& ch : container->chunks()) {
      char sum[24];
      std::snprintf(sum, sizeof sum, "%016llx", static_cast<unsigned long long>(ch.checksum));
      j["chunks"].push_back({{"tag", ch.tag.str()},
                             {"required", (ch.flags & cxb::kChunkRequired) != 0},
                             {"known", ch.known},
                             {"offset", ch.offset},
                             {"size", ch.size},
                             {"checksum", sum}});
    }
  }
  if (valid) {
    const SceneDesc& s = scene->scene;
    j["scene"]["name"] = s.name;
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      const Object& o = s.objects[i];
      const MeshInfo& m = s.meshes[o.mesh_index];
      j["scene"]["objects"].push_back({{"name", o.name},
                                       {"role", role_name(o.role)},
                                       {"mesh", m.source},
                                       {"vertices", m.vertex_count},
                                       {"triangles", m.triangle_count},
                                       {"position_bits", m.position_bits},
                                       {"draco_bytes", scene->draco_meshes[o.mesh_index].size()}});
      if (o.tables_from) j["scene"]["objects"].back()["tables_from"] = s.objects[*o.tables_from].name;
      if (const auto t = texture_list(s, o.material); !t.empty()) j["scene"]["objects"].back()["textures"] = t;
    }
    j["scene"]["lights"] = s.lights.size();
    j["scene"]["water"] = s.water.has_value();
    j["scene"]["water_waves"] = s.water ? s.water->waves.size() : 0;
    j["scene"]["camera"] = s.camera.has_value();
    j["scene"]["medium"] = s.medium.has_value();
    j["scene"]["scatters"] = scene_scatters(s);
    if (s.render) {
      j["scene"]["render_defaults"] = {{"preset", s.render->preset},
                                       {"caustics_map_size", s.render->caustics_map_size},
                                       {"glass_map_size", s.render->glass_map_size},
                                       {"glass_planes", s.render->glass_planes}};
    }
    j["level_maps"] = nlohmann::json::array();
    for (const LevelMap& m : scene->level_maps) {
      j["level_maps"].push_back({{"object", s.objects[m.object].name},
                                 {"light", m.light},
                                 {"map_size", m.map_size},
                                 {"levels", m.histogram.size()},
                                 {"planes_uniform", m.uniform_planes.size()},
                                 {"planes_smart", m.smart_planes.size()},
                                 {"slicing", m.slicing == Slicing::kSmart ? "smart" : "uniform"}});
    }
  }

  if (as_json) {
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("%s: %zu bytes\n", path.c_str(), bytes->size());
    if (container) {
      std::printf("format version %u, %zu chunks\n", container->header().version,
                  container->chunks().size());
      std::printf("  %-4s  %-8s  %10s  %10s  %-16s\n", "tag", "flags", "offset", "size", "xxh3-64");
      for (const auto& ch : container->chunks()) {
        std::printf("  %-4s  %-8s  %10llu  %10llu  %016llx%s\n", ch.tag.str().c_str(),
                    (ch.flags & cxb::kChunkRequired) ? "required" : "optional",
                    static_cast<unsigned long long>(ch.offset),
                    static_cast<unsigned long long>(ch.size),
                    static_cast<unsigned long long>(ch.checksum), ch.known ? "" : "  (unknown, skipped)");
      }
    }
    if (valid) {
      const SceneDesc& s = scene->scene;
      std::printf("scene '%s': %zu objects, %zu lights, %s, %s\n", s.name.c_str(), s.objects.size(),
                  s.lights.size(), s.water ? "water" : "no water", s.camera ? "camera" : "no camera");
      for (const Object& o : s.objects) {
        const MeshInfo& m = s.meshes[o.mesh_index];
        std::printf("  %-16s %-11s %-24s %7u vertices %7u triangles %6zu Draco bytes%s\n", o.name.c_str(),
                    role_name(o.role), m.source.c_str(), m.vertex_count, m.triangle_count,
                    scene->draco_meshes[o.mesh_index].size(),
                    o.tables_from ? ("  tables of " + s.objects[*o.tables_from].name).c_str() : "");
        const auto t = texture_list(s, o.material);
        for (std::size_t k = 0; k < t.size(); ++k) std::printf("%s%s", k == 0 ? "    textures: " : ", ", t[k].c_str());
        if (!t.empty()) std::printf("\n");
      }
      if (s.medium) {
        const auto& e = s.medium->extent;
        const auto& ss = s.medium->scattering.coefficient;
        std::printf("medium [%g, %g, %g]-[%g, %g, %g]: scattering %g %g %g /m, absorption %g %g %g /m, %s phase\n",
                    e[0], e[1], e[2], e[3], e[4], e[5], ss[0], ss[1], ss[2], s.medium->absorption[0],
                    s.medium->absorption[1], s.medium->absorption[2],
                    s.medium->scattering.phase == Phase::kSchlick ? "Schlick" : "isotropic");
      }
      if (s.render) {
        std::printf("render defaults (preset '%s'): caustics map %u^2, glass textures %u^2, %u glass planes\n",
                    s.render->preset.c_str(), s.render->caustics_map_size, s.render->glass_map_size,
                    s.render->glass_planes);
      }
      for (const LevelMap& m : scene->level_maps) {
        std::printf("  level map %-16s light %u: %u^2 map, %zu levels, planes uniform %zu / smart %zu (%s in use)\n",
                    s.objects[m.object].name.c_str(), m.light, m.map_size, m.histogram.size(),
                    m.uniform_planes.size(), m.smart_planes.size(), m.slicing == Slicing::kSmart ? "smart" : "uniform");
      }
      std::printf("valid\n");
    } else {
      std::printf("INVALID: %s\n", error.c_str());
    }
  }
  return valid ? kExitOk : kExitContainer;
}
