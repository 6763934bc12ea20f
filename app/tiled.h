#pragma once
// `recon reconstruct` in tiles (tiles.h): when --tile-size asks for it, or
// when the whole cloud would need more memory than --max-memory allows.

#include "command_parts.h"
#include "commands.h"

#include "recon/reconstruct.h"

#include <optional>
#include <string>

namespace recon::cli {

/// Why this run works in tiles ("--tile-size", or the memory estimate), or
/// nothing when it runs in memory as usual. May stream the input once to
/// count its points (only when its size leaves doubt).
[[nodiscard]] std::optional<std::string> tiling_reason(const ReconstructCommandOptions& o,
                                                       const ReconstructionOptions& options);

/// The tiled run: streams the input into tiles under --tmpdir (default: the
/// output's folder), reconstructs them one after the other and streams the
/// mesh out; the tiles are removed at the end, on errors and on Ctrl-C.
void run_tiled(const ReconstructCommandOptions& o, const ReconstructionOptions& options, const std::string& why,
               const GlobalOptions& global);

}  // namespace recon::cli
