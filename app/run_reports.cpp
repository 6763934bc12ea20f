#include "run_reports.h"

#include "recon/core/parallel.h"  // thread_count
#include "recon/core/timer.h"
#include "recon/structures/mesh.h"

#include <algorithm>
#include <limits>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace recon::cli {

template <int D>
StepReport phase_1_report(const TangentPlanes<D>& planes, std::size_t points) {
  const double seconds = planes.seconds_tree + planes.seconds_knn_pca + planes.seconds_spacing;
  std::ostringstream line;
  line << "phase I   tangent " << (D == 3 ? "planes" : "lines") << ": k = " << planes.k;
  if (planes.k != planes.k_requested)
    line << " (raised from " << planes.k_requested << ": noise " << format_length(planes.noise) << " is large)";
  line << ", rho = " << format_length(planes.rho)
       << (planes.rho_given ? " (given)" : " (estimated, median of local values)") << ", "
       << plural(points - planes.distinct_points, "duplicate") << ", "
       << plural(planes.degenerate, "degenerate neighbourhood");
  if (planes.isolated > 0) line << ", " << plural(planes.isolated, "isolated point") << " (outliers: no surface)";
  line << " (" << format_seconds(seconds) << ")";
  return step_report(line.str(), {{"k", planes.k},
                                  {"k_requested", planes.k_requested},
                                  {"noise", planes.noise},
                                  {"rho", planes.rho},
                                  {"rho_estimated", !planes.rho_given},
                                  {"distinct_points", planes.distinct_points},
                                  {"degenerate_neighbourhoods", planes.degenerate},
                                  {"isolated_points", planes.isolated},
                                  {"seconds_tree", planes.seconds_tree},
                                  {"seconds_knn_pca", planes.seconds_knn_pca},
                                  {"seconds_spacing", planes.seconds_spacing},
                                  {"seconds", seconds}});
}

StepReport quadrics_report(const LocalQuadrics& q) {
  std::ostringstream line;
  line << "          second-order fits: " << plural(q.borrowed, "sample") << " near creases took a neighbour's, "
       << plural(q.split, "neighbourhood") << " split between two sheets, " << plural(q.flat, "flat fit") << " ("
       << format_seconds(q.seconds) << ")";
  return step_report(line.str(),
                     {{"borrowed", q.borrowed}, {"split_sheets", q.split}, {"flat", q.flat}, {"seconds", q.seconds}});
}

template <int D>
StepReport phase_2_report(const OrientedNormals<D>& oriented) {
  const auto& g = oriented.graph;
  const double seconds = g.seconds_emst + g.seconds_graph + oriented.seconds_mst;
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
  if (oriented.nested_turned > 0)
    line << ", " << plural(oriented.nested_turned, "nested piece") << " turned to face its cavity";
  line << " (" << format_seconds(seconds) << ")";
  Json::Array size_list;
  for (std::uint32_t v : g.components.sizes) size_list.emplace_back(static_cast<std::size_t>(v));
  return step_report(line.str(), {{"components", oriented.component_count()},
                                  {"component_sizes", Json(size_list)},
                                  {"graph_edges", g.edge_count},
                                  {"gap_edges", g.gap_emst_edges},
                                  {"rejoined_pieces", g.rejoined},
                                  {"flips", oriented.flip_count},
                                  {"seconds_emst", g.seconds_emst},
                                  {"seconds_graph", g.seconds_graph},
                                  {"seconds_mst", oriented.seconds_mst},
                                  {"vote_flips", oriented.vote_flips},
                                  {"sheet_edges", oriented.sheet_edges},
                                  {"crease_patches_turned", oriented.crease_patches_turned},
                                  {"components_turned", oriented.components_turned},
                                  {"pieces_nested", oriented.pieces_nested},
                                  {"nested_turned", oriented.nested_turned},
                                  {"seconds", seconds}});
}

