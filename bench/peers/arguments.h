#pragma once
// The command line the CGAL peer programs share:
//   PROGRAM IN.ply -o OUT.ply [--k K] [--threads T]
// K counts the point itself, as recon's --k does.

#include <stdexcept>
#include <string>

namespace peers {

struct Arguments {
  std::string input, output;
  unsigned k = 0;
  unsigned threads = 0;  // 0: all cores
};

/// Throws std::runtime_error with `usage` when input or output is missing,
/// and when K is below `min_k`.
inline Arguments parse_arguments(int argc, char** argv, unsigned default_k, unsigned min_k, const std::string& usage) {
  Arguments a;
  a.k = default_k;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "-o" || arg == "--output")
      a.output = value();
    else if (arg == "--k")
      a.k = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--threads")
      a.threads = static_cast<unsigned>(std::stoul(value()));
    else if (!arg.empty() && arg[0] != '-' && a.input.empty())
      a.input = arg;
    else
      throw std::runtime_error("unknown argument '" + arg + "'");
  }
  if (a.input.empty() || a.output.empty()) throw std::runtime_error("usage: " + usage);
  if (a.k < min_k) throw std::runtime_error("--k must be at least " + std::to_string(min_k));
  return a;
}

}  // namespace peers
