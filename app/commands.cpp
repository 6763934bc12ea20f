#include "commands.h"
#include "command_parts.h"

#include "curves.h"
#include "progress.h"
#include "summary.h"

#include "recon/errors.h"
#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"
#include "recon/mesh.h"
#include "recon/reconstruct.h"
#include "recon/report.h"
#include "recon/resource_usage.h"
#include "recon/orientation.h"
#include "recon/parallel.h"
#include "recon/shapes.h"
#include "recon/spatial_order.h"  // permuted
#include "recon/tangent_planes.h"
#include "recon/timer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <sstream>

namespace recon::cli {

void add_input(CLI::App& app, InputOptions& in) {
  app.add_option("input", in.path, "Point cloud (.ply .xyz .txt .csv .pts .obj .off .pcd .las)")->required();
  app.add_option("--format", in.format,
                 "Input format when the extension does not say: ply, xyz, pts, obj, off, pcd, las");
  app.add_option("--columns", in.columns,
                 "What each column of a text file without a header holds, e.g. x,y,z,_,r,g,b "
                 "(x y z, nx ny nz, r g b, _ to skip a column)");
  app.add_flag("--skip-invalid", in.skip_invalid,
               "Skip points with a coordinate that is NaN, infinite or beyond 1e15 instead of refusing the file");
  app.add_flag("--no-colors", in.no_colors, "Drop the input's colours (the mesh or cloud is written without)");
}

namespace {
// "x,y,z,_,r,g,b" -> {"x", "y", "z", "_", "r", "g", "b"}.
std::vector<std::string> split_columns(const std::string& text) {
  std::vector<std::string> names;
  std::size_t start = 0;
  while (start <= text.size() && !text.empty()) {
    const std::size_t comma = text.find(',', start);
    const std::size_t end = comma == std::string::npos ? text.size() : comma;
    names.push_back(text.substr(start, end - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return names;
}
}  // namespace

// Peak memory per step for --stats (resource_usage.h): ends the last step
// and writes "memory": {"peak_mib": {step: MiB, ...}, "peak_mib_total": the
// largest}.
void report_memory(StepPeaks& memory, Summary& summary) {
  memory.finish();
  if (memory.peaks().empty()) return;
  Json& m = summary.stats()["memory"];
  double largest = 0.0;
  for (const auto& [step, mib] : memory.peaks()) {
    m["peak_mib"][step] = mib;
    largest = std::max(largest, mib);
  }
  m["peak_mib_total"] = largest;
}

PointCloud read_input(const InputOptions& in, Summary& summary) {
  Timer timer;
  io::ReadPointsOptions options;
  if (!in.format.empty()) options.format = io::point_format_from_name(in.format);
  options.columns = split_columns(in.columns);
  options.skip_invalid = in.skip_invalid;
  io::ReadNotes notes;
  PointCloud cloud = io::read_points(in.path, options, &notes);
  if (in.no_colors) cloud.colors = {};
  const char* extras = cloud.has_normals() ? (cloud.has_colors() ? " with normals and colours" : " with normals")
                                           : (cloud.has_colors() ? " with colours" : "");
  summary.say("read      " + in.path.string() + ": " + plural(cloud.size(), "point") + extras + " (" +
              format_seconds(timer.elapsed()) + ")");
  for (const std::string& line : notes.lines) summary.say("          " + line);
  summary.stats()["input"]["file"] = in.path.string();
  summary.stats()["input"]["points"] = cloud.size();
  summary.stats()["input"]["has_normals"] = cloud.has_normals();
  summary.stats()["input"]["has_colors"] = cloud.has_colors();
  summary.stats()["input"]["skipped_points"] = notes.skipped_points;
  summary.stats()["input"]["seconds"] = timer.elapsed();
  return cloud;
}

namespace {
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code ec;
  if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) return std::filesystem::equivalent(a, b, ec);
  return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
}
}  // namespace

// Checks made before any work, so that a run that cannot write its results
// fails at once: outputs must not be the input or each other, and their
// folders must exist.
void check_outputs(const std::filesystem::path& input, const std::vector<std::filesystem::path>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& out = outputs[i];
    if (out.empty()) continue;
    if (!input.empty() && same_file(input, out))
      throw InvalidInputError("refusing to overwrite the input file " + input.string() + "; choose another output");
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].empty() && same_file(outputs[j], out))
        throw InvalidInputError(out.string() + " is named for two outputs; give each its own file");
    std::filesystem::path folder = out.parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec))
      throw IoError(out.string() + ": cannot write: folder '" + folder.string() + "' does not exist");
    if (std::filesystem::is_directory(out, ec))
      throw IoError(out.string() + ": cannot write: it is a folder");
  }
}

