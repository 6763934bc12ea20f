#include "recon/resource_usage.h"

#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include <unistd.h>

namespace recon {
namespace {

// A "kB" field of /proc/self/status.
std::optional<std::size_t> status_field(std::string_view field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.size() > field.size() && line.compare(0, field.size(), field) == 0 && line[field.size()] == ':') {
      std::istringstream value(line.substr(field.size() + 1));
      std::size_t kib = 0;
      if (value >> kib) return kib * 1024;
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::size_t> resident_bytes() { return status_field("VmRSS"); }

std::optional<std::size_t> peak_resident_bytes() { return status_field("VmHWM"); }

bool reset_peak_resident() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

void StepPeaks::start(std::string step) {
  finish();
  step_ = std::move(step);
  reset_peak_resident();
}

void StepPeaks::finish() {
  if (step_.empty()) return;
  if (const auto peak = peak_resident_bytes())
    peaks_.emplace_back(step_, static_cast<double>(*peak) / (1024.0 * 1024.0));
  step_.clear();
}

std::size_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) : 0;
}

std::size_t default_memory_limit() {
  const std::size_t physical = physical_memory_bytes();
  return physical > 0 ? physical / 2 : std::size_t{4'000'000'000};
}

}  // namespace recon
