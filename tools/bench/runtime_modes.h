#pragma once
// caustix-bench subcommands: frames, methods, water: the runtime and a GL context only.

#include <memory>

#include "bench_common.h"

namespace caustix::bench {

std::unique_ptr<Modes> add_runtime_modes(CLI::App& app);

}  // namespace caustix::bench