// --report FILE.html, shared by reconstruct and normals.
void add_report_option(CLI::App& app, std::filesystem::path& report) {
  app.add_option("--report", report,
                 "Also write an interactive HTML report of every phase (one self-contained file, opens offline)");
}

ReportOptions run_report_options(const std::filesystem::path& source, Summary& summary) {
  ReportOptions options;
  options.title = source.filename().string();
  options.stats_json = summary.stats().dump(0);
  return options;
}

namespace {
// Writes the report of a finished run.
void write_run_report(const std::filesystem::path& path, const ReportInput& input, const std::filesystem::path& source,
                      Summary& summary) {
  Timer timer;
  const ReportOptions options = run_report_options(source, summary);
  const ReportLayers layers = make_report_layers(input, options);
  write_report(path, layers, options);
  summary.say("wrote     " + path.string() + " (report: " + std::to_string(layers.points.size() / 3) + " of " +
              std::to_string(layers.points_total) + " points drawn; " + format_seconds(timer.elapsed()) + ")");
}

// The formats write_points can write.
io::PointFormat writable_point_format(const std::filesystem::path& path) {
  const io::PointFormat format = io::point_format_from_path(path);
  if (format != io::PointFormat::ply && format != io::PointFormat::xyz)
    throw InvalidInputError(path.string() + ": oriented clouds are written as .ply or .xyz");
  return format;
}

// "800M", "2G", "1.5 GB", "3000000000": bytes (K, M, G, T are powers of 1000,
// as in the messages; a trailing 'B' or 'iB' is allowed: KiB, MiB... powers of 1024).
std::string parse_size(const std::string& text, std::size_t& bytes) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return "expected a size such as 800M or 2G, found '" + text + "'";
  }
  if (!std::isfinite(value)) return "expected a size such as 800M or 2G, found '" + text + "'";
  std::string unit = text.substr(used);
  unit.erase(std::remove(unit.begin(), unit.end(), ' '), unit.end());
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  static const std::pair<const char*, double> units[] = {
      {"", 1.0},      {"B", 1.0},      {"K", 1e3},        {"KB", 1e3},       {"KIB", 1024.0},
      {"M", 1e6},     {"MB", 1e6},     {"MIB", 1048576.0}, {"G", 1e9},        {"GB", 1e9},
      {"GIB", 1073741824.0}, {"T", 1e12}, {"TB", 1e12},    {"TIB", 1099511627776.0}};
  for (const auto& [name, factor] : units) {
    if (unit != name) continue;
    const double b = value * factor;
    if (!(b >= 1e6) || !(b < 1e18)) return "a memory limit must be between 1M and 1000000T, found '" + text + "'";
    bytes = static_cast<std::size_t>(b);
    return "";
  }
  return "unknown size unit in '" + text + "' (use K, M, G or T)";
}
}  // namespace

void add_phase_options(CLI::App& app, PhaseOptions& p) {
  p.k_option = app.add_option("-k,--k", p.k,
                              "Neighbours per tangent plane, the point itself included (default 20, 8 for curves; raised "
                              "automatically for noisy data unless given)")
                   ->check(CLI::Range(3, 256));
  app.add_option("--rho", p.rho,
                 "Sampling density: every point of the surface is within this distance of a sample (default: "
                 "estimated per point)")
      ->check(CLI::PositiveNumber);
  app.add_option_function<std::string>(
         "--max-memory",
         [&p](const std::string& text) {
           const std::string error = parse_size(text, p.max_memory);
           if (!error.empty()) throw CLI::ValidationError("--max-memory", error);
         },
         "Refuse work estimated to need more memory than this, e.g. 800M or 16G (default: half the physical "
         "memory)")
      ->type_name("SIZE");
}