StepReport input_report(const std::string& file, const PointCloud& cloud, const io::ReadNotes& notes, double seconds) {
  StepReport report;
  const char* extras = cloud.has_normals() ? (cloud.has_colors() ? " with normals and colours" : " with normals")
                                           : (cloud.has_colors() ? " with colours" : "");
  report.lines.push_back("read      " + file + ": " + plural(cloud.size(), "point") + extras + " (" +
                         format_seconds(seconds) + ")");
  for (const std::string& line : notes.lines) report.lines.push_back("          " + line);
  put(report.stats, {{"file", file},
                     {"points", cloud.size()},
                     {"has_normals", cloud.has_normals()},
                     {"has_colors", cloud.has_colors()},
                     {"skipped_points", notes.skipped_points},
                     {"seconds", seconds}});
  return report;
}

StepReport phase_3_report(const SignedDistanceFigures& f) {
  std::ostringstream line;
  line << "phase III signed distance: delta = " << format_length(f.delta)
       << (f.delta_given ? " (given)" : " (estimated)") << ", " << f.evaluated << " lattice corners evaluated, "
       << f.undefined << " undefined (" << format_seconds(f.seconds);
  if (f.seconds_beside > 0.0) line << ", and " << format_seconds(f.seconds_beside) << " beside phase II";
  line << ")";
  return step_report(line.str(), {{"delta", f.delta},
                                  {"delta_estimated", !f.delta_given},
                                  {"corners_evaluated", f.evaluated},
                                  {"corners_undefined", f.undefined},
                                  {"seconds", f.seconds},
                                  {"seconds_beside_orientation", f.seconds_beside}});
}

Json lattice_size_json(std::span<const std::int32_t> size) {
  Json::Array sizes;
  for (const std::int32_t n : size) sizes.emplace_back(static_cast<std::size_t>(n));
  return Json(sizes);
}

