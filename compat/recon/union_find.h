#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/structures/union_find.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/union_find.h> is deprecated: include <recon/structures/union_find.h>"
#endif
#include "recon/structures/union_find.h"
