#include "summary.h"

#include "recon/core/detail/float_chars.h"
#include "recon/core/version.h"
#include "recon/io/atomic_file.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace recon::cli {

Json& Json::operator[](const std::string& key) {
  if (!std::holds_alternative<Object>(value_)) value_ = Object{};
  auto& object = std::get<Object>(value_);
  for (auto& [k, v] : object)
    if (k == key) return v;
  object.emplace_back(key, Json{});
  return object.back().second;
}

namespace {
void append_string(std::string& out, const std::string& s) {
  out += '"';
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(c));
          out += buffer;
        } else {
          out += c;
        }
    }
  }
  out += '"';
}
}  // namespace

void Json::dump(std::string& out, int indent, int depth) const {
  const auto newline = [&](int d) {
    if (indent <= 0) return;
    out += '\n';
    out.append(static_cast<std::size_t>(indent * d), ' ');
  };
  if (const auto* d = std::get_if<double>(&value_)) {
    if (!std::isfinite(*d)) {
      out += "null";
    } else {
      // Whole numbers (counts) in full: to_chars's shortest form writes
      // nine million as 9e+06.
      char buffer[32];
      const bool whole = std::abs(*d) < 1e15 && *d == std::floor(*d);
      const auto result = whole ? std::to_chars(buffer, buffer + sizeof buffer, static_cast<long long>(*d))
                                : detail::float_to_chars(buffer, buffer + sizeof buffer, *d);
      out.append(buffer, result.ptr);
    }
  } else if (const auto* b = std::get_if<bool>(&value_)) {
    out += *b ? "true" : "false";
  } else if (const auto* s = std::get_if<std::string>(&value_)) {
    append_string(out, *s);
  } else if (const auto* a = std::get_if<Array>(&value_)) {
    // Numbers and strings on one line; objects (the lab's runs) one a line.
    const bool objects =
        std::any_of(a->begin(), a->end(), [](const Json& j) { return std::holds_alternative<Object>(j.value_); });
    out += '[';
    for (std::size_t i = 0; i < a->size(); ++i) {
      if (i) out += objects && indent > 0 ? "," : ", ";
      if (objects) newline(depth + 1);
      (*a)[i].dump(out, objects ? indent : 0, depth + 1);
    }
    if (objects && !a->empty()) newline(depth);
    out += ']';
  } else {
    const auto& o = std::get<Object>(value_);
    out += '{';
    for (std::size_t i = 0; i < o.size(); ++i) {
      if (i) out += ',';
      newline(depth + 1);
      append_string(out, o[i].first);
      out += indent > 0 ? ": " : ":";
      o[i].second.dump(out, indent, depth + 1);
    }
    if (!o.empty()) newline(depth);
    out += '}';
  }
}

std::string Json::dump(int indent) const {
  std::string out;
  dump(out, indent, 0);
  return out;
}

void put(Json& object, JsonMembers members) {
  for (const auto& [name, value] : members) object[name] = value;
}

StepReport step_report(std::string line, JsonMembers stats) {
  StepReport report{{std::move(line)}, {}};
  put(report.stats, stats);
  return report;
}

Summary::Summary(bool quiet) : quiet_(quiet) { stats_["version"] = std::string(version()); }

void Summary::add(const StepReport& report, const std::string& key, const std::string& subkey) {
  for (const std::string& line : report.lines) say(line);
  Json& place = subkey.empty() ? stats_[key] : stats_[key][subkey];
  place = report.stats;
}

void Summary::say(const std::string& text) const {
  if (!quiet_) std::cout << text << std::endl;
}

void Summary::write_stats(const std::filesystem::path& path) const {
  io::AtomicFile file(path);
  file.stream() << stats_.dump(2) << '\n';
  file.commit();
}

std::string plural(std::size_t n, const std::string& word) {
  if (n == 1) return "1 " + word;
  if (word.ends_with("vertex")) return std::to_string(n) + " " + word.substr(0, word.size() - 2) + "ices";
  return std::to_string(n) + " " + word + "s";
}

std::string format_seconds(double s) {
  char buffer[32];
  if (s < 1.0)
    std::snprintf(buffer, sizeof buffer, "%.0f ms", s * 1000.0);
  else
    std::snprintf(buffer, sizeof buffer, "%.2f s", s);
  return buffer;
}

std::string format_length(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

// "800M", "2G", "1.5 GB", "3000000000": bytes (K, M, G, T are powers of 1000,
// as in the messages; a trailing 'B' or 'iB' is allowed: KiB, MiB... powers of 1024).
std::string parse_size(const std::string& text, std::size_t& bytes) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return "expected a size such as 800M or 2G, found '" + text + "'";
  }
  if (!std::isfinite(value)) return "expected a size such as 800M or 2G, found '" + text + "'";
  std::string unit = text.substr(used);
  unit.erase(std::remove(unit.begin(), unit.end(), ' '), unit.end());
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  static const std::pair<const char*, double> units[] = {{"", 1.0},
                                                         {"B", 1.0},
                                                         {"K", 1e3},
                                                         {"KB", 1e3},
                                                         {"KIB", 1024.0},
                                                         {"M", 1e6},
                                                         {"MB", 1e6},
                                                         {"MIB", 1048576.0},
                                                         {"G", 1e9},
                                                         {"GB", 1e9},
                                                         {"GIB", 1073741824.0},
                                                         {"T", 1e12},
                                                         {"TB", 1e12},
                                                         {"TIB", 1099511627776.0}};
  for (const auto& [name, factor] : units) {
    if (unit != name) continue;
    const double b = value * factor;
    if (!(b >= 1e6) || !(b < 1e18)) return "a memory limit must be between 1M and 1000000T, found '" + text + "'";
    bytes = static_cast<std::size_t>(b);
    return "";
  }
  return "unknown size unit in '" + text + "' (use K, M, G or T)";
}

}  // namespace recon::cli
