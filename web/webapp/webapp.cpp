// The web page's window into the library (web/webapp/): the 3D
// reconstruction as `recon reconstruct` runs it, driven from a Web Worker
// (worker.js), with every phase's layers handed to the page as the report
// draws them (src/report/report.cpp) and the outputs written by the program's own
// writers.
//
// Files: the worker writes the dropped file into Emscripten's in-memory
// file system and the program's reader reads it by name, so a bad file gets
// the program's message word for word ("face.ply:12: ..."); outputs are
// written there too and the worker hands their bytes to the page.
//
// Protocol (C functions, called from worker.js; strings are UTF-8):
//   webapp_load(path, format) reads a cloud ("" format: from the
//     extension); webapp_sample(shape, points, seed) makes one as
//     `recon generate` does. Both keep it and return 0, or 1 (webapp_error()
//     says why). webapp_input() then describes it as JSON: points, colours,
//     normals, the memory estimate and the page's limit.
//   webapp_run(from_phase, method, k, rho, delta, cell, resolution) runs
//     phases I-V (from_phase 1) or, on the kept phases I-II, III-V again
//     (from_phase 3: a new delta, cell or resolution; phases I-II run again
//     too when the refined method's fits would change with the new cell,
//     phases_1_2_hold_for); k 0, rho 0, delta < 0, cell 0, resolution 0 mean
//     "the program's default". Returns 0, 1, or 2 when the page cancelled the
//     run (Module.reconCancelled() true at an interruption point: the page
//     sets it through a SharedArrayBuffer where it has one, worker.js).
//     Cancelled or failed in phases I-II, the run keeps nothing of them;
//     later, it keeps phases I-II for the next run. While it runs it calls the page's
//     hooks (Module.reconPhase, reconProgress, reconLayers: worker.js); the
//     layers go as the report's data (report_data: the JSON and the arrays'
//     bytes, copied out of the module's memory) after phase I, phase II and
//     (refined) phase IV, as subsamples drawn while the run goes on, and at
//     the end with the report's budgets.
//   webapp_set_limit(bytes) sets the memory a run may use (0: 2.5 GB, the
//     default); a cloud estimated to need more is refused before phase I.
//   webapp_kept() is 1 when phases I-II are kept for a run from phase III.
//   webapp_stats() is the last run's --stats JSON; webapp_write(what, path)
//     writes "mesh" (by the path's extension), "cloud" (the oriented cloud,
//     .ply), "report" or "stats" and returns 0 or 1.
//
// Cost: that of the program with one thread, plus the layers (the report's
// budgets bound them, whatever the cloud's size).

#include "run_reports.h"
#include "summary.h"

#include "recon/core/errors.h"
#include "recon/core/interruption.h"
#include "recon/core/memory_budget.h"
#include "recon/core/parallel.h"  // thread_count
#include "recon/core/progress.h"
#include "recon/core/shapes.h"
#include "recon/core/timer.h"
#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"
#include "recon/reconstruct.h"
#include "recon/report/report.h"

#include <emscripten/emscripten.h>

#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace {

using namespace recon;

// The memory a run may use by default: wasm32's 4 GiB address space, less
// what the page's own copies take (the file, the layers, the outputs).
constexpr double default_page_limit = 2.5e9;
// Points (graph edges, corners) and triangles drawn while the run goes on
// (measured in headless Chromium, docs/benchmarks.md); the run's final
// layers have the report's budgets.
constexpr std::size_t mid_run_points = 10'000;
constexpr std::size_t mid_run_triangles = 20'000;

struct State {
  PointCloud cloud;
  std::string name;                  // as the program would say it
  std::optional<cli::Summary> read;  // the input's account
  std::optional<Reconstruction> r;   // phases I-II kept, and the later ones
  ReconstructionOptions options;
  std::optional<cli::Summary> summary;  // the last run's account
  std::string error, text;              // returned strings
  double limit = default_page_limit;    // bytes a run may use (webapp_set_limit)
};
State state;