namespace {

// Phase IV's line and statistics; a cloud of far-apart clusters was
// contoured on a lattice per cluster (reconstruct.h), listed in "clusters"
// instead of one "lattice_size".
StepReport phase_4_report(const MarchingCubesResult& c, std::span<const ClusterLattice> clusters) {
  std::ostringstream line;
  line << "phase IV  contouring: cell = " << format_length(c.cell) << ", " << c.visited_cubes << " cubes visited of ";
  if (clusters.empty()) {
    line << static_cast<double>(c.size[0]) * c.size[1] * c.size[2] << " in the lattice (" << c.size[0] << " x "
         << c.size[1] << " x " << c.size[2] << "), ";
  } else {
    double cubes = 0.0;
    for (const ClusterLattice& l : clusters) cubes += static_cast<double>(l.size[0]) * l.size[1] * l.size[2];
    line << cubes << " in " << clusters.size() << " lattices, one per far-apart cluster (";
    for (std::size_t i = 0; i < clusters.size(); ++i)
      line << (i > 0 ? ", " : "") << clusters[i].size[0] << " x " << clusters[i].size[1] << " x "
           << clusters[i].size[2];
    line << "), ";
  }
  line << format_seconds(c.seconds - c.seconds_field);
  StepReport report = step_report(line.str(), {{"cell", c.cell}});
  Json& m = report.stats;
  if (clusters.empty()) {
    m["lattice_size"] = lattice_size_json(c.size);
  } else {
    Json::Array list;
    for (const ClusterLattice& l : clusters) {
      Json& one = list.emplace_back();
      put(one, {{"points", l.points}, {"lattice_size", lattice_size_json(l.size)}, {"triangles", l.triangles}});
    }
    m["clusters"] = Json(std::move(list));
  }
  put(m, {{"seed_cubes", c.seed_cubes},
          {"visited_cubes", c.visited_cubes},
          {"undefined_cubes", c.undefined_cubes},
          {"seconds", c.seconds - c.seconds_field}});
  return report;
}

StepReport refinement_report(const Refinement& r) {
  double moved = 0.0;
  for (const float d : r.displacement) moved += static_cast<double>(d);
  moved /= static_cast<double>(std::max<std::size_t>(1, r.displacement.size()));
  std::ostringstream line;
  line << "phase V   refinement: vertices moved " << format_length(moved) << " on average, "
       << plural(r.crease_vertices, "crease vertex") << " added, " << r.brought_back << " brought back onto a crease, "
       << plural(r.corner_vertices, "corner") << ", ";
  if (r.put_back > 0) line << plural(r.put_back, "vertex") << " put back where triangles crossed, ";
  line << plural(r.trimmed, "triangle") << " past open boundaries cut off, ";
  if (r.stray_triangles > 0) line << plural(r.stray_triangles, "triangle") << " beyond the data's reach dropped, ";
  line << plural(r.fragments, "fragment") << " dropped (" << plural(r.fragment_triangles, "triangle") << ") ("
       << format_seconds(r.seconds) << ")";
  return step_report(line.str(), {{"mean_displacement", moved},
                                  {"crease_vertices", r.crease_vertices},
                                  {"brought_back", r.brought_back},
                                  {"corner_vertices", r.corner_vertices},
                                  {"unmoved_vertices", r.unmoved},
                                  {"put_back_vertices", r.put_back},
                                  {"trimmed_triangles", r.trimmed},
                                  {"stray_triangles", r.stray_triangles},
                                  {"fragments", r.fragments},
                                  {"fragment_triangles", r.fragment_triangles},
                                  {"seconds", r.seconds}});
}

// The mesh's colours (when the input had some).
StepReport colors_report(const VertexColorOptions& options, double seconds) {
  std::ostringstream line;
  line << "colours   mesh vertices coloured from the samples: inverse-distance blend of the " << options.k
       << " nearest (" << format_seconds(seconds) << ")";
  return step_report(line.str(), {{"k", options.k}, {"seconds", seconds}});
}

StepReport mesh_report(const Mesh& mesh) {
  const MeshTopology t = analyze_topology(mesh);
  std::ostringstream line;
  line << "mesh      " << plural(t.vertices, "vertex") << ", " << plural(t.triangles, "triangle") << ", "
       << plural(t.components, "component") << ", "
       << (t.boundary_loops == 0 ? std::string("closed") : plural(t.boundary_loops, "boundary loop"))
       << ", Euler characteristic " << t.euler_characteristic;
  return step_report(line.str(), {{"vertices", t.vertices},
                                  {"faces", t.triangles},
                                  {"components", t.components},
                                  {"boundary_edges", t.boundary_edges},
                                  {"boundary_loops", t.boundary_loops},
                                  {"non_manifold_edges", t.non_manifold_edges},
                                  {"euler_characteristic", static_cast<double>(t.euler_characteristic)},
                                  {"area", t.area},
                                  {"signed_volume", t.signed_volume},
                                  {"has_colors", mesh.has_colors()}});
}

// Without a report only the mesh is needed once the phases are reported:
// the rest goes before the mesh's topology is measured, the run's last
// large allocation (it lowers the peak of a refined run by the 1992 mesh).
// A report (keep_all) of a cloud contoured on a lattice per far-apart
// cluster cannot draw one lattice's corners (layer 6), and its single-
// precision positions, relative to the whole cloud's centre, blur each
// cluster's shape at that distance: the run says so.
void say_what_the_report_leaves_out(const Reconstruction& r, Summary& summary) {
  const Box<3> box = bounding_box<3>(r.points());
  const double blur = 0.5 * box.extent().maxCoeff() * static_cast<double>(std::numeric_limits<float>::epsilon());
  std::ostringstream line;
  line.precision(3);
  line << "          --report leaves out the lattice corners (layer 6): they lie on " << r.clusters.size()
       << " lattices, one per far-apart cluster; and it draws in single precision about the cloud's centre, "
       << "to about " << blur << " here";
  summary.say(line.str());
}

void release_all_but_the_mesh(Reconstruction& r) {
  if (r.refinement) r.contour.mesh = {};
  if (r.simplification && r.refinement) r.refinement->mesh = {};
  r.origin_tree = {};
  r.planes = {};
  r.quadrics.reset();
  r.oriented.reset();
  r.input_normals = {};
  r.colors = {};
}

}  // namespace

