#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/phase4_contour/marching_cubes_table.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning \
    "<recon/marching_cubes_table.h> is deprecated: include <recon/phase4_contour/marching_cubes_table.h>"
#endif
#include "recon/phase4_contour/marching_cubes_table.h"
