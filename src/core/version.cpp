#include "recon/core/version.h"

// RECON_VERSION_STRING, written into the build folder at build time
// (cmake/recon_version.cmake): only this file recompiles when it changes.
#include "recon_version_string.h"

namespace recon {

std::string_view version() noexcept { return RECON_VERSION_STRING; }

}  // namespace recon