// Phase VI: triangles before and after, and the bound measured on the
// unsimplified mesh's vertices: in rho's units when the run has a rho (as
// --max-error takes it), else in the mesh's own (recon simplify).
StepReport simplification_report(const Simplification& s, std::optional<double> rho) {
  std::ostringstream line;
  line << "phase VI  simplification: " << s.triangles_before << " -> " << plural(s.triangles_after, "triangle") << " ("
       << plural(s.collapses, "collapse") << ", " << plural(s.corner_vertices, "fixed vertex") << ", "
       << plural(s.crease_vertices, "crease or boundary vertex") << " moved along their lines only";
  if (s.vertex_error > 0.0)
    line << "; vertices within "
         << (rho ? format_length(s.vertex_error / *rho) + " rho" : format_length(s.vertex_error));
  line << ") (" << format_seconds(s.seconds) << ")";
  return step_report(line.str(),
                     {{"triangles_before", s.triangles_before},
                      {"triangles_after", s.triangles_after},
                      {"collapses", s.collapses},
                      {"fixed_vertices", s.corner_vertices},
                      {"line_vertices", s.crease_vertices},
                      {rho ? "vertex_error_rho" : "vertex_error", rho ? s.vertex_error / *rho : s.vertex_error},
                      {"seconds", s.seconds}});
}

template StepReport phase_1_report<2>(const TangentPlanes<2>&, std::size_t);
template StepReport phase_1_report<3>(const TangentPlanes<3>&, std::size_t);
template StepReport phase_2_report<2>(const OrientedNormals<2>&);
template StepReport phase_2_report<3>(const OrientedNormals<3>&);

void report_phases_1_2(const TangentPlanes<3>& planes, Method method, const std::optional<LocalQuadrics>& quadrics,
                       const OrientedNormals<3>* oriented, std::size_t points, Summary& summary) {
  summary.add(phase_1_report(planes, points), "tangent_planes");
  summary.stats()["method"] = method_name(method);
  if (quadrics) summary.add(quadrics_report(*quadrics), "tangent_planes", "quadrics");
  if (oriented != nullptr) {
    summary.add(phase_2_report(*oriented), "orientation");
  } else {
    summary.say("phase II  skipped: the input's normals are used");
  }
}

void report_normal_estimation(const NormalEstimation& estimated, std::size_t points, Summary& summary) {
  report_phases_1_2(estimated.planes, estimated.method, estimated.quadrics, &estimated.oriented, points, summary);
}

void report_reconstruction(Reconstruction& r, const ReconstructionOptions& options, std::size_t points, bool keep_all,
                           Summary& summary) {
  report_phases_1_2(r.planes, r.method, r.quadrics, r.oriented ? &*r.oriented : nullptr, points, summary);
  const MarchingCubesResult& c = r.contour;
  summary.add(phase_3_report({r.delta, r.delta_given, c.evaluated_corners, c.undefined_corners,
                              r.seconds_distance_setup + c.seconds_field, r.seconds_distance_beside}),
              "signed_distance");
  summary.add(phase_4_report(c, r.clusters), "contouring");
  if (keep_all && !r.clusters.empty()) say_what_the_report_leaves_out(r, summary);
  if (r.refinement) summary.add(refinement_report(*r.refinement), "refinement");
  if (r.simplification) summary.add(simplification_report(*r.simplification, r.planes.rho), "simplification");
  if (r.mesh().has_colors()) summary.add(colors_report(options.colors, r.seconds_colors), "colors");
  if (!keep_all) release_all_but_the_mesh(r);
  summary.add(mesh_report(r.mesh()), "mesh");
}

void finish_run(Summary& summary, const std::filesystem::path& output, double seconds_write, double seconds_total) {
  summary.say("wrote     " + output.string() + " (" + format_seconds(seconds_write) + "); total " +
              format_seconds(seconds_total));
  summary.stats()["output"]["file"] = output.string();
  summary.stats()["output"]["seconds"] = seconds_write;
  summary.stats()["threads"] = thread_count();
  summary.stats()["seconds_total"] = seconds_total;
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
