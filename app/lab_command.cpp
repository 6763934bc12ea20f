// `recon lab INPUT`: the alternatives lab (recon/alternatives/lab.h) from the command
// line: a table on the terminal, --stats as JSON, --report with the lab panel.

#include "command_parts.h"
#include "commands.h"
#include "number_options.h"
#include "progress.h"

#include "recon/alternatives/lab.h"
#include "recon/core/timer.h"

#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>

namespace recon::cli {
namespace {

struct LabCommandOptions {
  InputOptions in;
  PhaseOptions phases;
  std::filesystem::path stats, report;
  LabOptions lab;
};

void add_limits(CLI::App& app, LabOptions& lab) {
  app.add_option("--max-complete", lab.max_points_complete,
                 "Run the complete graph (n^2 / 2 distances) up to this many points")
      ->default_val(lab.max_points_complete)
      ->check(whole_number_up_to(1e12));
  app.add_option("--max-brute-force", lab.max_points_brute_force,
                 "Run the brute-force search (n^2 distances) up to this many points")
      ->default_val(lab.max_points_brute_force)
      ->check(whole_number_up_to(1e12));
  app.add_option("--max-list-heap", lab.max_points_list_heap,
                 "Run Prim on the list heap (a scan per pop) up to this many points")
      ->default_val(lab.max_points_list_heap)
      ->check(whole_number_up_to(1e12));
  // A test hook, left out of --help: spoil one run's result, so that the
  // agreement checks must stop the lab (tests/cli/help_info_test.cpp).
  app.add_option("--test-spoil", lab.spoil, "Spoil this run's result (tests)")->group("");
  app.add_flag("--simplify", lab.simplify,
               "Also reconstruct the cloud and simplify its mesh to a tenth on each of phase VI's queues");
}

std::string cell(double v, int precision = 3) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", precision, v);
  return text;
}

std::string count_cell(std::uint64_t v) { return v == 0 ? "-" : std::to_string(v); }

std::string share_cell(std::optional<double> v) { return v ? cell(100.0 * *v, 4) + " %" : "-"; }

// One line per run that ran: what it cost and what it found.
std::string run_line(const LabRun& r) {
  char line[256];
  const std::string weight = r.tree_weight ? cell(*r.tree_weight, 10) : "-";
  const bool graph = r.kind == LabKind::graph;
  const bool simplify = r.kind == LabKind::simplify;
  const std::string result_cell = simplify ? std::to_string(r.triangles) + " tri." : weight;
  std::snprintf(line, sizeof line, "%-7s %-24s %-19s %9s %17s %6s %8s %9s %9s", std::string(name_of(r.kind)).c_str(),
                r.name.c_str(), r.graph.c_str(), format_seconds(r.seconds).c_str(), result_cell.c_str(),
                graph ? std::to_string(r.components).c_str() : "-", graph ? std::to_string(r.flips).c_str() : "-",
                graph ? share_cell(r.agree_default).c_str() : "-", graph ? share_cell(r.agree_truth).c_str() : "-");
  return line;
}

std::string counts_line(const LabRun& r) {
  const OperationCounts& c = r.counts;
  char line[256];
  std::snprintf(line, sizeof line, "%-24s %10s %10s %10s %12s %10s %10s %13s %6s", r.name.c_str(),
                count_cell(c.pushes).c_str(), count_cell(c.pops).c_str(), count_cell(c.decrease_keys).c_str(),
                count_cell(c.comparisons).c_str(), count_cell(c.finds).c_str(), count_cell(c.unions).c_str(),
                count_cell(c.distance_evaluations).c_str(), count_cell(c.rounds).c_str());
  return line;
}

void print_tables(const LabResult& result, Summary& summary) {
  summary.say("");
  summary.say(
      "kind    run                      graph                  time       tree weight  pieces    flips   default     "
      "truth");
  for (const LabRun& r : result.runs)
    if (r.skipped.empty()) summary.say(run_line(r));
  summary.say("");
  summary.say(
      "run                          pushes       pops  decr.-key  comparisons      finds     unions     distances "
      "rounds");
  for (const LabRun& r : result.runs)
    if (r.skipped.empty() && r.counts != OperationCounts{}) summary.say(counts_line(r));
  for (const LabRun& r : result.runs)
    if (!r.skipped.empty()) summary.say("skipped " + r.name + ": " + r.skipped);
  summary.say("");
  summary.say(
      "default: share of normals on the side the Riemannian graph (the default) gives them; truth: on the "
      "side of the input's own normals, where it has them. All the searches found the same neighbours, and "
      "all the trees of one graph weigh the same (checked); with --simplify, every queue gave the same mesh "
      "(checked; decr.-key counts its key updates, up or down).");
}

Json counts_json(const OperationCounts& c) {
  Json j;
  j["pushes"] = static_cast<double>(c.pushes);
  j["pops"] = static_cast<double>(c.pops);
  j["decrease_keys"] = static_cast<double>(c.decrease_keys);
  j["comparisons"] = static_cast<double>(c.comparisons);
  j["finds"] = static_cast<double>(c.finds);
  j["unions"] = static_cast<double>(c.unions);
  j["distance_evaluations"] = static_cast<double>(c.distance_evaluations);
  j["rounds"] = static_cast<double>(c.rounds);
  return j;
}

Json run_json(const LabRun& r) {
  Json j;
  j["name"] = r.name;
  j["kind"] = std::string(name_of(r.kind));
  if (!r.graph.empty()) j["graph"] = r.graph;
  if (!r.skipped.empty()) {
    j["seconds"] = std::numeric_limits<double>::quiet_NaN();  // written as null: it did not run
    j["skipped"] = r.skipped;
    return j;
  }
  j["seconds"] = r.seconds;
  j["counts"] = counts_json(r.counts);
  if (r.tree_weight) j["tree_weight"] = *r.tree_weight;
  if (r.kind == LabKind::simplify) j["triangles"] = r.triangles;
  if (r.kind == LabKind::graph) {
    j["edges"] = r.edges;
    j["components"] = r.components;
    j["flips"] = r.flips;
    j["agree_default"] = r.agree_default;
    if (r.agree_truth) j["agree_truth"] = *r.agree_truth;
  }
  return j;
}

void record(const LabResult& result, Summary& summary) {
  Json::Array runs;
  for (const LabRun& r : result.runs) runs.push_back(run_json(r));
  summary.stats()["runs"] = Json(runs);
  summary.stats()["tangent_planes"]["k"] = result.planes.k;
  summary.stats()["tangent_planes"]["rho"] = result.planes.rho;
  summary.stats()["tangent_planes"]["seconds"] = result.seconds_planes;
}

// The report: layers 1 to 5 of the default run, and the lab panel.
void write_lab_report(const std::filesystem::path& path, const LabResult& result, const std::filesystem::path& source,
                      Summary& summary) {
  Timer timer;
  const ReportOptions options = run_report_options(source, summary);
  ReportInput input;
  input.points = result.planes.point_tree.points();  // in the lab's (leaf) order
  input.planes = &result.planes;
  input.oriented = &result.default_orientation;
  input.normals = result.default_orientation.normals;
  ReportLayers layers = make_report_layers(input, options);
  layers.lab = make_report_lab(result.graphs, summary.stats().dump(0), input.points, input.offset, layers, options);
  write_report(path, layers, options);
  summary.say("wrote     " + path.string() + " (report with the lab panel; " + format_seconds(timer.elapsed()) + ")");
}

}  // namespace

