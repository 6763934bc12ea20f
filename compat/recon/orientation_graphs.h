#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/alternatives/orientation_graphs.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/orientation_graphs.h> is deprecated: include <recon/alternatives/orientation_graphs.h>"
#endif
#include "recon/alternatives/orientation_graphs.h"
