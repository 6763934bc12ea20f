// recon simplify: phase VI on a mesh read from a file. A tiled run's mesh
// is never whole in memory, so `reconstruct --simplify` refuses it; this
// simplifies any such mesh afterwards (or one from another program) with the
// same code: features found from the planes around each vertex, creases,
// corners and open boundaries kept (simplification.h).

#include "command_parts.h"
#include "commands.h"
#include "number_options.h"
#include "run_reports.h"
#include "summary.h"

#include "recon/core/errors.h"
#include "recon/core/timer.h"
#include "recon/io/mesh_io.h"
#include "recon/phase5_refine/vertex_normals.h"
#include "recon/phase6_simplify/simplification.h"

#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>

namespace recon::cli {

namespace {

struct SimplifyCommandOptions {
  std::filesystem::path input, output, stats;
  std::string target;
  std::optional<double> max_distance;
  bool ascii = false, normals = false;
};

// The read line: what the file holds.
StepReport read_report(const std::filesystem::path& path, const Mesh& mesh, double seconds) {
  std::ostringstream line;
  line << "read      " << path.string() << ": " << plural(mesh.vertices.size(), "vertex") << ", "
       << plural(mesh.triangles.size(), "triangle") << " (" << format_seconds(seconds) << ")";
  return step_report(line.str(), {{"path", path.string()},
                                  {"vertices", mesh.vertices.size()},
                                  {"triangles", mesh.triangles.size()},
                                  {"seconds", seconds}});
}

SimplifyOptions simplify_options(const SimplifyCommandOptions& o) {
  SimplifyOptions options;
  if (!o.target.empty()) std::tie(options.target_triangles, options.ratio) = simplify_target_of(o.target);
  options.max_error = o.max_distance.value_or(0.0);
  if (options.target_triangles == 0 && options.ratio == 0.0 && options.max_error == 0.0)
    throw InvalidInputError("simplify: give --to (a triangle count, ratio or percentage) or --max-distance");
  return options;
}

void run_simplify(const SimplifyCommandOptions& o, const GlobalOptions& global) {
  Timer total;
  Summary summary(global.quiet);
  const SimplifyOptions options = simplify_options(o);
  io::WriteMeshOptions write_options;
  write_options.format = io::mesh_format_from_path(o.output);  // fail early on a bad extension
  write_options.ascii = o.ascii;
  check_outputs(o.input, {o.output, o.stats});
  Timer timer;
  const Mesh mesh = io::read_mesh(o.input);
  summary.add(read_report(o.input, mesh, timer.elapsed()), "read");
  if (options.target_triangles > mesh.triangles.size())
    throw InvalidInputError(o.input.string() + ": cannot simplify to " + std::to_string(options.target_triangles) +
                            " triangles: the mesh has only " + std::to_string(mesh.triangles.size()));
  Simplification s = simplify(mesh, options);
  summary.add(simplification_report(s, std::nullopt), "simplification");
  // A GLB always has normals; the others when asked. The input's own
  // normals travel with their vertices; without them, the faces' mean.
  const bool glb = write_options.format == io::MeshFormat::glb;
  if (o.normals || glb) {
    static_cast<void>(fill_face_normals(s.mesh));
  } else {
    s.mesh.normals.clear();
  }
  timer = Timer();
  io::write_mesh(o.output, s.mesh, write_options);
  finish_run(summary, o.output, timer.elapsed(), total.elapsed());
  if (!o.stats.empty()) summary.write_stats(o.stats);
}

}  // namespace

Command add_simplify(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<SimplifyCommandOptions>();
  app.add_option("input", o->input, "Mesh to simplify (PLY, OBJ or OFF)")->required();
  app.add_option("-o,--output", o->output, "Simplified mesh (.ply, .obj, .off, .stl or .glb)")->required();
  add_simplify_options(app, "--to", o->target, "", "--max-distance", o->max_distance, "input mesh",
                       "distance (in the mesh's units)");
  add_mesh_output_options(app, o->ascii, o->normals, "the input's own where it has them", o->stats);
  return [o, &global] { run_simplify(*o, global); };
}

}  // namespace recon::cli
