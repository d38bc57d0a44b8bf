#pragma once
// What every caustix command-line tool does the same way: parse with CLI11
// (help and version exit 0, any parse error exits 2 with CLI11's message),
// report errors on stderr as "TOOL: error: MESSAGE" with the documented exit
// code, and read image sizes. Include only from tools (needs CLI11).

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "caustix/common/exit_codes.h"
#include "caustix/common/version.h"

namespace caustix::cli {

// Adds --version; parses. Returns the exit code when the tool should stop now.
inline std::optional<int> parse(CLI::App& app, const std::string& tool, int argc, char** argv) {
  app.set_version_flag("--version", tool + " " + kVersionString);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  return std::nullopt;
}

inline int fail(const std::string& tool, const Error& e) {
  std::cerr << tool << ": error: " << e.message << "\n";
  return exit_code_for(e);
}

// "WxH" or "N" (square), sides in 1..16384.
inline bool parse_size(const std::string& s, int& w, int& h) {
  int a = 0, b = 0;
  char x = 0, extra = 0;
  const int n = std::sscanf(s.c_str(), "%d%c%d%c", &a, &x, &b, &extra);
  if (n == 1) b = a;
  else if (!(n == 3 && (x == 'x' || x == 'X'))) return false;
  if (a < 1 || b < 1 || a > 16384 || b > 16384) return false;
  w = a;
  h = b;
  return true;
}

// A --size option checked while parsing (so a bad size is a usage error).
inline CLI::Option* add_size_option(CLI::App& app, const std::string& name, std::string& value,
                                    const std::string& help) {
  return app.add_option(name, value, help + " (WxH or N, sides 1..16384)")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& s) {
            int w = 0, h = 0;
            return parse_size(s, w, h) ? std::string() : "'" + s + "' is not WxH or N with sides in 1..16384";
          },
          "SIZE"));
}

}  // namespace caustix::cli
