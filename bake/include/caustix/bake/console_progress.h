#pragma once
// What a bake says while it runs, on stderr, as caustix-bake and the
// in-process bakes of caustix-render and caustix-view say it: warnings as
// they are found ("TOOL: warning: ..."); on a terminal one progress line
// rewritten in place (stage, item, percentage, estimated time left),
// elsewhere (a build log) a plain line as each item starts and at each
// further tenth of a stage that has run a second; with `verbose` each
// stage's time as it ends. Nothing but warnings' record with `quiet`. It
// also keeps what a failed bake's --report needs (BakeLog).

#include <chrono>
#include <string>

#include "caustix/bake/bake.h"

namespace caustix::bake {

class ConsoleProgress {
 public:
  ConsoleProgress(std::string tool, bool quiet, bool verbose);

  void warning(const std::string& w);
  void progress(const std::string& stage, const std::string& item, double fraction);
  // Before anything else goes to the terminal.
  void clear_line();
  // Calls this object's warning() and progress(): it must outlive the bake.
  BakeObserver observer();
  const BakeLog& log() const { return log_; }

 private:
  using Clock = std::chrono::steady_clock;
  std::string tool_;
  bool quiet_, verbose_, tty_, shown_ = false;
  int tenth_ = 0;
  Clock::time_point stage_start_ = Clock::now();
  BakeLog log_;
};

}  // namespace caustix::bake
