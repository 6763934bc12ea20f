#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/phase1_planes/local_quadrics.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/local_quadrics.h> is deprecated: include <recon/phase1_planes/local_quadrics.h>"
#endif
#include "recon/phase1_planes/local_quadrics.h"
