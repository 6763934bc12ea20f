#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/alternatives/uniform_grid.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/uniform_grid.h> is deprecated: include <recon/alternatives/uniform_grid.h>"
#endif
#include "recon/alternatives/uniform_grid.h"
