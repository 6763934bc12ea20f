#include "progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <sys/ioctl.h>
#include <unistd.h>

namespace recon::cli {
namespace {

constexpr std::size_t widest_bar = 20, narrowest_bar = 5;
// Room kept for the time left ("  ~1 min 10 s left") when the bar is sized,
// so that the bar keeps its width as the time left changes.
constexpr std::size_t time_left_room = 18;

std::string one_decimal(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", value);
  return text;
}

// "[########............]": done / total of `width` characters.
std::string bar(std::uint64_t done, std::uint64_t total, std::size_t width) {
  const double share = static_cast<double>(done) / static_cast<double>(total);
  const auto filled = std::min(width, static_cast<std::size_t>(share * static_cast<double>(width)));
  return "[" + std::string(filled, '#') + std::string(width - filled, '.') + "]";
}

// " 42%": rounded down, so 100% means done.
std::string percent(std::uint64_t done, std::uint64_t total) {
  auto whole = static_cast<int>(100.0 * static_cast<double>(done) / static_cast<double>(total));
  if (done < total) whole = std::min(whole, 99);
  char text[8];
  std::snprintf(text, sizeof text, "%3d%%", whole);
  return text;
}

// The counted form's parts after the bar: " 42%  (1234 / 2900 tiles)".
std::string counts(std::uint64_t done, const ProgressState& state) {
  std::string text = percent(done, state.total) + "  (" + std::to_string(done) + " / " + std::to_string(state.total);
  if (!state.unit.empty()) text += " " + state.unit;
  return text + ")";
}

// "  ~1 min 10 s left" at the rate so far, or nothing in the first second,
// while nothing is done, and once everything is.
std::string time_left(std::uint64_t done, const ProgressState& state) {
  if (!(state.seconds >= 1.0) || done == 0 || done >= state.total) return {};
  const double rate = static_cast<double>(done) / state.seconds;
  return "  " + time_left_text(static_cast<double>(state.total - done) / rate);
}

// The terminal's width in columns, or 80 when it does not say.
std::size_t terminal_width() {
  winsize size{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  return 80;
}

}  // namespace

std::string time_left_text(double seconds) {
  const auto s = std::max<long long>(1, std::llround(seconds));
  std::string text;
  if (s < 60) {
    text = std::to_string(s) + " s";
  } else if (s < 600) {  // to 10 s
    const long long tens = (s + 5) / 10 * 10;
    text = std::to_string(tens / 60) + " min";
    if (tens % 60 != 0) text += " " + std::to_string(tens % 60) + " s";
  } else if (const long long minutes = (s + 30) / 60; minutes < 60) {
    text = std::to_string(minutes) + " min";
  } else {
    text = std::to_string(minutes / 60) + " h";
    if (minutes % 60 != 0) text += " " + std::to_string(minutes % 60) + " min";
  }
  return "~" + text + " left";
}

std::string progress_line(const ProgressState& state, std::size_t width) {
  const std::size_t room = width > 0 ? width - 1 : 0;
  std::string line = "recon: " + state.phase;
  if (state.total == 0) {
    line += " ... " + one_decimal(state.seconds) + " s";
  } else {
    const std::uint64_t done = std::min(state.done, state.total);
    // The bar as wide as the room left by the widest counts (done as long
    // as the total) and the time left allows, with its brackets and a space.
    const std::size_t used = line.size() + 1 + counts(state.total, state).size() + time_left_room;
    if (room >= used + narrowest_bar + 3) line += " " + bar(done, state.total, std::min(widest_bar, room - used - 3));
    line += " " + counts(done, state) + time_left(done, state);
  }
  if (line.size() > room) line.resize(room);
  return line;
}

Progress::Progress(bool enabled) : enabled_(enabled && ::isatty(STDERR_FILENO) != 0) {
  if (enabled_) thread_ = std::thread([this] { run(); });
}

Progress::~Progress() { stop(); }

void Progress::phase(const std::string& name, const ProgressCounter* counter, const std::string& unit) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  phase_ = name;
  unit_ = unit;
  counter_ = counter;
  started_ = std::chrono::steady_clock::now();
  if (drawn_) {  // clear the old line before anything else is printed
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
    drawn_ = false;
  }
}

void Progress::stop() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    counter_ = nullptr;
  }
  wake_.notify_all();
  thread_.join();
}

void Progress::run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, std::chrono::milliseconds(250));
    ProgressState state;
    state.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    if (stopping_ || phase_.empty() || state.seconds < 1.0) continue;
    state.phase = phase_;
    state.unit = unit_;
    if (counter_ != nullptr) {
      state.total = counter_->total.load(std::memory_order_relaxed);
      state.done = counter_->done.load(std::memory_order_relaxed);
    }
    std::fprintf(stderr, "\r\033[K%s", progress_line(state, terminal_width()).c_str());
    std::fflush(stderr);
    drawn_ = true;
  }
  if (drawn_) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
  }
}

}  // namespace recon::cli
