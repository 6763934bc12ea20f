#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/core/fp_traps.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/fp_traps.h> is deprecated: include <recon/core/fp_traps.h>"
#endif
#include "recon/core/fp_traps.h"
