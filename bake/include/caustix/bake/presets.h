#pragma once
// Bake presets: named points on the speed/accuracy trade, chosen from the
// sweeps of docs/tradeoff.md (caustix-bench tradeoff). A preset sets every
// bake knob and the runtime defaults recorded in the .cxb (RNDR chunk);
// caustix-bake --preset NAME applies it, and options given explicitly on
// the command line still win.

#include <functional>
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

// Sets `options` to the preset's value of every knob a preset sets, except
// those `given(flag)` says the command line set (flag: caustix-bake's option
// name, "--planes"); records its runtime defaults. caustix-bake --preset and
// the in-process bakes of caustix-render and caustix-view (bake_cache.h)
// both apply a preset through this, so that they write the same bytes.
void apply_preset(const Preset& preset, BakeOptions& options,
                  const std::function<bool(std::string_view flag)>& given = nullptr);

}  // namespace caustix::bake
