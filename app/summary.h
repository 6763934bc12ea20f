#pragma once
// What a run reports: lines for the terminal as the phases finish, and the
// same figures as JSON for --stats.

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace recon::cli {

/// A small JSON value: enough for statistics (numbers, strings, booleans,
/// arrays and objects that keep their insertion order).
class Json {
 public:
  using Array = std::vector<Json>;
  using Object = std::vector<std::pair<std::string, Json>>;

  Json() : value_(Object{}) {}
  Json(double v) : value_(v) {}
  Json(int v) : value_(static_cast<double>(v)) {}
  Json(std::size_t v) : value_(static_cast<double>(v)) {}
  Json(bool v) : value_(v) {}
  Json(std::string v) : value_(std::move(v)) {}
  Json(const char* v) : value_(std::string(v)) {}
  Json(Array v) : value_(std::move(v)) {}

  /// Object member, created (as an empty object) when absent.
  Json& operator[](const std::string& key);
  [[nodiscard]] std::string dump(int indent = 0) const;

 private:
  void dump(std::string& out, int indent, int depth) const;
  std::variant<double, bool, std::string, Array, Object> value_;
};

/// What a run has to say about one step: its lines for the terminal and
/// its entry in --stats. The functions that build these (run_reports.h)
/// only compute; Summary::add prints and records.
struct StepReport {
  std::vector<std::string> lines;
  Json stats;
};

/// Named values for an object's members, in the order they are to appear.
using JsonMembers = std::initializer_list<std::pair<const char*, Json>>;

/// Sets `object`'s members (creating those absent) in the order given.
void put(Json& object, JsonMembers members);
/// A step's report of one line, with these statistics in this order.
[[nodiscard]] StepReport step_report(std::string line, JsonMembers stats);

class Summary {
 public:
  /// Its statistics start with "version": recon::version(), so that every
  /// --stats file, a Python run's stats and a report say what made them.
  explicit Summary(bool quiet);
  /// Prints one line (unless quiet).
  void say(const std::string& text) const;
  /// Prints the report's lines and puts its statistics at stats()[key]
  /// (or stats()[key][subkey]).
  void add(const StepReport& report, const std::string& key, const std::string& subkey = "");
  Json& stats() { return stats_; }
  /// Writes the statistics as JSON, atomically.
  void write_stats(const std::filesystem::path& path) const;

 private:
  bool quiet_;
  Json stats_;
};

/// "1 point", "3 points", "2 vertices".
std::string plural(std::size_t n, const std::string& word);
/// "1.23 s", "45 ms".
std::string format_seconds(double s);
/// Shortest round-trip decimal form of a length.
std::string format_length(double v);
/// Parses a memory size: "800M", "2G", "1.5 GB", "3000000000" (K, M, G, T
/// are powers of 1000, as in the messages; KiB, MiB... powers of 1024),
/// between 1M and 1000000T. Returns "" and sets `bytes`, or returns what
/// was wrong.
std::string parse_size(const std::string& text, std::size_t& bytes);

}  // namespace recon::cli
