#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/core/operation_counts.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/operation_counts.h> is deprecated: include <recon/core/operation_counts.h>"
#endif
#include "recon/core/operation_counts.h"
