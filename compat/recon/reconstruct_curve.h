#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/curves/reconstruct_curve.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/reconstruct_curve.h> is deprecated: include <recon/curves/reconstruct_curve.h>"
#endif
#include "recon/curves/reconstruct_curve.h"
