#include "recon/core/interruption.h"

#include <utility>

namespace recon {
namespace {
thread_local const std::function<void()>* installed = nullptr;
}  // namespace

InterruptionCheck::InterruptionCheck(std::function<void()> check) : check_(std::move(check)), previous_(installed) {
  installed = &check_;
}

InterruptionCheck::~InterruptionCheck() { installed = previous_; }

void interruption_point() {
  if (installed != nullptr) (*installed)();
}

}  // namespace recon
