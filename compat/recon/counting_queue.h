#pragma once
// Deprecated path (recon 0.1): the header moved to <recon/alternatives/counting_queue.h> when the
// sources were arranged by phase. Define RECON_ALLOW_OLD_HEADERS to include
// it here without the warning.
#ifndef RECON_ALLOW_OLD_HEADERS
#pragma GCC warning "<recon/counting_queue.h> is deprecated: include <recon/alternatives/counting_queue.h>"
#endif
#include "recon/alternatives/counting_queue.h"
