#include "tiled.h"

#include "progress.h"
#include "run_reports.h"

#include "recon/core/errors.h"
#include "recon/core/memory_budget.h"
#include "recon/core/resource_usage.h"
#include "recon/core/timer.h"
#include "recon/io/mesh_io.h"
#include "recon/tiles/tiles.h"

#include <atomic>
#include <cmath>
#include <sstream>
#include <string>

namespace recon::cli {
namespace {

// Fewer bytes than this a point cannot take in any point format ("0 0 0\n").
constexpr std::uintmax_t least_bytes_per_point = 6;

std::size_t count_points(const InputOptions& in) {
  std::size_t count = 0;
  pass_over_file(in.path, read_options(in))([&](PointCloudView chunk, std::size_t) { count += chunk.size(); });
  return count;
}

std::string memory_text(double bytes) {
  std::ostringstream out;
  out.precision(3);
  out << bytes / 1e9 << " GB";
  return out.str();
}

}  // namespace

std::optional<std::string> tiling_reason(const ReconstructCommandOptions& o, const ReconstructionOptions& options) {
  if (o.tile_size > 0.0) return std::string("--tile-size");
  std::error_code error;
  const std::uintmax_t bytes = std::filesystem::file_size(o.in.path, error);
  if (error) return std::nullopt;  // (a pipe, a device: read as usual, which says what is wrong)
  const std::size_t limit = memory_limit_or_default(options.max_memory);
  const bool refined = options.method == Method::refined;
  const auto needs = [&](std::size_t n) { return estimated_bytes_reconstruction(n, options.planes.k, refined); };
  if (needs(static_cast<std::size_t>(bytes / least_bytes_per_point)) <= static_cast<double>(limit)) return std::nullopt;
  const std::size_t points = count_points(o.in);
  if (needs(points) <= static_cast<double>(limit)) return std::nullopt;
  return plural(points, "point") + " need about " + memory_text(needs(points)) + ", more than --max-memory " +
         memory_text(static_cast<double>(limit));
}

namespace {

void refuse_what_tiles_do_not_do(const ReconstructCommandOptions& o) {
  const auto refuse = [](const std::string& what) {
    throw InvalidInputError("tiled runs (--tile-size, or clouds larger than --max-memory) " + what);
  };
  if (io::mesh_format_from_path(o.output) != io::MeshFormat::ply) refuse("write binary PLY: name the output .ply");
  if (o.ascii) refuse("write binary PLY: drop --ascii");
  if (o.use_normals) refuse("estimate and orient the normals: drop --use-normals");
  if (!o.report.empty()) refuse("write no report: drop --report");
  // The stitched mesh goes straight to the file, never whole in memory.
  if (!o.simplify.empty() || o.max_error)
    refuse(
        "do not simplify (the mesh is never whole in memory): drop --simplify and --max-error, and simplify the tiled "
        "mesh afterwards with `recon simplify MESH -o OUT --to T`");
}

StepReport plan_report(const TilePlan& plan, const std::string& why) {
  std::uint64_t binned = 0;
  for (const TileInfo& t : plan.tiles) binned += t.points;
  const double edge = plan.tile_cubes * plan.lattice.cell;
  StepReport r;
  r.lines.push_back("tiles     " + why + ": " + plural(plan.tiles.size(), "tile") + " with a core edge of " +
                    format_length(edge) + " and a halo of " + format_length(plan.halo) + "; " +
                    plural(plan.input_points, "point") + " binned as " + std::to_string(binned) + " (" +
                    format_seconds(plan.seconds_bounds + plan.seconds_binning) + ")");
  r.lines.push_back("          cloud-wide: k = " + std::to_string(plan.k) +
                    ", rho = " + format_length(plan.spacing.rho) + ", cell " + format_length(plan.lattice.cell) +
                    ", from phase I on " + plural(plan.statistics_points, "point") +
                    (plan.statistics_over_tiles ? " measured over the tiles" : "") + " (" +
                    format_seconds(plan.seconds_statistics) + ")");
  if (plan.statistics_inexact > 0)
    r.lines.push_back("          " + plural(plan.statistics_inexact, "sample") +
                      " measured with a neighbourhood that may reach past its tile (halo too narrow)");
  put(r.stats, {{"reason", why},
                {"tiles", plan.tiles.size()},
                {"core_edge", edge},
                {"halo", plan.halo},
                {"points_binned", static_cast<double>(binned)},
                {"statistics_points", static_cast<double>(plan.statistics_points)},
                {"statistics_over_tiles", plan.statistics_over_tiles},
                {"statistics_inexact", static_cast<double>(plan.statistics_inexact)},
                {"k", plan.k},
                {"rho", plan.spacing.rho},
                {"cell", plan.lattice.cell},
                {"seconds_plan", plan.seconds_bounds + plan.seconds_statistics + plan.seconds_binning}});
  return r;
}

StepReport run_report(const TiledRun& run) {
  const TileReconciliation& c = run.reconciliation;
  double orient = 0.0, contour = 0.0;
  std::size_t inexact = 0;
  Json::Array per_tile;
  for (std::size_t t = 0; t < run.plan.tiles.size(); ++t) {
    const TileOrientation& o = run.orientations[t];
    orient += o.seconds;
    contour += run.contours[t].seconds;
    inexact += o.inexact_samples;
    Json tile;
    put(tile, {{"points", o.points},
               {"pieces", o.pieces},
               {"inexact_samples", o.inexact_samples},
               {"triangles", run.contours[t].triangles},
               {"seconds_orient", o.seconds},
               {"seconds_contour", run.contours[t].seconds}});
    per_tile.push_back(tile);
  }
  StepReport r;
  r.lines.push_back("orient    " + plural(c.nodes, "piece") + " in the tiles, " + plural(c.objects, "object") + "; " +
                    std::to_string(c.turned) + " turned round to agree (" + std::to_string(c.disagreeing) + " of " +
                    std::to_string(c.shared_samples) + " shared samples still disagree) (" + format_seconds(orient) +
                    ")");
  if (c.nested_turned > 0)
    r.lines.push_back("          " + plural(c.nested_turned, "nested object") + " turned to face its cavity");
  if (inexact > 0)
    r.lines.push_back("          " + plural(inexact, "sample") +
                      " near a core may see less than the whole cloud (halo too narrow)");
  r.lines.push_back("contour   " + plural(run.mesh.triangles, "triangle") + " (" + format_seconds(contour) +
                    "); stitched with " + std::to_string(run.mesh.welded) + " vertices welded at tile borders (" +
                    format_seconds(run.mesh.seconds) + ")");
  put(r.stats, {{"objects", c.objects},
                {"pieces", c.nodes},
                {"pieces_turned", c.turned},
                {"shared_samples", c.shared_samples},
                {"disagreeing_samples", c.disagreeing},
                {"objects_nested", c.objects_nested},
                {"nested_turned", c.nested_turned},
                {"inexact_samples", inexact},
                {"welded_vertices", run.mesh.welded}});
  if (run.plan.method == Method::refined) {
    const StitchedMesh& m = run.mesh;
    r.lines.push_back("refine    " + plural(m.crease_vertices, "vertex") + " added on creases; " +
                      plural(m.trimmed, "triangle") + " trimmed past open boundaries, " +
                      plural(m.stray_triangles, "stray triangle") + ", " + plural(m.fragments, "fragment") + " (" +
                      plural(m.fragment_triangles, "triangle") + ") dropped, over the whole mesh");
    put(r.stats, {{"crease_vertices", m.crease_vertices},
                  {"trimmed_triangles", m.trimmed},
                  {"stray_triangles", m.stray_triangles},
                  {"fragments", m.fragments},
                  {"fragment_triangles", m.fragment_triangles}});
  }
  put(r.stats, {{"seconds_orient", orient},
                {"seconds_reconcile", c.seconds},
                {"seconds_contour", contour},
                {"seconds_stitch", run.mesh.seconds},
                {"per_tile", Json(per_tile)}});
  return r;
}

}  // namespace

void run_tiled(const ReconstructCommandOptions& o, const ReconstructionOptions& options, const std::string& why,
               const GlobalOptions& global) {
  Timer total;
  refuse_what_tiles_do_not_do(o);
  Summary summary(global.quiet);
  TilingOptions tiling;
  tiling.reconstruction = options;
  if (o.in.no_colors) tiling.reconstruction.mesh_colors = false;  // (the tiles then hold none)
  tiling.tile_size = o.tile_size;
  const std::filesystem::path parent = !o.tmpdir.empty() ? o.tmpdir : std::filesystem::absolute(o.output).parent_path();
  TileWorkspace workspace(parent);
  // The line follows the step, counting its tiles when there are several:
  // "recon: orienting [####....]  40%  (8 / 20 tiles)  ~3 min left".
  ProgressCounter tiles_done, points_done;
  tiling.progress = &points_done;
  std::string step_now;
  Progress progress(!global.quiet);
  const TiledRun run =
      reconstruct_tiled(pass_over_file(o.in.path, read_options(o.in)), tiling, workspace.path(), o.output,
                        [&](const char* step, std::size_t done, std::size_t total_tiles) {
                          if (step != step_now) {
                            step_now = step;
                            tiles_done.start(total_tiles > 1 ? total_tiles : 0);
                            if (step_now == "planning")  // the passes over the input count their points
                              progress.phase("planning", &points_done, "points");
                            else
                              progress.phase(step_now, &tiles_done, "tiles");
                          }
                          tiles_done.done.store(done, std::memory_order_relaxed);
                        });
  progress.stop();
  summary.stats()["input"]["file"] = o.in.path.string();
  summary.stats()["input"]["points"] = static_cast<double>(run.plan.input_points);
  summary.add(plan_report(run.plan, why), "tiled");
  summary.add(run_report(run), "tiled", "run");
  summary.say("mesh      " + plural(run.mesh.vertices, "vertex") + ", " + plural(run.mesh.triangles, "triangle") +
              (run.plan.method == Method::refined ? " (refined, phase V included" : " (hoppe92") +
              (run.plan.colors ? ", with colours)" : ")"));
  summary.stats()["mesh"]["vertices"] = run.mesh.vertices;
  summary.stats()["mesh"]["triangles"] = run.mesh.triangles;
  summary.stats()["mesh"]["has_colors"] = run.plan.colors;
  if (const std::optional<std::size_t> peak = peak_resident_bytes())
    summary.stats()["memory"]["peak_mib_total"] = static_cast<double>(*peak) / (1024.0 * 1024.0);
  finish_run(summary, o.output, run.mesh.seconds, total.elapsed());
  if (!o.stats.empty()) summary.write_stats(o.stats);
}

}  // namespace recon::cli
