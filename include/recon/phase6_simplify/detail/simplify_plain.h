#pragma once
// Phase VI's reference loop (simplification.h), not part of the API: the
// same rules and the same binary heap as simplify(), with none of its
// speed-ups: every re-costing gathers the vertex's ring again, every key is
// set again, one thread. The tests hold simplify() to it, mesh for mesh,
// so that a cache that misses a change shows as a different mesh.
// Same throws and preconditions as simplify(); options.queue is ignored.
// Cost: the first round's (3.4 s for 973,520 triangles to a tenth).

#include "recon/phase6_simplify/simplification.h"

namespace recon::detail {

[[nodiscard]] Simplification simplify_plain(const Mesh& mesh, const SimplifyOptions& options);

}  // namespace recon::detail