// The hooks of worker.js (EM_JS: JavaScript called from here).
EM_JS(void, js_phase, (const char* phase), { Module["reconPhase"](UTF8ToString(phase)); });
EM_JS(void, js_progress, (double done, double total), { Module["reconProgress"](done, total); });
EM_JS(int, js_cancelled, (), { return Module["reconCancelled"]() ? 1 : 0; });
// Thrown at an interruption point once the page has cancelled the run.
struct Cancelled {};
// The layers: the JSON, then `count` arrays given as (address, bytes) pairs
// at `arrays`; copied out of the module's memory for the page.
EM_JS(void, js_layers, (int stage, const char* json, std::size_t length, const std::uint32_t* arrays, int count), {
  const copies = [];
  for (let i = 0; i < count; ++i) {
    const at = HEAPU32[(arrays >> 2) + 2 * i], bytes = HEAPU32[(arrays >> 2) + 2 * i + 1];
    copies.push(HEAPU8.slice(at, at + bytes));
  }
  Module["reconLayers"](stage, UTF8ToString(json, length), copies);
});

void tell_phase(const char* phase) { js_phase(phase); }
void tell_progress(const ProgressCounter& counter) {
  js_progress(static_cast<double>(counter.done.load()), static_cast<double>(counter.total.load()));
}
// Stage 2: phases I-II are done; stage 5: the run is.
void tell_layers(int stage, const ReportLayers& layers, const ReportOptions& options) {
  const ReportData data = report_data(layers, options);
  std::vector<std::uint32_t> arrays;  // wasm32: an address is 32 bits
  for (const auto& a : data.arrays)
    arrays.insert(arrays.end(), {static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(a.data())),
                                 static_cast<std::uint32_t>(a.size())});
  js_layers(stage, data.json.data(), data.json.size(), arrays.data(), static_cast<int>(data.arrays.size()));
}

// The estimate the page shows before a run: the program's own (memory_budget.h)
// plus the cloud the page holds.
double estimated_bytes(std::size_t points, int k, bool refined) {
  return estimated_bytes_reconstruction(points, k, refined) + 40.0 * static_cast<double>(points);
}

// The account of the cloud just read or made, as `recon reconstruct` gives it.
void keep_cloud(PointCloud cloud, std::string name, const io::ReadNotes& notes, double seconds) {
  state.r.reset();
  state.summary.reset();
  state.cloud = std::move(cloud);
  state.name = std::move(name);
  state.read.emplace(false);
  state.read->add(cli::input_report(state.name, state.cloud, notes, seconds), "input");
}

ReconstructionOptions run_options(int method, int k, double rho, double delta, double cell, int resolution) {
  ReconstructionOptions o;
  o.method = method == 1 ? Method::hoppe92 : Method::refined;
  if (k > 0) o.planes.k = k;
  o.planes.adapt_k = k <= 0;  // as the program: a given k is the k used
  if (rho > 0.0) o.planes.rho = rho;
  if (delta >= 0.0) o.distance.delta = delta;
  if (cell > 0.0) o.cell = cell;
  if (resolution > 0) o.resolution = resolution;
  o.max_memory = static_cast<std::size_t>(state.limit);
  o.keep_graph = true;  // the page draws the graph and the corners, as a report does
  o.keep_corners = true;
  // Phase V's fitted normals for the GLB download, which has them as the
  // program's does; the other formats are written without, as the program
  // writes them without --normals (see mesh_for).
  o.vertex_normals = true;
  return o;
}

// Refuses, before any work, a cloud the page cannot hold.
void check_fits(int k, bool refined) {
  const double bytes = estimated_bytes(state.cloud.size(), k > 0 ? k : TangentPlaneOptions{}.k, refined);
  if (bytes > state.limit) {
    throw ResourceLimitError(state.name + ": " + std::to_string(state.cloud.size()) + " points would need about " +
                             std::to_string(static_cast<long long>(bytes / 1e6)) + " MB, more than the page's " +
                             std::to_string(static_cast<long long>(state.limit / 1e6)) +
                             " MB: run the program instead (recon reconstruct FILE -o mesh.ply, see README.md)");
  }
}

