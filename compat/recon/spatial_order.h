#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/structures/spatial_order.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/spatial_order.h> is deprecated: include <recon/structures/spatial_order.h>"
#endif
#include "recon/structures/spatial_order.h"
