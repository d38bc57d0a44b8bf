#include "caustix/runtime/caustics_options.h"

namespace caustix::runtime {

const char* to_string(CausticsMethod m) {
  switch (m) {
    case CausticsMethod::kLevelMap: return "levelmap";
    case CausticsMethod::kUniform: return "uniform";
    case CausticsMethod::kVolumetric: return "volumetric";
    case CausticsMethod::kNone: return "none";
  }
  return "?";
}

std::optional<CausticsMethod> parse_method(const std::string& name) {
  for (CausticsMethod m : {CausticsMethod::kLevelMap, CausticsMethod::kUniform, CausticsMethod::kVolumetric, CausticsMethod::kNone}) {
    if (name == to_string(m)) return m;
  }
  return std::nullopt;
}

}  // namespace caustix::runtime
