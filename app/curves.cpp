#include "curves.h"

#include "summary.h"

#include "recon/errors.h"
#include "recon/io/curve_io.h"
#include "recon/parallel.h"
#include "recon/memory_budget.h"
#include "recon/reconstruct_curve.h"
#include "recon/timer.h"

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

void report(const CurveReconstruction& r, std::size_t points, Summary& summary) {
  const TangentPlanes<2>& planes = r.planes;
  std::ostringstream line;
  line << "phase I   tangent lines: k = " << planes.k;
  if (planes.k != planes.k_requested)
    line << " (raised from " << planes.k_requested << ": noise " << format_length(planes.noise) << " is large)";
  line << ", rho = " << format_length(planes.rho) << (planes.rho_given ? " (given)" : " (estimated)") << ", "
       << plural(points - planes.distinct_points, "duplicate") << ", "
       << plural(planes.isolated, "isolated point") << " ("
       << format_seconds(planes.seconds_tree + planes.seconds_knn_pca + planes.seconds_spacing) << ")";
  summary.say(line.str());
  Json& s1 = summary.stats()["tangent_planes"];
  s1["k"] = planes.k;
  s1["k_requested"] = planes.k_requested;
  s1["rho"] = planes.rho;
  s1["rho_estimated"] = !planes.rho_given;
  s1["noise"] = planes.noise;
  s1["distinct_points"] = planes.distinct_points;
  s1["isolated_points"] = planes.isolated;
  s1["seconds"] = planes.seconds_tree + planes.seconds_knn_pca + planes.seconds_spacing;

  const OrientedNormals<2>& o = r.oriented;
  line.str("");
  line << "phase II  orientation: " << plural(o.component_count(), "component") << ", graph of "
       << plural(o.graph.edge_count, "edge") << ", " << plural(o.flip_count, "flip") << " ("
       << format_seconds(o.graph.seconds_emst + o.graph.seconds_graph + o.seconds_mst) << ")";
  summary.say(line.str());
  Json& s2 = summary.stats()["orientation"];
  s2["components"] = o.component_count();
  s2["graph_edges"] = o.graph.edge_count;
  s2["flips"] = o.flip_count;
  s2["seconds"] = o.graph.seconds_emst + o.graph.seconds_graph + o.seconds_mst;

  const MarchingSquaresResult& c = r.contour;
  line.str("");
  line << "phase III signed distance: delta = " << format_length(r.delta) << (r.delta_given ? " (given)" : " (estimated)")
       << ", " << c.evaluated_corners << " lattice corners evaluated, " << c.undefined_corners << " undefined ("
       << format_seconds(r.seconds_distance_setup + c.seconds_field) << ")";
  summary.say(line.str());
  Json& s3 = summary.stats()["signed_distance"];
  s3["delta"] = r.delta;
  s3["delta_estimated"] = !r.delta_given;
  s3["corners_evaluated"] = c.evaluated_corners;
  s3["corners_undefined"] = c.undefined_corners;
  s3["seconds"] = r.seconds_distance_setup + c.seconds_field;

  line.str("");
  line << "phase IV  marching squares: cell = " << format_length(c.cell) << ", " << c.visited_squares
       << " squares visited of " << static_cast<double>(c.size[0]) * c.size[1] << " in the lattice (" << c.size[0]
       << " x " << c.size[1] << "), " << plural(c.saddle_squares, "saddle") << " ("
       << format_seconds(c.seconds - c.seconds_field) << ")";
  summary.say(line.str());
  Json& s4 = summary.stats()["contouring"];
  s4["cell"] = c.cell;
  s4["lattice_size"] = Json(Json::Array{Json(static_cast<std::size_t>(c.size[0])), Json(static_cast<std::size_t>(c.size[1]))});
  s4["visited_squares"] = c.visited_squares;
  s4["undefined_squares"] = c.undefined_squares;
  s4["saddle_squares"] = c.saddle_squares;
  s4["seconds"] = c.seconds - c.seconds_field;

  const PolylineSet& curves = c.curves;
  double total_length = 0.0;
  for (const Polyline& p : curves.polylines) total_length += length(curves, p);
  line.str("");
  line << "curves    " << plural(curves.polylines.size(), "curve") << ": " << curves.closed_count()
       << " closed, " << curves.open_count() << " open; " << plural(curves.vertices.size(), "vertex")
       << ", length " << format_length(total_length);
  summary.say(line.str());
  Json& s5 = summary.stats()["curves"];
  s5["count"] = curves.polylines.size();
  s5["closed"] = curves.closed_count();
  s5["open"] = curves.open_count();
  s5["vertices"] = curves.vertices.size();
  s5["length"] = total_length;
}

}  // namespace

bool wants_curves(const std::filesystem::path& input, const std::string& format, const std::filesystem::path& output) {
  std::string extension = output.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (extension == ".svg" || extension == ".txt") return true;
  return io::holds_2d_points(input, read_options(format));
}

void reconstruct_curves(const CurveRun& run) {
  Timer total;
  Summary summary(run.quiet);
  io::WriteCurvesOptions write_options;
  write_options.format = io::curve_format_from_path(run.output);  // fail early on a bad extension
  if (run.use_normals)
    throw InvalidInputError("--use-normals: 2D inputs carry no normals; run without the option to estimate them");

  Timer timer;
  const std::vector<Vec2> points = io::read_points_2d(run.input, read_options(run.format));
  summary.say("read      " + run.input.string() + ": " + plural(points.size(), "point") + " in 2D (" +
              format_seconds(timer.elapsed()) + ")");
  summary.stats()["input"]["file"] = run.input.string();
  summary.stats()["input"]["points"] = points.size();
  summary.stats()["input"]["dimension"] = 2;
  summary.stats()["input"]["seconds"] = timer.elapsed();

  CurveReconstructionOptions options;
  if (run.k) {
    options.planes.k = *run.k;
    options.planes.adapt_k = false;
  }
  options.planes.rho = run.rho;
  options.distance.delta = run.delta;
  options.cell = run.cell;
  options.resolution = run.resolution;
  const std::size_t limit = memory_limit_or_default(run.max_memory);
  check_memory_planes_and_graph(points.size(), options.planes.k, limit);
  options.max_squares = max_squares_within(limit);
  const CurveReconstruction r = reconstruct_curve(points, options);
  report(r, points.size(), summary);

  Timer write_timer;
  write_options.points = points;
  write_options.normals = r.oriented.normals;
  write_options.normal_length = r.planes.rho;
  io::write_curves(run.output, r.contour.curves, write_options);
  summary.say("wrote     " + run.output.string() + " (" + format_seconds(write_timer.elapsed()) + "); total " +
              format_seconds(total.elapsed()));
  summary.stats()["output"]["file"] = run.output.string();
  summary.stats()["output"]["seconds"] = write_timer.elapsed();
  summary.stats()["threads"] = thread_count();
  summary.stats()["seconds_total"] = total.elapsed();
  if (!run.stats.empty()) summary.write_stats(run.stats);
}

}  // namespace recon::cli