TangentPlaneOptions phase_1_options(const PhaseOptions& p) {
  TangentPlaneOptions options;
  options.k = p.k;
  options.adapt_k = p.k_option->count() == 0;
  options.rho = p.rho;
  return options;
}

void report_phase_1(const TangentPlanes<3>& planes, std::size_t points, Summary& summary) {
  std::ostringstream line;
  line << "phase I   tangent planes: k = " << planes.k;
  if (planes.k != planes.k_requested)
    line << " (raised from " << planes.k_requested << ": noise " << format_length(planes.noise) << " is large)";
  line << ", rho = " << format_length(planes.rho)
       << (planes.rho_given ? " (given)" : " (estimated, median of local values)") << ", "
       << plural(points - planes.distinct_points, "duplicate") << ", "
       << plural(planes.degenerate, "degenerate neighbourhood");
  if (planes.isolated > 0) line << ", " << plural(planes.isolated, "isolated point") << " (outliers: no surface)";
  line << " ("
       << format_seconds(planes.seconds_tree + planes.seconds_knn_pca + planes.seconds_spacing) << ")";
  summary.say(line.str());
  Json& s = summary.stats()["tangent_planes"];
  s["k"] = planes.k;
  s["k_requested"] = planes.k_requested;
  s["noise"] = planes.noise;
  s["rho"] = planes.rho;
  s["rho_estimated"] = !planes.rho_given;
  s["distinct_points"] = planes.distinct_points;
  s["degenerate_neighbourhoods"] = planes.degenerate;
  s["isolated_points"] = planes.isolated;
  s["seconds_tree"] = planes.seconds_tree;
  s["seconds_knn_pca"] = planes.seconds_knn_pca;
  s["seconds_spacing"] = planes.seconds_spacing;
}

