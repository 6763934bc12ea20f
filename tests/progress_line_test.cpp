// app/progress.h: the text of the terminal's progress line (the bar, the
// percentage, the counts, the time left, the form without a total, and how
// it fits a narrow terminal).

#include "progress.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>

namespace recon::cli {
namespace {

ProgressState state(std::string phase, std::uint64_t done, std::uint64_t total, double seconds, std::string unit = {}) {
  ProgressState s;
  s.phase = std::move(phase);
  s.done = done;
  s.total = total;
  s.seconds = seconds;
  s.unit = std::move(unit);
  return s;
}

// What the line shows on a wide terminal (120 columns), case by case.
TEST(ProgressLine, OnAWideTerminal) {
  struct Case {
    const char* what;
    ProgressState state;
    const char* line;
  };
  const Case cases[] = {
      {"the bar, the percentage, the counts; 42.6% done in 52 s: 70 s to go at that rate",
       {"orientation", 1234567, 2900000, 52.0, ""},
       "recon: orientation [########............]  42%  (1234567 / 2900000)  ~1 min 10 s left"},
      {"a unit after the counts",
       {"tiles", 8, 20, 120.0, "tiles"},
       "recon: tiles [########............]  40%  (8 / 20 tiles)  ~3 min left"},
      {"rounded down: only the end shows 100%",
       {"contouring", 999999, 1000000, 10.0, ""},
       "recon: contouring [###################.]  99%  (999999 / 1000000)  ~1 s left"},
      {"the end, with no time left",
       {"contouring", 1000000, 1000000, 10.0, ""},
       "recon: contouring [####################] 100%  (1000000 / 1000000)"},
      {"a count past the total shows as the total",
       {"refinement", 150, 100, 5.0, ""},
       "recon: refinement [####################] 100%  (100 / 100)"},
      {"no time left before anything is done",
       {"orientation", 0, 3000, 20.0, ""},
       "recon: orientation [....................]   0%  (0 / 3000)"},
      {"no time left in the first second",
       {"orientation", 1500, 3000, 0.5, ""},
       "recon: orientation [##########..........]  50%  (1500 / 3000)"},
      {"without a total, the time taken", {"signed distance", 0, 0, 3.24, ""}, "recon: signed distance ... 3.2 s"},
      {"without a total, a count is not shown", {"tiles", 5, 0, 61.0, "tiles"}, "recon: tiles ... 61.0 s"},
  };
  for (const Case& c : cases) EXPECT_EQ(progress_line(c.state, 120), c.line) << c.what;
}

TEST(ProgressLine, FitsANarrowTerminal) {
  const ProgressState tiles = state("tiles", 8, 20, 120.0, "tiles");
  // The bar narrows first ...
  EXPECT_EQ(progress_line(tiles, 70), "recon: tiles [#####.........]  40%  (8 / 20 tiles)  ~3 min left");
  // ... then goes ...
  EXPECT_EQ(progress_line(tiles, 50), "recon: tiles  40%  (8 / 20 tiles)  ~3 min left");
  // ... then the line is cut, one column short of the width (no wrapping).
  EXPECT_EQ(progress_line(tiles, 30), "recon: tiles  40%  (8 / 20 ti");
  EXPECT_EQ(progress_line(state("signed distance", 0, 0, 3.0), 20), "recon: signed dista");
}

TEST(ProgressLine, TheBarKeepsItsWidthAsTheCountsAndTheTimeLeftChange) {
  const std::string early = progress_line(state("tangent planes", 5, 2000000, 0.5), 80);
  const std::string later = progress_line(state("tangent planes", 1500000, 2000000, 75.0), 80);
  EXPECT_EQ(later, "recon: tangent planes [########...]  75%  (1500000 / 2000000)  ~25 s left");
  EXPECT_EQ(early.find(']'), later.find(']'));
  EXPECT_LE(progress_line(state("tangent planes", 1000, 2000000, 7000.0), 80).size(), 79u);  // ~3 h 53 min left
}

TEST(ProgressLine, TimeLeftIsRoundedToWhatAPersonPlansBy) {
  EXPECT_EQ(time_left_text(0.2), "~1 s left");
  EXPECT_EQ(time_left_text(42.4), "~42 s left");
  EXPECT_EQ(time_left_text(59.6), "~1 min left");
  EXPECT_EQ(time_left_text(70.0), "~1 min 10 s left");
  EXPECT_EQ(time_left_text(125.0), "~2 min 10 s left");  // to 10 s under 10 minutes
  EXPECT_EQ(time_left_text(599.0), "~10 min left");
  EXPECT_EQ(time_left_text(1500.0), "~25 min left");
  EXPECT_EQ(time_left_text(3599.0), "~1 h left");
  EXPECT_EQ(time_left_text(7500.0), "~2 h 5 min left");
}

}  // namespace
}  // namespace recon::cli
