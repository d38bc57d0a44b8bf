#pragma once
// Exit codes of every caustix command-line tool (documented in docs/tools.md).
// Never renumber: build systems and scripts test for them.

#include "caustix/common/status.h"

namespace caustix {

inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;   // bug or unexpected library failure
inline constexpr int kExitUsage = 2;      // bad command line
inline constexpr int kExitInput = 3;      // scene.json or mesh invalid/missing
inline constexpr int kExitContainer = 4;  // .cxb malformed, corrupt, unsupported
inline constexpr int kExitOutput = 5;     // output could not be written
inline constexpr int kExitGraphics = 6;   // no usable OpenGL context / GL error
inline constexpr int kExitBudget = 7;     // stopped by a --max-seconds / --max-memory budget

inline int exit_code_for(const Error& e) { return static_cast<int>(e.code); }

}  // namespace caustix