namespace {

void report_phase_2(const OrientedNormals<3>& oriented, Summary& summary) {
  const auto& g = oriented.graph;
  std::ostringstream line;
  line << "phase II  orientation: " << plural(oriented.component_count(), "component");
  std::vector<std::uint32_t> shown = g.components.sizes;
  std::sort(shown.rbegin(), shown.rend());
  line << " (";
  for (std::size_t c = 0; c < shown.size() && c < 8; ++c) line << (c ? ", " : "") << shown[c];
  if (shown.size() > 8) line << ", ...";
  line << " points), graph of " << plural(g.edge_count, "edge") << ", " << plural(oriented.flip_count, "flip");
  if (oriented.crease_patches_turned > 0)
    line << ", " << plural(oriented.crease_patches_turned, "face") << " turned across a sharp crease";
  line << " (" << format_seconds(g.seconds_emst + g.seconds_graph + oriented.seconds_mst) << ")";
  summary.say(line.str());
  Json& s = summary.stats()["orientation"];
  s["components"] = oriented.component_count();
  Json::Array size_list;
  for (std::uint32_t v : g.components.sizes) size_list.emplace_back(static_cast<std::size_t>(v));
  s["component_sizes"] = Json(size_list);
  s["graph_edges"] = g.edge_count;
  s["gap_edges"] = g.gap_emst_edges;
  s["rejoined_pieces"] = g.rejoined;
  s["flips"] = oriented.flip_count;
  s["seconds_emst"] = g.seconds_emst;
  s["seconds_graph"] = g.seconds_graph;
  s["seconds_mst"] = oriented.seconds_mst;
  s["vote_flips"] = oriented.vote_flips;
  s["sheet_edges"] = oriented.sheet_edges;
  s["crease_patches_turned"] = oriented.crease_patches_turned;
  s["components_turned"] = oriented.components_turned;
}

// Without a report only the mesh is needed once the phases are reported:
// the rest goes before the mesh's topology is measured, the run's last
// large allocation (it lowers the peak of a refined run by the 1992 mesh).
void release_all_but_the_mesh(Reconstruction& r) {
  if (r.refinement) r.contour.mesh = {};
  r.origin_tree = {};
  r.planes = {};
  r.quadrics.reset();
  r.oriented.reset();
  r.input_normals = {};
  r.colors = {};
}

void report_phases_3_4(const Reconstruction& r, Summary& summary) {
  const MarchingCubesResult& c = r.contour;
  std::ostringstream line;
  line << "phase III signed distance: delta = " << format_length(r.delta) << (r.delta_given ? " (given)" : " (estimated)")
       << ", " << c.evaluated_corners << " lattice corners evaluated, " << c.undefined_corners << " undefined ("
       << format_seconds(r.seconds_distance_setup + c.seconds_field);
  if (r.seconds_distance_beside > 0.0) line << ", and " << format_seconds(r.seconds_distance_beside) << " beside phase II";
  line << ")";
  summary.say(line.str());
  line.str("");
  line << "phase IV  contouring: cell = " << format_length(c.cell) << ", " << c.visited_cubes << " cubes visited of "
       << static_cast<double>(c.size[0]) * c.size[1] * c.size[2] << " in the lattice (" << c.size[0] << " x "
       << c.size[1] << " x " << c.size[2] << "), " << format_seconds(c.seconds - c.seconds_field);
  summary.say(line.str());
  Json& s = summary.stats()["signed_distance"];
  s["delta"] = r.delta;
  s["delta_estimated"] = !r.delta_given;
  s["corners_evaluated"] = c.evaluated_corners;
  s["corners_undefined"] = c.undefined_corners;
  s["seconds"] = r.seconds_distance_setup + c.seconds_field;
  s["seconds_beside_orientation"] = r.seconds_distance_beside;
  Json& m = summary.stats()["contouring"];
  m["cell"] = c.cell;
  m["lattice_size"] = Json(Json::Array{Json(static_cast<std::size_t>(c.size[0])), Json(static_cast<std::size_t>(c.size[1])),
                                       Json(static_cast<std::size_t>(c.size[2]))});
  m["seed_cubes"] = c.seed_cubes;
  m["visited_cubes"] = c.visited_cubes;
  m["undefined_cubes"] = c.undefined_cubes;
  m["seconds"] = c.seconds - c.seconds_field;
}

void report_quadrics(const LocalQuadrics& q, Summary& summary) {
  std::ostringstream line;
  line << "          second-order fits: " << plural(q.borrowed, "sample") << " near creases took a neighbour's, "
       << plural(q.split, "neighbourhood") << " split between two sheets, " << plural(q.flat, "flat fit") << " ("
       << format_seconds(q.seconds) << ")";
  summary.say(line.str());
  Json& s = summary.stats()["tangent_planes"]["quadrics"];
  s["borrowed"] = q.borrowed;
  s["split_sheets"] = q.split;
  s["flat"] = q.flat;
  s["seconds"] = q.seconds;
}

void report_refinement(const Refinement& r, Summary& summary) {
  double moved = 0.0;
  for (const float d : r.displacement) moved += static_cast<double>(d);
  moved /= static_cast<double>(std::max<std::size_t>(1, r.displacement.size()));
  std::ostringstream line;
  line << "phase V   refinement: vertices moved " << format_length(moved) << " on average, "
       << plural(r.crease_vertices, "crease vertex") << " added, " << r.brought_back
       << " brought back onto a crease, " << plural(r.corner_vertices, "corner") << ", "
       << plural(r.trimmed, "triangle") << " past open boundaries cut off, ";
  if (r.stray_triangles > 0) line << plural(r.stray_triangles, "triangle") << " beyond the data's reach dropped, ";
  line << plural(r.fragments, "fragment") << " dropped (" << plural(r.fragment_triangles, "triangle") << ") ("
       << format_seconds(r.seconds) << ")";
  summary.say(line.str());
  Json& s = summary.stats()["refinement"];
  s["mean_displacement"] = moved;
  s["crease_vertices"] = r.crease_vertices;
  s["brought_back"] = r.brought_back;
  s["corner_vertices"] = r.corner_vertices;
  s["unmoved_vertices"] = r.unmoved;
  s["trimmed_triangles"] = r.trimmed;
  s["stray_triangles"] = r.stray_triangles;
  s["fragments"] = r.fragments;
  s["fragment_triangles"] = r.fragment_triangles;
  s["seconds"] = r.seconds;
}

// The mesh's colours, when the input had some.
void report_colors(const Reconstruction& r, const VertexColorOptions& options, Summary& summary) {
  if (!r.mesh().has_colors()) return;
  std::ostringstream line;
  line << "colours   mesh vertices coloured from the samples: inverse-distance blend of the " << options.k
       << " nearest (" << format_seconds(r.seconds_colors) << ")";
  summary.say(line.str());
  Json& s = summary.stats()["colors"];
  s["k"] = options.k;
  s["seconds"] = r.seconds_colors;
}

void report_mesh(const Mesh& mesh, Summary& summary) {
  const MeshTopology t = analyze_topology(mesh);
  std::ostringstream line;
  line << "mesh      " << plural(t.vertices, "vertex") << ", " << plural(t.triangles, "triangle") << ", "
       << plural(t.components, "component") << ", "
       << (t.boundary_loops == 0 ? std::string("closed") : plural(t.boundary_loops, "boundary loop"))
       << ", Euler characteristic " << t.euler_characteristic;
  summary.say(line.str());
  Json& m = summary.stats()["mesh"];
  m["vertices"] = t.vertices;
  m["faces"] = t.triangles;
  m["components"] = t.components;
  m["boundary_edges"] = t.boundary_edges;
  m["boundary_loops"] = t.boundary_loops;
  m["non_manifold_edges"] = t.non_manifold_edges;
  m["euler_characteristic"] = static_cast<double>(t.euler_characteristic);
  m["area"] = t.area;
  m["signed_volume"] = t.signed_volume;
  m["has_colors"] = mesh.has_colors();
}

}  // namespace

