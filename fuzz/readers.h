#pragma once
// The reader entry points the fuzz targets call, by name. Kept apart from
// the targets so that Eigen and the reader declarations are compiled once
// (readers.cpp), not once per target: the CI fuzz step builds in seconds.

#include <string_view>

namespace recon::fuzz {

/// Reads `content` as a whole file with one reader; a recon::Error (the
/// answer to a bad file) is caught, anything else escapes.
using Reader = void (*)(std::string_view content);

/// The reader named "ply_points", "obj_mesh", ... (see CMakeLists.txt);
/// nullptr for an unknown name.
[[nodiscard]] Reader reader_named(std::string_view name);

}  // namespace recon::fuzz