Command add_lab(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<LabCommandOptions>();
  add_input(app, o->in);
  app.add_option("--stats", o->stats, "Also write every run's figures as JSON to this file");
  add_report_option(app, o->report);
  add_phase_options(app, o->phases);
  add_limits(app, o->lab);
  return [o, &global] {
    Timer total;
    Summary summary(global.quiet);
    check_outputs(o->in.path, {o->stats, o->report});
    const PointCloud cloud = read_input(o->in, summary);
    if (cloud.has_normals()) summary.say("truth     the input's own normals are taken as the true side");
    LabOptions options = o->lab;
    options.planes = phase_1_options(o->phases);
    if (cloud.has_normals()) options.true_normals = cloud.normals;
    options.keep_graphs = !o->report.empty();
    Progress progress(!global.quiet);
    progress.phase("lab: every alternative");
    const LabResult result = run_lab(cloud.positions, options);
    progress.stop();
    summary.add(phase_1_report(result.planes, cloud.size()), "tangent_planes");
    print_tables(result, summary);
    record(result, summary);
    summary.stats()["seconds_total"] = total.elapsed();
    if (!o->report.empty()) write_lab_report(o->report, result, o->in.path, summary);
    if (!o->stats.empty()) summary.write_stats(o->stats);
  };
}

}  // namespace recon::cli
