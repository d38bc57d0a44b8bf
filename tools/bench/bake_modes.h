#pragma once
// caustix-bench subcommands: bake-stages, table-5-4, ltt, raycast, tradeoff: the baker, CGAL, Embree, OpenImageIO.

#include <memory>

#include "bench_common.h"

namespace caustix::bench {

std::unique_ptr<Modes> add_bake_modes(CLI::App& app);

}  // namespace caustix::bench
