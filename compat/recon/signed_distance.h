#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/phase3_distance/signed_distance.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/signed_distance.h> is deprecated: include <recon/phase3_distance/signed_distance.h>"
#endif
#include "recon/phase3_distance/signed_distance.h"
