#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/phase6_simplify/simplification.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/simplification.h> is deprecated: include <recon/phase6_simplify/simplification.h>"
#endif
#include "recon/phase6_simplify/simplification.h"
