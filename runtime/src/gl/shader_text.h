#pragma once
// Assembling shader sources from the embedded texts (runtime/shaders/*.glsl
// and the public caustix.glsl). Internal to the runtime.

#include <string>

#include "caustix_shaders.h"

namespace caustix::runtime {

inline constexpr const char* kGlslVersion = "#version 450 core\n";

// #version, then caustix.glsl's Fresnel functions alone, then `main_src`.
inline std::string with_optics(const char* main_src) {
  return std::string(kGlslVersion) + "#define CAUSTIX_OPTICS_ONLY\n" + shaders::k_caustix_glsl + main_src;
}

}  // namespace caustix::runtime
