// report_page() of a recon built with RECON_REPORT=OFF (no Node.js at build
// time): the report cannot be written, and says so.
#include "recon/core/errors.h"
#include "recon/report/report.h"

namespace recon {

ReportPage report_page() {
  throw InvalidInputError(
      "this recon was built without the report viewer (RECON_REPORT=OFF): run scripts/setup, which installs "
      "Node.js and web/'s packages, and build again");
}

}  // namespace recon
