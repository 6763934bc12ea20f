#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/core/version.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/version.h> is deprecated: include <recon/core/version.h>"
#endif
#include "recon/core/version.h"
