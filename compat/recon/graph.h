#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/structures/graph.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/graph.h> is deprecated: include <recon/structures/graph.h>"
#endif
#include "recon/structures/graph.h"
