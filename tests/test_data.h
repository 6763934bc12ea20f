#pragma once
// Where the tests find the shared real-data folder, and how they skip
// when it is absent (people outside this workplace do not have it).

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace recon::testing {

inline std::filesystem::path shared_data(const std::string& relative) {
  return std::filesystem::path(RECON_SHARED_DATA_DIR) / relative;
}

}  // namespace recon::testing

/// Skips the current test with a clear message when a shared data file is missing.
#define RECON_REQUIRE_DATA(path)                                                                \
  do {                                                                                          \
    if (!std::filesystem::exists(path))                                                         \
      GTEST_SKIP() << "real data not available: " << (path).string()                            \
                   << " (the ../shared/data folder of the recon workplace; skipped elsewhere)"; \
  } while (0)