Command add_reconstruct(CLI::App& app, const GlobalOptions& global) {
  struct Options {
    InputOptions in;
    PhaseOptions phases;
    std::filesystem::path output, stats, report;
    std::optional<double> delta, cell;
    std::optional<int> resolution;
    bool ascii = false, use_normals = false, keep_fragments = false;
    std::string method = "refined";
  };
  auto o = std::make_shared<Options>();
  add_input(app, o->in);
  app.add_option("-o,--output", o->output, "Mesh to write (.ply .obj .off .stl); for 2D points, curves (.svg .obj .txt)")
      ->required();
  app.add_option("--method", o->method,
                 "refined (default: second-order fits, a finer lattice, the mesh moved onto the fitted surface, "
                 "creases sharpened, fragments dropped) or hoppe92 (the 1992 paper's four phases exactly)")
      ->check(CLI::IsMember({"refined", "hoppe92"}));
  app.add_flag("--keep-fragments", o->keep_fragments,
               "Keep small mesh components next to larger ones drawn from the same data (refined)");
  add_phase_options(app, o->phases);
  app.add_option("--delta", o->delta, "Noise level, a length (default: estimated from the tangent-plane fits)")
      ->check(CLI::NonNegativeNumber);
  auto* cell = app.add_option("--cell", o->cell, "Lattice cube side, a length (default: rho)")
                   ->check(CLI::PositiveNumber);
  app.add_option("--resolution", o->resolution, "Lattice cubes along the longest side of the bounding box")
      ->check(CLI::Range(1, 1 << 20))
      ->excludes(cell);
  app.add_flag("--use-normals", o->use_normals, "Use the input's own normals (skips phase II)");
  app.add_flag("--ascii", o->ascii, "Write ASCII PLY instead of binary");
  app.add_option("--stats", o->stats, "Also write the run's figures as JSON to this file");
  add_report_option(app, o->report);
  return [o, &global] {
    if (wants_curves(o->in.path, o->in.format, o->output)) {  // 2D points: curves (curves.cpp)
      if (!o->report.empty())
        throw InvalidInputError("--report draws 3D reconstructions; for curves, the SVG output shows the points, "
                                "their normals and the curves (and the playground, web/playground, every phase)");
      check_outputs(o->in.path, {o->output, o->stats});
      const auto& p = o->phases;
      reconstruct_curves({o->in.path, o->output, o->stats, o->in.format,
                          p.k_option->count() > 0 ? std::optional<int>(p.k) : std::nullopt, p.rho, o->delta, o->cell,
                          o->resolution, p.max_memory, o->use_normals, global.quiet});
      return;
    }
    Timer total;
    Summary summary(global.quiet);
    io::WriteMeshOptions write_options;
    write_options.format = io::mesh_format_from_path(o->output);  // fail early on a bad extension
    write_options.ascii = o->ascii;
    check_outputs(o->in.path, {o->output, o->stats, o->report});
    StepPeaks memory;
    memory.start("read");
    PointCloud cloud = read_input(o->in, summary);
    const std::size_t points = cloud.size();

    ReconstructionOptions options;
    options.method = method_from_name(o->method);
    options.refinement.keep_fragments = o->keep_fragments;
    options.planes = phase_1_options(o->phases);
    options.distance.delta = o->delta;
    options.cell = o->cell;
    options.resolution = o->resolution;
    options.use_input_normals = o->use_normals;
    options.max_memory = o->phases.max_memory;
    // Without a report only the counts are reported; the report draws the
    // graph and the evaluated corners.
    options.keep_graph = !o->report.empty();
    options.keep_corners = !o->report.empty();
    Progress progress(!global.quiet);
    options.on_phase = [&progress, &memory](const char* phase) {
      progress.phase(phase);
      memory.start(phase);
    };
    Reconstruction r = reconstruct(std::move(cloud), options);
    progress.stop();
    memory.start("summary");  // the mesh's topology, for the report below

    report_phase_1(r.planes, points, summary);
    summary.stats()["method"] = method_name(r.method);
    if (r.quadrics) report_quadrics(*r.quadrics, summary);
    if (r.oriented) {
      report_phase_2(*r.oriented, summary);
    } else {
      summary.say("phase II  skipped: the input's normals are used");
    }
    report_phases_3_4(r, summary);
    if (r.refinement) report_refinement(*r.refinement, summary);
    report_colors(r, options.colors, summary);
    if (o->report.empty()) release_all_but_the_mesh(r);
    report_mesh(r.mesh(), summary);
    memory.start("write");
    Timer timer;
    io::write_mesh(o->output, r.mesh(), write_options);
    report_memory(memory, summary);
    summary.say("wrote     " + o->output.string() + " (" + format_seconds(timer.elapsed()) + "); total " +
                format_seconds(total.elapsed()));
    summary.stats()["output"]["file"] = o->output.string();
    summary.stats()["output"]["seconds"] = timer.elapsed();
    summary.stats()["threads"] = thread_count();
    summary.stats()["seconds_total"] = total.elapsed();
    if (!o->report.empty()) write_run_report(o->report, report_input(r), o->in.path, summary);
    if (!o->stats.empty()) summary.write_stats(o->stats);
  };
}

