// recon: surface reconstruction from unorganized points (Hoppe et al. 1992).
// This file only parses the command line and turns exceptions into one
// line on stderr and an exit code; the work is in the library.

#include "commands.h"
#include "number_options.h"

#include "recon/core/errors.h"
#include "recon/core/fp_traps.h"
#include "recon/core/parallel.h"
#include "recon/core/version.h"
#include "recon/io/atomic_file.h"
#include "recon/io/point_io.h"  // file_being_read
#include "recon/tiles/tiles.h"

#include <csignal>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <new>
#include <string>

#include <unistd.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {
// Ctrl-C (SIGINT), SIGTERM, SIGHUP: stop at once, wherever the run is.
// Nothing is left half-written: outputs are renamed into place only when
// complete, so removing the pending temporaries (and a tiled run's tiles)
// is the whole clean-up.
// Then the signal is raised again with its default action, so that the
// caller (a shell, a script) sees the run end by that signal.
extern "C" void on_interrupt(int signal_number) {
  recon::io::remove_pending_temporaries();
  recon::remove_tile_workspaces();
  constexpr char message[] = "\nrecon: interrupted; unfinished output removed\n";
  [[maybe_unused]] const ssize_t ignored = ::write(STDERR_FILENO, message, sizeof message - 1);
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

// SIGBUS while an input file is mapped: another program shortened the file
// while recon was reading it (or the storage failed under it). The read
// cannot go on; like any other error: one line naming the file, unfinished
// outputs removed, exit status 1. A SIGBUS with no input being read is not
// this, and ends the program as it would have.
extern "C" void on_bus_error(int signal_number) {
  const char* file = recon::io::file_being_read();
  if (file[0] == '\0') {
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
    return;
  }
  recon::io::remove_pending_temporaries();
  recon::remove_tile_workspaces();
  auto say = [](const char* text) {
    std::size_t length = 0;
    while (text[length] != '\0') ++length;
    [[maybe_unused]] const ssize_t ignored = ::write(STDERR_FILENO, text, length);
  };
  say("recon: error: ");
  say(file);
  say(": the file was shortened, or could not be read, while recon was reading it\n");
  ::_exit(1);
}

void stop_cleanly_on_interrupt() {
  struct sigaction action = {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) sigaction(signal_number, &action, nullptr);
  action.sa_handler = on_bus_error;
  sigaction(SIGBUS, &action, nullptr);
}

// Runs the chosen subcommand; errors become one line and an exit code (1
// for what the user can act on, 2 for a fault of recon's own).
int run_commands(const CLI::App& app, const std::map<CLI::App*, recon::cli::Command>& commands,
                 const recon::cli::GlobalOptions& global, bool trap_fp) {
  try {
    recon::set_thread_count(global.threads);
    if (trap_fp && !recon::set_fp_traps(true))
      throw recon::Error("--trap-fp: this platform cannot trap floating-point exceptions");
    for (CLI::App* sub : app.get_subcommands()) commands.at(sub)();
  } catch (const recon::Error& e) {
    std::cerr << "recon: error: " << e.what() << '\n';
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "recon: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "recon: internal error: " << e.what() << '\n';
    return 2;
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  stop_cleanly_on_interrupt();
#if defined(__GLIBC__)
  // Arrays of a megabyte or more get their own pages and give them back when
  // freed. (By default glibc raises this threshold after the first large
  // free, and the phases' large temporaries then stay resident: about 10 %
  // more peak memory on a million points, measured.)
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
  CLI::App app{
      "recon: triangle meshes and oriented normals from unorganized point clouds\n"
      "(Hoppe, DeRose, Duchamp, McDonald, Stuetzle: Surface reconstruction from unorganized points, 1992)"};
  app.require_subcommand(1);
  // "recon 0.1.0+g1a2b3c4", exit status 0: what a bug report should quote (recon/core/version.h).
  app.set_version_flag("--version", "recon " + std::string(recon::version()), "Print recon's version and exit");
  app.fallthrough();  // --quiet and --threads may also follow the subcommand
  recon::cli::GlobalOptions global;
  app.add_flag("-q,--quiet", global.quiet, "Print nothing but errors");
  // (At most recon::max_thread_count(); the library refuses more, naming the bound.)
  app.add_option("--threads", global.threads, "Threads for the parallel phases (default: all cores)")
      ->check(recon::cli::whole_number_up_to(std::numeric_limits<int>::max()));
  // A debugging aid, left out of --help: stop with SIGFPE at the first
  // invalid operation, division by zero or overflow (see recon/core/fp_traps.h).
  bool trap_fp = false;
  app.add_flag("--trap-fp", trap_fp, "Trap floating-point exceptions (debugging)")->group("");

  std::map<CLI::App*, recon::cli::Command> commands;
  auto add = [&](const char* name, const char* help, auto adder) {
    CLI::App* sub = app.add_subcommand(name, help);
    commands[sub] = adder(*sub, global);
  };
  add("info", "Describe a point cloud: size, bounding box, duplicates, sampling density", recon::cli::add_info);
  add("normals", "Estimate consistently oriented normals (phases I and II) and write the oriented cloud",
      recon::cli::add_normals);
  add("reconstruct", "Reconstruct a triangle mesh from a point cloud (all four phases)", recon::cli::add_reconstruct);
  add("generate",
      "Write a point sample of a known shape (sphere, torus, ellipsoid, box, two, terrain, part, handle, conics, "
      "shell, nested; thin solids: plate, club, airfoil, cup, cavity-cube, two-cavities), or what a range scanner "
      "sees of it (--scan)",
      recon::cli::add_generate);
  add("simplify",
      "Simplify a mesh (phase VI alone: for a tiled run's mesh, or another program's), keeping creases, corners, "
      "open boundaries and separate objects",
      recon::cli::add_simplify);
  add("check",
      "Check that a mesh is embedded and manifold: no triangles crossing, no pinched vertex, no edge of three "
      "triangles, no triangle of zero area (exact predicates); exit status 1 when not",
      recon::cli::add_check);
  add("lab",
      "Run every alternative of phases I-II (searches, priority queues, MST algorithms, graphs) on one cloud, "
      "timed, counted and checked against each other",
      recon::cli::add_lab);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "recon: error: " << e.what() << " (see recon --help)\n";
    return 2;
  }
  return run_commands(app, commands, global, trap_fp);
}
