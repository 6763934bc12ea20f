#pragma once
// The subcommands of the `recon` program. Each registers its options on the
// CLI11 app and returns the function that runs it.

#include <CLI/CLI.hpp>

#include <functional>

namespace recon::cli {

struct GlobalOptions {
  bool quiet = false;
  int threads = 0;  // 0: all cores
};

using Command = std::function<void()>;

Command add_info(CLI::App& app, const GlobalOptions& global);
Command add_normals(CLI::App& app, const GlobalOptions& global);
Command add_reconstruct(CLI::App& app, const GlobalOptions& global);
Command add_generate(CLI::App& app, const GlobalOptions& global);
Command add_lab(CLI::App& app, const GlobalOptions& global);
Command add_simplify(CLI::App& app, const GlobalOptions& global);  // simplify.cpp
Command add_check(CLI::App& app, const GlobalOptions& global);     // check.cpp

}  // namespace recon::cli