Command add_info(CLI::App& app, const GlobalOptions& global) {
  auto in = std::make_shared<InputOptions>();
  auto k = std::make_shared<int>(TangentPlaneOptions{}.k);
  add_input(app, *in);
  app.add_option("-k,--k", *k, "Neighbourhood size used to estimate rho")->default_val(*k)->check(CLI::Range(3, 256));
  return [in, k, &global] {
    Summary summary(global.quiet);
    const PointCloud cloud = read_input(*in, summary);
    Box<3> box;
    for (const auto& p : cloud.positions) box.extend(p);
    std::ostringstream out;
    out << "points        " << cloud.size() << (cloud.has_normals() ? " (with normals)" : "") << "\n";
    out << "bounding box  [" << format_length(box.min.x()) << ", " << format_length(box.min.y()) << ", "
        << format_length(box.min.z()) << "] .. [" << format_length(box.max.x()) << ", " << format_length(box.max.y())
        << ", " << format_length(box.max.z()) << "]\n";
    out << "diagonal      " << format_length(box.diagonal()) << "\n";
    TangentPlaneOptions options;
    options.k = *k;
    try {
      const auto planes = estimate_tangent_planes<3>(cloud.positions, options);
      out << "duplicates    " << cloud.size() - planes.distinct_points << " (exact copies of an earlier point)\n";
      out << "rho           " << format_length(planes.rho) << " (median of the local estimates, k = " << *k << ")\n";
      out << "degenerate    " << planes.degenerate << " neighbourhoods with no unique normal\n";
      out << "isolated      " << planes.isolated << " (samples far from all others: outliers, which draw no surface)";
    } catch (const InvalidInputError& e) {
      out << "rho           not available: " << e.what();
    }
    std::cout << out.str() << std::endl;
  };
}

