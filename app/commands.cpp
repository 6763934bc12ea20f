#include "commands.h"
#include "command_parts.h"

#include "curves.h"
#include "number_options.h"
#include "progress.h"
#include "run_reports.h"
#include "summary.h"
#include "tiled.h"

#include "recon/core/errors.h"
#include "recon/core/parallel.h"
#include "recon/core/resource_usage.h"
#include "recon/core/shapes.h"
#include "recon/core/timer.h"
#include "recon/estimate_normals.h"
#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/orientation.h"
#include "recon/reconstruct.h"
#include "recon/report/report.h"
#include "recon/structures/mesh.h"
#include "recon/structures/spatial_order.h"  // permuted

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <tuple>

namespace recon::cli {

void add_input(CLI::App& app, InputOptions& in) {
  app.add_option("input", in.path,
                 "Point cloud (.ply .xyz .txt .csv .pts .obj .off .pcd .las); - or /dev/stdin: standard input, "
                 "with --format")
      ->required()
      ->transform([](std::string name) { return name == "-" ? std::string("/dev/stdin") : name; }, "", "stdin");
  app.add_option("--format", in.format,
                 "Input format when the extension does not say: ply, xyz, pts, obj, off, pcd, las");
  app.add_option("--columns", in.columns,
                 "What each column of a text file without a header holds, e.g. x,y,z,_,r,g,b "
                 "(x y z, nx ny nz, r g b, _ to skip a column)");
  app.add_flag("--skip-invalid", in.skip_invalid,
               "Skip points with a coordinate that is NaN, infinite or beyond 1e15 instead of refusing the file");
  app.add_flag("--no-colors", in.no_colors, "Drop the input's colours (the mesh or cloud is written without)");
}

io::ReadPointsOptions read_options(const InputOptions& in) {
  io::ReadPointsOptions options;
  if (!in.format.empty()) options.format = io::point_format_from_name(in.format);
  options.columns = io::column_names(in.columns);
  options.skip_invalid = in.skip_invalid;
  return options;
}

std::optional<io::PointSource> open_if_stream(const InputOptions& in) {
  if (!io::is_stream(in.path)) return std::nullopt;
  return io::PointSource(in.path);
}

PointCloud read_input(const InputOptions& in, Summary& summary, io::ReadNotes* said,
                      std::optional<io::PointSource>* opened) {
  Timer timer;
  io::ReadNotes notes;
  PointCloud cloud = opened != nullptr && opened->has_value() ? io::read_points(**opened, read_options(in), &notes)
                                                              : io::read_points(in.path, read_options(in), &notes);
  if (opened != nullptr) opened->reset();
  if (in.no_colors) cloud.colors = {};
  const double seconds = timer.elapsed();
  summary.add(input_report(in.path.string(), cloud, notes, seconds), "input");
  if (said != nullptr) *said = std::move(notes);
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
    if (std::filesystem::is_directory(out, ec)) throw IoError(out.string() + ": cannot write: it is a folder");
  }
}

// --report FILE.html, shared by reconstruct and normals.
void add_report_option(CLI::App& app, std::filesystem::path& report) {
  app.add_option("--report", report,
                 "Also write an interactive HTML report of every phase (one self-contained file, opens offline)");
}

void add_simplify_options(CLI::App& app, const std::string& target_flag, std::string& target,
                          const std::string& subject, const std::string& bound_flag, std::optional<double>& bound,
                          const std::string& reference, const std::string& measure) {
  app.add_option(target_flag, target,
                 "Simplify " + subject +
                     "to this many triangles, or this ratio or percentage of them (5000, 0.1, "
                     "10%), keeping creases, corners, open boundaries and separate objects")
      ->check(simplify_target());
  app.add_option(bound_flag, bound,
                 "Simplify keeping every vertex of the " + reference + " within this " + measure +
                     " of the result (with " + target_flag + ": stop at whichever comes first)")
      ->check(positive_length());
}

// --method, shared by reconstruct and normals: what the refined default
// does there, and which of the paper's phases hoppe92 runs.
void add_method_option(CLI::App& app, std::string& method, const std::string& refined, const std::string& phases) {
  app.add_option("--method", method,
                 "refined (default: " + refined + ") or hoppe92 (the 1992 paper's " + phases + " exactly)")
      ->check(CLI::IsMember({"refined", "hoppe92"}));
}

