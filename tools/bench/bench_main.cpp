// caustix-bench: measurements behind docs/ (not timed tests). The
// subcommands live in runtime_modes.cpp (frames, methods, water), temporal.cpp and
// bake_modes.cpp (bake-stages, table-5-4, ltt, raycast, tradeoff); a
// CAUSTIX_PARTS=runtime build has only the former.

#include <CLI/CLI.hpp>

#include <memory>
#include <vector>

#include "caustix/common/cli.h"
#include "caustix/common/exit_codes.h"
#include "runtime_modes.h"
#include "temporal.h"
#if CAUSTIX_BENCH_BAKE_MODES
#include "bake_modes.h"
#endif

int main(int argc, char** argv) {
  using namespace caustix;
  CLI::App app{"caustix-bench: measurements for docs/"};
  app.require_subcommand(1);
  std::vector<std::unique_ptr<bench::Modes>> groups;
  groups.push_back(bench::add_runtime_modes(app));
  groups.push_back(bench::add_temporal_mode(app));
#if CAUSTIX_BENCH_BAKE_MODES
  groups.push_back(bench::add_bake_modes(app));
#endif
  if (auto rc = cli::parse(app, "caustix-bench", argc, argv)) return *rc;
  for (auto& g : groups) {
    if (g->chosen()) return g->run();
  }
  return kExitUsage;
}
