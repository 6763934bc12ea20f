#pragma once
// recon's version, the one string that the program (--version), the Python
// package (recon.__version__, the wheel), every --stats JSON and the HTML
// report show, so that a bug report says exactly what ran.

#include <string_view>

namespace recon {

/// The version of this build: the CMake project's VERSION, plus the git
/// commit when built from a checkout, as "0.1.0" (a release: its tag
/// v0.1.0, or a tarball without git), "0.1.0+g1a2b3c4" (another commit) or
/// "0.1.0+g1a2b3c4.dirty" (uncommitted changes). A valid PEP 440 version.
/// Made at build time by cmake/recon_version.cmake (docs/releasing.md).
/// Cost: O(1) (a constant).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] std::string_view version() noexcept;

}  // namespace recon