// The report's title and statistics for the layers, as `--report` gives them.
ReportOptions layer_options(cli::Summary& summary) { return cli::run_report_options(state.name, summary); }

// The layers drawn while the run goes on: light enough that no task of the
// page's main thread takes over 100 ms (regular subsamples, which the page
// states; docs/benchmarks.md, Issue 29).
ReportOptions mid_run_options(cli::Summary& summary) {
  ReportOptions options = layer_options(summary);
  options.max_points = mid_run_points;
  options.max_edges = mid_run_points;
  options.max_corners = mid_run_points;
  options.max_triangles = mid_run_triangles;
  options.max_boundary_edges = mid_run_points;
  return options;
}

// Phase I's layers (points, kd-tree cells, unoriented planes), or with
// phase II's (graph, spanning tree, oriented normals) once it ran.
void tell_early_layers(int stage, const Reconstruction& r) {
  ReportInput input;
  input.points = r.points();
  input.offset = r.offset;
  input.planes = &r.planes;
  input.oriented = r.oriented ? &*r.oriented : nullptr;
  if (stage >= 2) input.normals = r.normals();  // none yet after phase I
  input.colors = r.colors;
  cli::Summary summary = *state.read;
  const ReportOptions options = mid_run_options(summary);
  tell_layers(stage, make_report_layers(input, options), options);
}

// Phase IV's mesh (the 1992 surface) and the corners, drawn while phase V
// runs: called as it starts, when the contour is whole but, like every
// result until the run's end, relative to r.offset.
void tell_contour_layers(const Reconstruction& r) {
  Mesh moved = r.contour.mesh;
  for (Vec3& v : moved.vertices) v += r.offset;
  ReportInput input = report_input(r);
  input.mesh = &moved;
  input.refinement = nullptr;
  cli::Summary summary = *state.read;
  const ReportOptions options = mid_run_options(summary);
  tell_layers(4, make_report_layers(input, options), options);
}

// Phases I-II (from_phase 1), then III-V, each stage's layers to the page.
void run(int from_phase, const ReconstructionOptions& options) {
  Timer total;
  ProgressCounter counter;
  const ProgressScope counting(&counter);  // (reconstruct_phase_1 installs none)
  ReconstructionOptions o = options;
  o.on_phase = [](const char* phase) {
    tell_phase(phase);
    if (std::string_view(phase) == "refinement" && state.r) tell_contour_layers(*state.r);
  };
  o.progress = &counter;
  double last = -1.0;
  const InterruptionCheck progress([&] {
    if (js_cancelled() != 0) throw Cancelled{};
    if (total.elapsed() - last < 0.1) return;
    last = total.elapsed();
    tell_progress(counter);
  });
  state.summary.reset();
  if (from_phase <= 2 || !state.r || !phases_1_2_hold_for(*state.r, o)) {
    state.r.reset();  // (kept only once phase II is done)
    Reconstruction r = reconstruct_phase_1(PointCloudView(state.cloud), o);
    tell_early_layers(1, r);
    reconstruct_phase_2_on(r, o);
    tell_early_layers(2, r);
    state.r.emplace(std::move(r));
  }
  reconstruct_phases_3_on(*state.r, o);
  state.options = o;
  state.summary = *state.read;
  cli::report_reconstruction(*state.r, o, state.cloud.size(), true, *state.summary);
  state.summary->stats()["threads"] = thread_count();  // 1: WebAssembly here runs on one thread
  state.summary->stats()["seconds_total"] = total.elapsed();
  const ReportOptions drawn = layer_options(*state.summary);
  tell_layers(5, make_report_layers(report_input(*state.r), drawn), drawn);
}

// The cloud with phase II's normals, in the input's order (`recon normals`).
PointCloud oriented_cloud() {
  PointCloud cloud = state.cloud;
  const auto normals = state.r->normals();
  cloud.normals.assign(cloud.size(), Vec3::Zero());
  for (std::size_t j = 0; j < state.r->order.size(); ++j) cloud.normals[state.r->order[j]] = normals[j];
  return cloud;
}

