#pragma once
// Bake presets: named points on the speed/accuracy trade, chosen from the
// sweeps of docs/tradeoff.md (caustix-bench tradeoff). A preset sets every
// bake knob and the runtime defaults recorded in the .cxb (RNDR chunk);
// caustix-bake --preset NAME applies it, and options given explicitly on
// the command line still win.

#include <span>
#include <string_view>

#include "caustix/bake/bake.h"

namespace caustix::bake {

struct Preset {
  const char* name;
  const char* summary;
  BakeOptions options;  // options.render holds the runtime defaults
};

// fast, balanced, accurate (in that order).
std::span<const Preset> presets();
// nullptr when there is no preset of that name.
const Preset* find_preset(std::string_view name);

}  // namespace caustix::bake
