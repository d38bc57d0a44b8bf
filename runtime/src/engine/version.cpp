#include "caustix/runtime/version.h"

namespace caustix {

const char* version() { return kVersionString; }

Version version_numbers() { return Version{CAUSTIX_VERSION_MAJOR, CAUSTIX_VERSION_MINOR, CAUSTIX_VERSION_PATCH}; }

}  // namespace caustix
