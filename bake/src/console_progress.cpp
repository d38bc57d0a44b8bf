#include "caustix/bake/console_progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace caustix::bake {

ConsoleProgress::ConsoleProgress(std::string tool, bool quiet, bool verbose)
    : tool_(std::move(tool)), quiet_(quiet), verbose_(verbose), tty_(isatty(fileno(stderr)) != 0) {}

void ConsoleProgress::warning(const std::string& w) {
  log_.warnings.push_back(w);
  if (quiet_) return;
  clear_line();
  std::fprintf(stderr, "%s: warning: %s\n", tool_.c_str(), w.c_str());
}

void ConsoleProgress::progress(const std::string& stage, const std::string& item, double fraction) {
  const auto now = Clock::now();
  const bool new_stage = stage != log_.stage;
  if (new_stage) {
    log_.stage = stage;
    stage_start_ = now;
    tenth_ = 0;
  }
  const double seconds = std::chrono::duration<double>(now - stage_start_).count();
  if (fraction >= 1.0) {
    log_.stages_done.emplace_back(stage, seconds);
    log_.stage.clear();
    log_.item.clear();
    clear_line();
    if (verbose_ && !quiet_) std::fprintf(stderr, "%s: %s: %.2f s\n", tool_.c_str(), stage.c_str(), seconds);
    return;
  }
  const bool new_item = new_stage || item != log_.item;
  log_.item = item;
  if (quiet_) return;
  std::string eta;
  if (fraction >= 0.02 && seconds >= 1.0) {
    eta = ", about " + std::to_string(static_cast<long>(std::lround(seconds * (1.0 - fraction) / fraction))) + " s left";
  }
  const std::string line =
      stage + (item.empty() ? "" : ": " + item) + " " + std::to_string(static_cast<int>(fraction * 100.0)) + " %" + eta;
  if (tty_) {
    std::fprintf(stderr, "\r\033[K%s: %s", tool_.c_str(), line.c_str());
    std::fflush(stderr);
    shown_ = true;
  } else if (new_item || (seconds >= 1.0 && static_cast<int>(fraction * 10.0) > tenth_)) {
    std::fprintf(stderr, "%s: %s\n", tool_.c_str(), line.c_str());
  }
  tenth_ = std::max(tenth_, static_cast<int>(fraction * 10.0));
}

void ConsoleProgress::clear_line() {
  if (!shown_) return;
  std::fputs("\r\033[K", stderr);
  shown_ = false;
}

BakeObserver ConsoleProgress::observer() {
  BakeObserver o;
  o.warning = [this](const std::string& w) { warning(w); };
  o.progress = [this](const std::string& stage, const std::string& item, double f) { progress(stage, item, f); };
  return o;
}

}  // namespace caustix::bake