Command add_normals(CLI::App& app, const GlobalOptions& global) {
  auto in = std::make_shared<InputOptions>();
  auto phases = std::make_shared<PhaseOptions>();
  auto output = std::make_shared<std::filesystem::path>();
  auto ascii = std::make_shared<bool>(false);
  auto stats = std::make_shared<std::filesystem::path>();
  auto report = std::make_shared<std::filesystem::path>();
  add_input(app, *in);
  app.add_option("-o,--output", *output, "Oriented cloud to write (.ply or .xyz), with the input's colours if any")
      ->required();
  app.add_flag("--ascii", *ascii, "Write ASCII PLY instead of binary");
  app.add_option("--stats", *stats, "Also write the run's figures as JSON to this file");
  add_report_option(app, *report);
  add_phase_options(app, *phases);
  return [=, &global] {
    Timer total;
    Summary summary(global.quiet);
    io::WritePointsOptions write_options;
    write_options.format = writable_point_format(*output);  // fail early on a bad extension
    write_options.ascii = *ascii;
    check_outputs(in->path, {*output, *stats, *report});
    StepPeaks memory;
    memory.start("read");
    PointCloud cloud = read_input(*in, summary);
    Progress progress(!global.quiet);
    progress.phase("phase I, tangent planes");
    memory.start("tangent planes");
    // Work in the kd-tree's leaf order (much faster on large clouds, and no
    // second copy of the points); write in the input's.
    const TangentPlaneOptions options = phase_1_options(*phases);
    check_memory_planes_and_graph(cloud.size(), options.k,
                                  phases->max_memory > 0 ? phases->max_memory : default_memory_limit());
    KdTree<3> tree(cloud.positions, options.tree);
    const std::vector<std::uint32_t> order = tree.renumber_by_leaf_order();
    const auto planes = estimate_tangent_planes<3>(std::move(tree), options);
    progress.phase("");
    report_phase_1(planes, cloud.size(), summary);
    progress.phase("phase II, orientation");
    memory.start("orientation");
    const auto oriented = orient_normals<3>(planes);
    progress.phase("");
    report_phase_2(oriented, summary);
    progress.stop();
    memory.start("write");
    cloud.normals.resize(cloud.size());
    for (std::size_t j = 0; j < order.size(); ++j) cloud.normals[order[j]] = oriented.normals[j];
    Timer timer;
    io::write_points(*output, cloud, write_options);
    report_memory(memory, summary);
    summary.say("wrote     " + output->string() + " (" + format_seconds(timer.elapsed()) + "); total " +
                format_seconds(total.elapsed()));
    summary.stats()["output"]["file"] = output->string();
    summary.stats()["threads"] = thread_count();
    summary.stats()["seconds_total"] = total.elapsed();
    if (!report->empty()) {
      ReportInput input;
      input.points = planes.point_tree.points();
      input.planes = &planes;
      input.oriented = &oriented;
      input.normals = oriented.normals;
      const std::vector<Color> colors =
          cloud.has_colors() ? permuted<Color>(cloud.colors, order) : std::vector<Color>{};
      input.colors = colors;
      write_run_report(*report, input, in->path, summary);
    }
    if (!stats->empty()) summary.write_stats(*stats);
  };
}

