#include "curves.h"

#include "run_reports.h"
#include "summary.h"

#include "recon/core/errors.h"
#include "recon/core/memory_budget.h"
#include "recon/core/parallel.h"
#include "recon/core/timer.h"
#include "recon/curves/reconstruct_curve.h"
#include "recon/io/curve_io.h"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace recon::cli {
namespace {

io::ReadPointsOptions read_options(const std::string& format) {
  io::ReadPointsOptions options;
  if (!format.empty()) options.format = io::point_format_from_name(format);
  return options;
}

StepReport phase_4_report(const MarchingSquaresResult& c) {
  std::ostringstream line;
  line << "phase IV  marching squares: cell = " << format_length(c.cell) << ", " << c.visited_squares
       << " squares visited of " << static_cast<double>(c.size[0]) * c.size[1] << " in the lattice (" << c.size[0]
       << " x " << c.size[1] << "), " << plural(c.saddle_squares, "saddle") << " ("
       << format_seconds(c.seconds - c.seconds_field) << ")";
  return step_report(line.str(), {{"cell", c.cell},
                                  {"lattice_size", lattice_size_json(c.size)},
                                  {"visited_squares", c.visited_squares},
                                  {"undefined_squares", c.undefined_squares},
                                  {"saddle_squares", c.saddle_squares},
                                  {"seconds", c.seconds - c.seconds_field}});
}

StepReport curves_report(const PolylineSet& curves) {
  double total_length = 0.0;
  for (const Polyline& p : curves.polylines) total_length += length(curves, p);
  std::ostringstream line;
  line << "curves    " << plural(curves.polylines.size(), "curve") << ": " << curves.closed_count() << " closed, "
       << curves.open_count() << " open; " << plural(curves.vertices.size(), "vertex") << ", length "
       << format_length(total_length);
  return step_report(line.str(), {{"count", curves.polylines.size()},
                                  {"closed", curves.closed_count()},
                                  {"open", curves.open_count()},
                                  {"vertices", curves.vertices.size()},
                                  {"length", total_length}});
}

void report(const CurveReconstruction& r, std::size_t points, Summary& summary) {
  summary.add(phase_1_report(r.planes, points), "tangent_planes");
  summary.add(phase_2_report(r.oriented), "orientation");
  const MarchingSquaresResult& c = r.contour;
  summary.add(phase_3_report({r.delta, r.delta_given, c.evaluated_corners, c.undefined_corners,
                              r.seconds_distance_setup + c.seconds_field, 0.0}),
              "signed_distance");
  summary.add(phase_4_report(c), "contouring");
  summary.add(curves_report(c.curves), "curves");
}

// The library's options for a 2D run: the curve defaults (k = 8, raised for
// noisy data) unless k is given.
CurveReconstructionOptions curve_options(const ReconstructCommandOptions& o, std::size_t points) {
  CurveReconstructionOptions options;
  if (o.phases.k_option->count() > 0) {
    options.planes.k = o.phases.k;
    options.planes.adapt_k = false;
  }
  options.planes.rho = o.phases.rho;
  options.distance.delta = o.delta;
  options.cell = o.cell;
  options.resolution = o.resolution;
  const std::size_t limit = memory_limit_or_default(o.phases.max_memory);
  check_memory_planes_and_graph(points, options.planes.k, limit);
  options.max_squares = max_squares_within(limit);
  return options;
}

std::vector<Vec2> read_input_2d(const ReconstructCommandOptions& o, Summary& summary,
                                std::optional<io::PointSource>& opened) {
  Timer timer;
  std::vector<Vec2> points = opened ? io::read_points_2d(*opened, read_options(o.in.format))
                                    : io::read_points_2d(o.in.path, read_options(o.in.format));
  opened.reset();
  summary.say("read      " + o.in.path.string() + ": " + plural(points.size(), "point") + " in 2D (" +
              format_seconds(timer.elapsed()) + ")");
  put(summary.stats()["input"],
      {{"file", o.in.path.string()}, {"points", points.size()}, {"dimension", 2}, {"seconds", timer.elapsed()}});
  return points;
}

}  // namespace

bool wants_curves(const std::filesystem::path& input, const std::string& format, const std::filesystem::path& output,
                  const io::PointSource* opened) {
  std::string extension = output.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (extension == ".svg" || extension == ".txt") return true;
  return opened != nullptr ? io::holds_2d_points(*opened, read_options(format))
                           : io::holds_2d_points(input, read_options(format));
}

void reconstruct_curves(const ReconstructCommandOptions& o, bool quiet, std::optional<io::PointSource>& opened) {
  if (!o.report.empty())
    throw InvalidInputError(
        "--report draws 3D reconstructions; for curves, the SVG output shows the points, "
        "their normals and the curves (and the playground, web/playground, every phase)");
  check_outputs(o.in.path, {o.output, o.stats});
  Timer total;
  Summary summary(quiet);
  io::WriteCurvesOptions write_options;
  write_options.format = io::curve_format_from_path(o.output);  // fail early on a bad extension
  if (o.use_normals)
    throw InvalidInputError("--use-normals: 2D inputs carry no normals; run without the option to estimate them");
  // Options the 2D readers do not apply are refused rather than ignored.
  if (!o.in.columns.empty())
    throw InvalidInputError(
        "--columns names 3D columns; 2D points are read as two columns, x y, or from a 3D "
        "file with a constant coordinate: drop --columns");
  if (o.in.skip_invalid)
    throw InvalidInputError("--skip-invalid is not applied to 2D points; drop it and mend the input");

  const std::vector<Vec2> points = read_input_2d(o, summary, opened);
  const CurveReconstruction r = reconstruct_curve(points, curve_options(o, points.size()));
  report(r, points.size(), summary);

  Timer write_timer;
  write_options.points = points;
  write_options.normals = r.oriented.normals;
  write_options.normal_length = r.planes.rho;
  io::write_curves(o.output, r.contour.curves, write_options);
  finish_run(summary, o.output, write_timer.elapsed(), total.elapsed());
  if (!o.stats.empty()) summary.write_stats(o.stats);
}

}  // namespace recon::cli
