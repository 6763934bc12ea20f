#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/core/memory_budget.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/memory_budget.h> is deprecated: include <recon/core/memory_budget.h>"
#endif
#include "recon/core/memory_budget.h"