// The mesh as `recon reconstruct -o PATH` writes it: with vertex normals in
// GLB only.
Mesh mesh_for(const std::string& path) {
  Mesh mesh = state.r->mesh();
  if (io::mesh_format_from_path(path) != io::MeshFormat::glb) mesh.normals.clear();
  return mesh;
}

void write(const std::string& what, const std::string& path) {
  if (!state.r || !state.summary) throw InvalidInputError("nothing to write: no run has finished");
  if (what == "mesh") {
    io::write_mesh(path, mesh_for(path));
  } else if (what == "cloud") {
    io::write_points(path, oriented_cloud());
  } else if (what == "report") {
    const ReportOptions options = cli::run_report_options(state.name, *state.summary);
    write_report(path, make_report_layers(report_input(*state.r), options), options);
  } else if (what == "stats") {
    state.summary->write_stats(path);
  } else {
    throw InvalidInputError("webapp: nothing called " + what + " to write");
  }
}

// Runs `step`, turning an exception into 1 and the program's one line, and
// a cancellation into 2.
template <class Step>
int guarded(Step step) {
  state.error.clear();
  try {
    step();
    return 0;
  } catch (const std::exception& e) {
    state.error = e.what();
    return 1;
  } catch (const Cancelled&) {
    state.error = "cancelled";
    return 2;
  }
}

}  // namespace

extern "C" {

EMSCRIPTEN_KEEPALIVE int webapp_load(const char* path, const char* format) {
  return guarded([&] {
    io::ReadPointsOptions options;
    if (format[0] != '\0') options.format = io::point_format_from_name(format);
    io::ReadNotes notes;
    Timer timer;
    PointCloud cloud = io::read_points(path, options, &notes);
    keep_cloud(std::move(cloud), path, notes, timer.elapsed());
  });
}

EMSCRIPTEN_KEEPALIVE int webapp_sample(const char* shape, int points, int seed) {
  return guarded([&] {
    Timer timer;
    PointCloud cloud = make_shape(shape)->sample(static_cast<std::size_t>(points), static_cast<std::uint64_t>(seed));
    cloud.normals.clear();  // as `recon generate` writes it without --with-normals
    keep_cloud(std::move(cloud), std::string(shape) + ".ply", {}, timer.elapsed());
  });
}

EMSCRIPTEN_KEEPALIVE const char* webapp_input(int k, int method) {
  cli::Json json;
  json["points"] = state.cloud.size();
  json["has_colors"] = state.cloud.has_colors();
  json["has_normals"] = state.cloud.has_normals();
  json["estimated_bytes"] = estimated_bytes(state.cloud.size(), k > 0 ? k : TangentPlaneOptions{}.k, method != 1);
  json["limit_bytes"] = state.limit;
  state.text = json.dump(0);
  return state.text.c_str();
}

EMSCRIPTEN_KEEPALIVE int webapp_run(int from_phase, int method, int k, double rho, double delta, double cell,
                                    int resolution) {
  return guarded([&] {
    check_fits(k, method != 1);
    run(from_phase, run_options(method, k, rho, delta, cell, resolution));
  });
}

// 1 when the worker holds phases I-II (of the last run's method, k and rho) for a later run from phase III.
EMSCRIPTEN_KEEPALIVE int webapp_kept() { return state.r ? 1 : 0; }

EMSCRIPTEN_KEEPALIVE const char* webapp_stats() {
  state.text = state.summary ? state.summary->stats().dump(2) : std::string("{}");
  return state.text.c_str();
}

EMSCRIPTEN_KEEPALIVE int webapp_write(const char* what, const char* path) {
  return guarded([&] { write(what, path); });
}

EMSCRIPTEN_KEEPALIVE const char* webapp_error() { return state.error.c_str(); }

EMSCRIPTEN_KEEPALIVE void webapp_set_limit(double bytes) { state.limit = bytes > 0.0 ? bytes : default_page_limit; }

}  // extern "C"
