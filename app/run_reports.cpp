#include "run_reports.h"

#include "recon/mesh.h"
#include "recon/timer.h"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace recon::cli {
namespace {

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

}  // namespace

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

void report_reconstruction(Reconstruction& r, const ReconstructionOptions& options, std::size_t points, bool keep_all,
                           Summary& summary) {
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
  if (!keep_all) release_all_but_the_mesh(r);
  report_mesh(r.mesh(), summary);
}

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

ReportOptions run_report_options(const std::filesystem::path& source, Summary& summary) {
  ReportOptions options;
  options.title = source.filename().string();
  options.stats_json = summary.stats().dump(0);
  return options;
}

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

}  // namespace recon::cli
