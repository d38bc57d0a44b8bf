#pragma once
// caustix-bench temporal: frame-to-frame stability of the caustics as the
// light, the water or an object moves (docs/temporal.md). The runtime and a
// GL context only.

#include <memory>

#include "bench_common.h"

namespace caustix::bench {

std::unique_ptr<Modes> add_temporal_mode(CLI::App& app);

}  // namespace caustix::bench