namespace {

// Gaussian noise of standard deviation `fraction` of the cloud's bounding-box
// diagonal, reproducible from the seed.
void add_noise(PointCloud& cloud, double fraction, std::uint64_t seed) {
  Box<3> box;
  for (const auto& p : cloud.positions) box.extend(p);
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> gauss(0.0, fraction * box.diagonal());
  for (auto& p : cloud.positions) p += Vec3(gauss(rng), gauss(rng), gauss(rng));
}

// How many points `recon generate SHAPE` writes without -n: the course's
// data set at its own size, every other shape at 100,000.
std::size_t default_point_count(const std::string& shape) { return shape == "conics" ? 16000 : 100000; }

// --truth: a dense, noise-free sample of the true surface with its true
// normals, the ground truth the evaluation scripts compare a mesh with
// (a PLY with x y z nx ny nz). It is drawn with a seed of its own, so it is
// not the cloud itself.
void write_truth(const Shape& shape, const std::filesystem::path& path, std::size_t count, std::uint64_t seed,
                 Summary& summary) {
  const PointCloud truth = shape.sample(count, seed ^ 0x2545f4914f6cdd1dULL);
  io::write_points(path, truth, {io::PointFormat::ply, false});
  summary.say("wrote     " + path.string() + ": " + plural(truth.size(), "point") +
              " of the true surface, with normals");
}

}  // namespace

Command add_generate(CLI::App& app, const GlobalOptions& global) {
  struct Options {
    std::string shape;
    std::size_t count = 0;  // 0: default_point_count(shape)
    std::uint64_t seed = 1;
    double noise = 0.0;
    bool with_normals = false;
    std::filesystem::path output;
    std::filesystem::path truth;
    std::size_t truth_count = 300000;
  };
  auto o = std::make_shared<Options>();
  app.add_option("shape", o->shape,
                 "sphere, torus, ellipsoid, box, two (a sphere beside a torus), terrain (a scan-like open "
                 "height field on a jittered grid), part (a slab with three holes: sharp creases, genus 3), handle "
                 "(a long thin capsule), or conics (the course's data set: two cones, two cylinders and a sphere)")
      ->required();
  app.add_option("-o,--output", o->output, "Point cloud to write (.ply or .xyz)")->required();
  app.add_option("-n,--points", o->count, "Number of points (default 100000; conics: 16000)")
      ->check(CLI::Range(1, 1 << 30));
  app.add_option("--seed", o->seed, "Random seed")->default_val(o->seed);
  app.add_option("--noise", o->noise, "Gaussian noise, as a fraction of the bounding-box diagonal")
      ->check(CLI::Range(0.0, 1.0));
  app.add_flag("--with-normals", o->with_normals, "Also write the true outward normals");
  CLI::Option* truth = app.add_option(
      "--truth", o->truth,
      "Also write the ground truth: a dense noise-free sample of the true surface with its normals (.ply)");
  app.add_option("--truth-points", o->truth_count, "Number of points of the ground truth")
      ->default_val(o->truth_count)
      ->check(CLI::Range(1, 1 << 30))
      ->needs(truth);
  return [o, &global] {
    Summary summary(global.quiet);
    io::WritePointsOptions write_options;
    write_options.format = writable_point_format(o->output);
    if (!o->truth.empty() && io::point_format_from_path(o->truth) != io::PointFormat::ply)
      throw InvalidInputError(o->truth.string() + ": the ground truth is written as .ply (x y z nx ny nz)");
    check_outputs({}, {o->output, o->truth});
    const auto shape = make_shape(o->shape);
    const std::size_t count = o->count > 0 ? o->count : default_point_count(o->shape);
    PointCloud cloud = shape->sample(count, o->seed);
    if (o->noise > 0.0) add_noise(cloud, o->noise, o->seed);
    if (!o->with_normals) cloud.normals.clear();
    io::write_points(o->output, cloud, write_options);
    summary.say("wrote     " + o->output.string() + ": " + plural(cloud.size(), "point") + " sampled from '" +
                o->shape + "'");
    if (!o->truth.empty()) write_truth(*shape, o->truth, o->truth_count, o->seed, summary);
  };
}

}  // namespace recon::cli
