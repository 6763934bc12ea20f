#include "recon/core/detail/float_chars.h"

#include "recon/core/fp_traps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

// The strtod/snprintf forms the WebAssembly build uses (Emscripten's libc++
// has no floating-point <charconv>) against <charconv>'s own, here where
// both exist: the same text for every double and float printed, the same
// value and the same error for every number read.
namespace recon::detail {
namespace {

// strtod overflows on purpose here (a shortest candidate of 1.8e308 reads
// as infinity, "1e400" must be out of range): the suite's traps
// (RECON_TRAP_FP) are off for these tests, and back on after.
class NoFpTraps {
 public:
  NoFpTraps() : before_(fp_traps_enabled()) { set_fp_traps(false); }
  ~NoFpTraps() { set_fp_traps(before_); }
  NoFpTraps(const NoFpTraps&) = delete;
  NoFpTraps& operator=(const NoFpTraps&) = delete;

 private:
  bool before_;
};

std::string standard(double v) {
  char text[64];
  return {text, std::to_chars(text, text + sizeof text, v).ptr};
}
std::string standard(float v) {
  char text[64];
  return {text, std::to_chars(text, text + sizeof text, v).ptr};
}
template <class T>
std::string portable(T v) {
  char text[64];
  const auto [end, ec] = portable_to_chars(text, text + sizeof text, v);
  EXPECT_EQ(ec, std::errc{});
  return {text, end};
}

// Doubles of every magnitude and bit pattern, and the awkward ones.
std::vector<double> doubles() {
  std::vector<double> out = {0.0,
                             -0.0,
                             1.0,
                             -1.0,
                             0.1,
                             1e-5,
                             1e-4,
                             123456789.0,
                             9e6,
                             1e15,
                             1e16,
                             1e21,
                             1e22,
                             5e-324,
                             2.2250738585072014e-308,
                             1.7976931348623157e308,
                             0.3,
                             2.0 / 3.0,
                             100.0,
                             1234.5};
  std::mt19937_64 random(29);
  for (int i = 0; i < 20000; ++i) {
    const std::uint64_t bits = random();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (std::isfinite(v)) out.push_back(v);
    out.push_back(std::ldexp(static_cast<double>(random() % 1000000), static_cast<int>(random() % 80) - 40));
  }
  return out;
}

TEST(FloatChars, ShortestDoublesAreCharconvs) {
  const NoFpTraps traps;
  for (const double v : doubles()) ASSERT_EQ(portable(v), standard(v)) << v;
  EXPECT_EQ(portable(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(portable(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(FloatChars, ShortestFloatsAreCharconvs) {
  const NoFpTraps traps;
  for (const double d : doubles()) {
    if (!(std::fabs(d) <= static_cast<double>(std::numeric_limits<float>::max()))) continue;
    const float v = static_cast<float>(d);
    ASSERT_EQ(portable(v), standard(v)) << d;
  }
}

TEST(FloatChars, FixedPrecisionIsCharconvs) {
  for (int c = 0; c <= 255; ++c) {
    const double v = c / 255.0;
    char a[32], b[32];
    const auto pa = portable_to_chars(a, a + sizeof a, v, std::chars_format::fixed, 4).ptr;
    const auto pb = std::to_chars(b, b + sizeof b, v, std::chars_format::fixed, 4).ptr;
    ASSERT_EQ(std::string(a, pa), std::string(b, pb)) << c;
  }
}

TEST(FloatChars, TooSmallABufferIsRefused) {
  char text[3];
  EXPECT_EQ(portable_to_chars(text, text + sizeof text, 0.125).ec, std::errc::value_too_large);
}

// Reads `text` both ways: the same end, error and value.
void expect_same_reading(const std::string& text) {
  double a = -7.0, b = -7.0;
  const auto ra = portable_from_chars(text.data(), text.data() + text.size(), a);
  const auto rb = std::from_chars(text.data(), text.data() + text.size(), b);
  EXPECT_EQ(ra.ptr - text.data(), rb.ptr - text.data()) << text;
  EXPECT_EQ(ra.ec, rb.ec) << text;
  if (std::isnan(b)) {
    EXPECT_TRUE(std::isnan(a)) << text;
  } else {
    EXPECT_EQ(a, b) << text;
  }
}

TEST(FloatChars, ReadingIsCharconvs) {
  const NoFpTraps traps;
  for (const char* text : {"0",         "-0",
                           "1.5",       "-2.25e3",
                           "1e400",     "-1e400",
                           "1e-400",    "4.9e-324",
                           "1e-310",    ".5",
                           "5.",        "1e",
                           "1e+",       "1.5x",
                           "+1",        " 1",
                           "",          "-",
                           ".",         "inf",
                           "-Infinity", "nan",
                           "NaN(123)",  "0x1p3",
                           "12,5",      "3.14159265358979323846264338327950288",
                           "1E5",       "123456789012345678901234"})
    expect_same_reading(text);
  for (const double v : doubles()) expect_same_reading(standard(v));
}

}  // namespace
}  // namespace recon::detail
