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

// `src` (which starts with its #version line) with `text` (e.g. #defines)
// after that line.
inline std::string insert_after_version(const char* src, const std::string& text) {
  std::string s(src);
  const auto eol = s.find('\n');
  return s.substr(0, eol + 1) + text + s.substr(eol + 1);
}

}  // namespace caustix::runtime
