#pragma once
// The version of the caustix library an application links, beside the one
// its headers declare (CAUSTIX_VERSION_MAJOR/MINOR/PATCH). A program can
// refuse to run against a library whose major version differs from the one
// it was built with: docs/embedding.md ("Versioning") says what changes it.

#include "caustix/common/version.h"

namespace caustix {

struct Version {
  int major = 0, minor = 0, patch = 0;
};

// "MAJOR.MINOR.PATCH" of the linked library.
const char* version();
Version version_numbers();

}  // namespace caustix