// --ascii, --normals and --stats, shared by reconstruct and simplify.
void add_mesh_output_options(CLI::App& app, bool& ascii, bool& normals, const std::string& source,
                             std::filesystem::path& stats) {
  app.add_flag("--ascii", ascii, "Write ASCII PLY instead of binary");
  app.add_flag("--normals", normals,
               "Write vertex normals (PLY nx ny nz, OBJ vn): " + source +
                   ", the triangles' area-weighted mean elsewhere (a .glb always has them)");
  app.add_option("--stats", stats, "Also write the run's figures as JSON to this file");
}

namespace {

// The formats write_points can write.
io::PointFormat writable_point_format(const std::filesystem::path& path) {
  const io::PointFormat format = io::point_format_from_path(path);
  if (format != io::PointFormat::ply && format != io::PointFormat::xyz)
    throw InvalidInputError(path.string() + ": oriented clouds are written as .ply or .xyz");
  return format;
}

}  // namespace

void add_phase_options(CLI::App& app, PhaseOptions& p) {
  p.k_option =
      app.add_option("-k,--k", p.k,
                     "Neighbours per tangent plane, the point itself included (default 20, 8 for curves; raised "
                     "automatically for noisy data unless given)")
          ->check(CLI::Range(3, 256));
  app.add_option("--rho", p.rho,
                 "Sampling density: every point of the surface is within this distance of a sample (default: "
                 "estimated per point)")
      ->check(positive_length());
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

namespace {

/// --use-normals on a cloud whose reader dropped its normals (PCD with NaN
/// normals): say so, rather than that the input has none.
void refuse_dropped_normals(const io::ReadNotes& notes) {
  for (const std::string& line : notes.lines) {
    if (line.starts_with("normals dropped: "))
      throw InvalidInputError("--use-normals: the input's normals were dropped when it was read (" + line.substr(17) +
                              "); run without the option to estimate them");
  }
}

}  // namespace

namespace {

// Whether `output` names a GLB file (by its extension, any case).
bool writes_glb(const std::filesystem::path& output) {
  std::string extension = output.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".glb";
}

// The library's options for a 3D run of `recon reconstruct`.
ReconstructionOptions reconstruction_options(const ReconstructCommandOptions& o) {
  ReconstructionOptions options;
  options.method = method_from_name(o.method);
  options.refinement.keep_fragments = o.keep_fragments;
  options.refinement.keep_embedding = o.embedded;
  options.planes = phase_1_options(o.phases);
  options.distance.delta = o.delta;
  options.cell = o.cell;
  options.resolution = o.resolution;
  options.use_input_normals = o.use_normals;
  options.max_memory = o.phases.max_memory;
  // GLB always has them (viewers shade with them); other formats when asked.
  options.vertex_normals = o.normals || writes_glb(o.output);
  if (!o.simplify.empty())
    std::tie(options.simplify.triangles, options.simplify.ratio) = simplify_target_of(o.simplify);
  options.simplify.max_error = o.max_error.value_or(0.0);
  // Without a report only the counts are reported; the report draws the
  // graph and the evaluated corners.
  options.keep_graph = !o.report.empty();
  options.keep_corners = !o.report.empty();
  return options;
}

// Progress on the terminal (with the phases' counts, when `counter` is
// given) and the peak memory of each phase.
std::function<void(const char*)> on_phase(Progress& progress, StepPeaks& memory, const ProgressCounter* counter) {
  return [&progress, &memory, counter](const char* phase) {
    progress.phase(phase, counter);
    memory.start(phase);
  };
}

void run_reconstruct(const ReconstructCommandOptions& o, const GlobalOptions& global,
                     std::optional<io::PointSource>& opened) {
  check_outputs(o.in.path, {o.output, o.stats, o.report});
  if (const std::optional<std::string> why = tiling_reason(o, reconstruction_options(o))) {
    if (opened)
      throw InvalidInputError(o.in.path.string() + ": " + *why +
                              ": a tiled run reads its input in several passes, and a stream (a pipe, a FIFO, -) "
                              "can be read only once; save it to a file first");
    run_tiled(o, reconstruction_options(o), *why, global);
    return;
  }
  Timer total;
  Summary summary(global.quiet);
  io::WriteMeshOptions write_options;
  write_options.format = io::mesh_format_from_path(o.output);  // fail early on a bad extension
  write_options.ascii = o.ascii;
  StepPeaks memory;
  memory.start("read");
  io::ReadNotes notes;
  PointCloud cloud = read_input(o.in, summary, &notes, &opened);
  const std::size_t points = cloud.size();
  if (o.use_normals && !cloud.has_normals()) refuse_dropped_normals(notes);

  ReconstructionOptions options = reconstruction_options(o);
  ProgressCounter counter;
  Progress progress(!global.quiet);
  options.progress = progress.enabled() ? &counter : nullptr;
  options.on_phase = on_phase(progress, memory, options.progress);
  Reconstruction r = reconstruct(std::move(cloud), options);
  progress.stop();
  memory.start("summary");  // the mesh's topology, for the report below
  report_reconstruction(r, options, points, !o.report.empty(), summary);

  memory.start("write");
  Timer timer;
  io::write_mesh(o.output, r.mesh(), write_options);
  report_memory(memory, summary);
  finish_run(summary, o.output, timer.elapsed(), total.elapsed());
  if (!o.report.empty()) write_run_report(o.report, report_input(r), o.in.path, summary);
  if (!o.stats.empty()) summary.write_stats(o.stats);
}

}  // namespace

Command add_reconstruct(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<ReconstructCommandOptions>();
  add_input(app, o->in);
  app.add_option("-o,--output", o->output,
                 "Mesh to write (.ply .obj .off .stl .glb); for 2D points, curves (.svg .obj .txt)")
      ->required();
  add_method_option(app, o->method,
                    "second-order fits, a finer lattice, the mesh moved onto the fitted surface, creases sharpened, "
                    "fragments dropped",
                    "four phases");
  app.add_flag("--keep-fragments", o->keep_fragments,
               "Keep small mesh components next to larger ones drawn from the same data (refined)");
  app.add_flag("--embedded", o->embedded,
               "Put back phase V's moves that make triangles cross or a vertex pinched, checked exactly: an embedded "
               "mesh, as slicers and boolean operations need (refined; slower, and creases a little rounder where "
               "they crossed)");
  add_phase_options(app, o->phases);
  app.add_option("--delta", o->delta, "Noise level, a length (default: estimated from the tangent-plane fits)")
      ->check(non_negative_length());
  auto* cell =
      app.add_option("--cell", o->cell, "Lattice cube side, a length (default: rho)")->check(positive_length());
  app.add_option("--resolution", o->resolution, "Lattice cubes along the longest side of the bounding box")
      ->check(CLI::Range(1, 1 << 20))
      ->excludes(cell);
  app.add_flag("--use-normals", o->use_normals, "Use the input's own normals (skips phase II)");
  add_simplify_options(app, "--simplify", o->simplify, "the mesh ", "--max-error", o->max_error, "unsimplified mesh",
                       "multiple of rho");
  add_mesh_output_options(app, o->ascii, o->normals, "the fitted surface's where phase V has one", o->stats);
  add_report_option(app, o->report);
  app.add_option("--tile-size", o->tile_size,
                 "Work in tiles with cores of this edge (a length), streaming the input and the mesh; without it, "
                 "tiles are used when the cloud needs more memory than --max-memory")
      ->check(positive_length());
  app.add_option("--tmpdir", o->tmpdir, "Folder for the tiles of a tiled run (default: the output's folder)")
      ->check(CLI::ExistingDirectory);
  return [o, &global] {
    // The 2D check looks at the input before it is read: a stream is read
    // once, here, and both look at what was read.
    std::optional<io::PointSource> opened = open_if_stream(o->in);
    if (wants_curves(o->in.path, o->in.format, o->output, opened ? &*opened : nullptr)) {  // 2D: curves.cpp
      reconstruct_curves(*o, global.quiet, opened);
    } else {
      run_reconstruct(*o, global, opened);
    }
  };
}

namespace {

struct InfoCommandOptions {
  InputOptions in;
  int k = TangentPlaneOptions{}.k;
};

// The bounding box and what phase I says of the sampling.
std::string describe_cloud(const PointCloud& cloud, int k) {
  const Box<3> box = bounding_box<3>(cloud.positions);
  std::ostringstream out;
  out << "points        " << cloud.size() << (cloud.has_normals() ? " (with normals)" : "") << "\n";
  out << "bounding box  [" << format_length(box.min.x()) << ", " << format_length(box.min.y()) << ", "
      << format_length(box.min.z()) << "] .. [" << format_length(box.max.x()) << ", " << format_length(box.max.y())
      << ", " << format_length(box.max.z()) << "]\n";
  out << "diagonal      " << format_length(box.diagonal()) << "\n";
  TangentPlaneOptions options;
  options.k = k;
  try {
    const auto planes = estimate_tangent_planes<3>(cloud.positions, options);
    out << "duplicates    " << cloud.size() - planes.distinct_points << " (exact copies of an earlier point)\n";
    out << "rho           " << format_length(planes.rho) << " (median of the local estimates, k = " << k << ")\n";
    out << "degenerate    " << planes.degenerate << " neighbourhoods with no unique normal\n";
    out << "isolated      " << planes.isolated << " (samples far from all others: outliers, which draw no surface)";
  } catch (const InvalidInputError& e) {
    out << "rho           not available: " << e.what();
  }
  return out.str();
}

}  // namespace

Command add_info(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<InfoCommandOptions>();
  add_input(app, o->in);
  app.add_option("-k,--k", o->k, "Neighbourhood size used to estimate rho")
      ->default_val(o->k)
      ->check(CLI::Range(3, 256));
  return [o, &global] {
    Summary summary(global.quiet);
    const PointCloud cloud = read_input(o->in, summary);
    std::cout << describe_cloud(cloud, o->k) << std::endl;
  };
}

namespace {

struct NormalsCommandOptions {
  InputOptions in;
  PhaseOptions phases;
  std::filesystem::path output, stats, report;
  bool ascii = false;
  std::string method = "refined";
};

void write_normals_report(const std::filesystem::path& path, const NormalEstimation& estimated, const PointCloud& cloud,
                          const std::filesystem::path& source, Summary& summary) {
  ReportInput input;
  input.points = estimated.points();
  input.offset = estimated.offset;
  input.planes = &estimated.planes;
  input.oriented = &estimated.oriented;
  input.normals = estimated.oriented.normals;
  const std::vector<Color> colors =
      cloud.has_colors() ? permuted<Color>(cloud.colors, estimated.order) : std::vector<Color>{};
  input.colors = colors;
  write_run_report(path, input, source, summary);
}

void run_normals(const NormalsCommandOptions& o, const GlobalOptions& global) {
  Timer total;
  Summary summary(global.quiet);
  io::WritePointsOptions write_options;
  write_options.format = writable_point_format(o.output);  // fail early on a bad extension
  write_options.ascii = o.ascii;
  check_outputs(o.in.path, {o.output, o.stats, o.report});
  StepPeaks memory;
  memory.start("read");
  PointCloud cloud = read_input(o.in, summary);
  ProgressCounter counter;
  Progress progress(!global.quiet);
  NormalEstimationOptions options;
  options.method = method_from_name(o.method);
  options.planes = phase_1_options(o.phases);
  options.max_memory = o.phases.max_memory;
  options.progress = progress.enabled() ? &counter : nullptr;
  options.on_phase = on_phase(progress, memory, options.progress);
  const NormalEstimation estimated = estimate_normals(cloud, options);
  progress.stop();
  report_normal_estimation(estimated, cloud.size(), summary);

  memory.start("write");
  cloud.normals = estimated.normals_in_input_order();
  Timer timer;
  io::write_points(o.output, cloud, write_options);
  report_memory(memory, summary);
  finish_run(summary, o.output, timer.elapsed(), total.elapsed());
  if (!o.report.empty()) write_normals_report(o.report, estimated, cloud, o.in.path, summary);
  if (!o.stats.empty()) summary.write_stats(o.stats);
}

}  // namespace

Command add_normals(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<NormalsCommandOptions>();
  add_input(app, o->in);
  app.add_option("-o,--output", o->output, "Oriented cloud to write (.ply or .xyz), with the input's colours if any")
      ->required();
  app.add_flag("--ascii", o->ascii, "Write ASCII PLY instead of binary");
  app.add_option("--stats", o->stats, "Also write the run's figures as JSON to this file");
  add_report_option(app, o->report);
  add_method_option(app, o->method,
                    "the normals reconstruct orients: second-order fits, each piece's side decided at its best extreme",
                    "phases I and II");
  add_phase_options(app, o->phases);
  return [o, &global] { run_normals(*o, global); };
}

namespace {

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

struct GenerateCommandOptions {
  std::string shape;
  std::size_t count = 0;  // 0: default_point_count(shape)
  std::uint64_t seed = 1;
  double noise = 0.0;
  std::size_t scan_views = 0;  // 0: sample by area, no scanner
  double misregistration = 0.0;
  std::optional<double> thickness;  // absent: the shape's default
  bool with_normals = false;
  std::filesystem::path output;
  std::filesystem::path truth;
  std::size_t truth_count = 300000;
};

}  // namespace

Command add_generate(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<GenerateCommandOptions>();
  app.add_option("shape", o->shape,
                 "sphere, torus, ellipsoid, box, two (a sphere beside a torus), terrain (a scan-like open "
                 "height field on a jittered grid), part (a slab with three holes: sharp creases, genus 3), handle "
                 "(a long thin capsule), conics (the course's data set: two cones, two cylinders and a sphere), shell "
                 "(a hollow ball: outer radius 1, a cavity of radius 0.7 whose wall faces into it), or nested "
                 "(that shell with a ball of radius 0.3 in its cavity); the thin solids, closed, with their "
                 "--thickness: plate (2 x 1 x t), club (a thin blade of thickness t under a 0.1 x 0.1 handle, genus "
                 "0), airfoil (a NACA wing of chord 1, thickest t, its trailing edge thinning to nothing, end caps), "
                 "cup (radius 0.5, height 0.8, walls and floor t thick, genus 0), cavity-cube (a unit cube with a "
                 "spherical cavity, walls t at their thinnest), two-cavities (a hollow ball with a hollow ball in its "
                 "cavity: two nested cavities, every wall t thick)")
      ->required();
  app.add_option("-o,--output", o->output, "Point cloud to write (.ply or .xyz)")->required();
  app.add_option("-n,--points", o->count, "Number of points (default 100000; conics: 16000)")
      ->check(CLI::Range(1, 1 << 30));
  app.add_option("--seed", o->seed, "Random seed")->default_val(o->seed);
  app.add_option("--noise", o->noise,
                 "Gaussian noise, as a fraction of the bounding-box diagonal (with --scan: along each ray, growing "
                 "with the range)")
      ->check(finite_within(0.0, 1.0));
  CLI::Option* scan_views =
      app.add_option("--scan", o->scan_views,
                     "Sample as a range scanner would from this many views around the shape, 15-45 degrees above "
                     "it: only the first surface each pixel's ray hits (occlusion and the underside leave holes), "
                     "denser near the scanner, about -n points in all")
          ->check(CLI::Range(1, 64));
  app.add_option("--misregistration", o->misregistration,
                 "With --scan: each view is off by a rigid motion, a rotation of this many radians and a shift of "
                 "this fraction of the diagonal")
      ->check(finite_within(0.0, 0.5))
      ->needs(scan_views);
  app.add_option("--thickness", o->thickness,
                 "Wall thickness of a thin solid, in the shape's units (plate 0.05, club 0.03, airfoil 0.12, cup "
                 "0.04, cavity-cube 0.1, two-cavities 0.1, shell 0.3 by default)")
      ->check(finite_within(0.0, 1.0));
  app.add_flag("--with-normals", o->with_normals,
               "Also write the true outward normals (with --scan: of the points hit)");
  CLI::Option* truth = app.add_option(
      "--truth", o->truth,
      "Also write the ground truth: a dense noise-free sample of the true surface with its normals (.ply); with "
      "--scan, of the whole surface, the parts no view saw included");
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
    const auto shape = make_shape(o->shape, o->thickness);
    const std::size_t count = o->count > 0 ? o->count : default_point_count(o->shape);
    PointCloud cloud = o->scan_views > 0 ? scan(*shape, {o->scan_views, count, o->noise, o->misregistration, o->seed})
                                         : shape->sample(count, o->seed);
    if (o->noise > 0.0 && o->scan_views == 0) add_noise(cloud, o->noise, o->seed);
    if (!o->with_normals) cloud.normals.clear();
    io::write_points(o->output, cloud, write_options);
    summary.say("wrote     " + o->output.string() + ": " + plural(cloud.size(), "point") +
                (o->scan_views > 0 ? " scanned from " + plural(o->scan_views, "view") + " of '" : " sampled from '") +
                o->shape + "'");
    if (!o->truth.empty()) write_truth(*shape, o->truth, o->truth_count, o->seed, summary);
  };
}

}  // namespace recon::cli
