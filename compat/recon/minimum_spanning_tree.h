#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/phase2_orientation/minimum_spanning_tree.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning \
    "<recon/minimum_spanning_tree.h> is deprecated: include <recon/phase2_orientation/minimum_spanning_tree.h>"
#endif
#include "recon/phase2_orientation/minimum_spanning_tree.h"
