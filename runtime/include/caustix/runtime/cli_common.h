#pragma once
// Parsing helpers shared by caustix-render and caustix-view.

#include <cstdio>
#include <string>

namespace caustix::runtime {

// "WxH" or "N" (square). Returns false on anything else or sizes outside 1..16384.
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

}  // namespace caustix::runtime
