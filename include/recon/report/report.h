#pragma once
// The reconstruction report: one self-contained HTML file that shows every
// phase of a run in an interactive 3D view, with the run's statistics
// beside it (`recon reconstruct ... --report FILE.html`).
//
// This is the visual feedback layer. It reads the phase results the library
// already returns and writes them as data; the drawing is done in the
// browser by the viewer in web/report/ (three.js), which the build bundles
// into this library, so a report needs no network and no other file.
//
// Eight layers, each taken from one phase's result:
//   1. the input points, coloured by component (phase II's pieces), or by
//      their own colours when the run had them (the page offers both);
//   2. the kd-tree's cells, node boxes down to a depth chosen on the page;
//   3. the tangent planes' normals before orientation, coloured by the
//      planarity of their neighbourhood (surface variation, see below);
//   4. the Riemannian graph and its minimum spanning tree, tree edges across
//      which the orientation was reversed highlighted;
//   5. the oriented normals;
//   6. the signed distance at the lattice corners the walk evaluated, by
//      sign, undefined corners marked;
//   7. phase IV's mesh (the 1992 surface), shaded, with its boundary edges;
//   8. phase V's refined mesh (Method::refined only), coloured by each
//      vertex's distance to the 1992 surface of layer 7, with its boundary
//      edges.
// A mesh with colours (Mesh::colors: the final mesh of a run whose input
// had colours, layer 8's or, in hoppe92, layer 7's) is drawn in them; the
// page offers layer 8's distance colours beside them.
//
// The lab panel (`recon lab INPUT --report FILE.html`, lab.h). A report
// may carry the alternatives lab's results (ReportLayers::lab); the page
// then has a "Lab" panel beside the layers, and without them it is exactly
// as above. The panel shows
//   a. the times of the runs as bars, one per run that ran, grouped by kind
//      (search, queue, mst, graph), each group on its own scale (linear, or
//      logarithmic on demand); a run that was skipped is listed with why;
//   b. per kind, a table of what each run counted (pushes, pops, ...; a
//      counter no run of the kind used is left out), its tree's weight, and
//      for the graph runs their edges, pieces, flips and how far they agree
//      with the default run and with the truth;
//   c. each orientation graph the lab kept as a layer of its own, drawn as
//      layer 4 draws the Riemannian graph (the edges, the spanning tree, the
//      tree edges where the orientation turned), with the points coloured by
//      that graph's components (off at first): the complete graph's tree
//      runs between separate objects, and where the sampling is uneven the
//      mutual k-NN graph falls apart into pieces.
// The runs are `recon lab`'s --stats JSON as it was written; the graphs
// are drawn within the same budgets as layers 1 and 4.
//
// Large runs stay viewable: each layer draws at most a budget of elements
// (ReportOptions) and beyond it a regular subsample (every s-th point, edge
// source, corner or triangle), which the page states. Per-point arrays are
// in spatial order, so every s-th point is an even sample of the surface.
// Geometry is stored as little-endian float32 relative to `centre` (the
// middle of the points' bounding box), normals as int8, base64-encoded in a
// JSON block (4 characters per 3 bytes). The default budgets bound a
// report's size whatever the size of the run: a 1M-point torus gives 66 MB,
// two meshes of about a million triangles each.

#include "recon/alternatives/lab.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/orientation.h"
#include "recon/phase4_contour/marching_cubes.h"
#include "recon/phase5_refine/refinement.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace recon {

struct Reconstruction;

struct ReportOptions {
  std::size_t max_points = 100'000;   ///< points drawn, with their planes and normals (27 bytes each)
  std::size_t max_edges = 100'000;    ///< Riemannian-graph edges drawn (24 bytes each; tree edges: one per drawn point)
  std::size_t max_corners = 200'000;  ///< lattice corners drawn (16 bytes each)
  std::size_t max_triangles =
      1'000'000;  ///< mesh triangles drawn, per mesh layer (7 and 8; 12 bytes each, and their vertices)
  std::size_t max_boundary_edges = 100'000;  ///< mesh boundary edges drawn (24 bytes each)
  int max_kdtree_depth = 12;                 ///< kd-tree cells stored down to this depth (the root is depth 0)
  std::string title;                         ///< shown as the page's heading (the input file, say)
  std::string stats_json = "{}";             ///< the run's statistics (the --stats JSON), shown beside the view
};

/// What the report is drawn from. Per-point spans are indexed alike (spatial
/// order, as Reconstruction keeps them); positions are relative to `offset`
/// (input coordinates = position + offset), except the mesh, which is in
/// input coordinates.
struct ReportInput {
  std::span<const Vec3> points;
  Vec3 offset = Vec3::Zero();
  const TangentPlanes<3>* planes = nullptr;      ///< required
  const OrientedNormals<3>* oriented = nullptr;  ///< phase II with its graph kept; null: no layer 4
  std::span<const Vec3>
      normals;  ///< the oriented normals used (phase II's or the input's); empty: none yet (no layer 5)
  std::span<const Color> colors;                 ///< the points' own colours, or empty (none)
  const MarchingCubesResult* contour = nullptr;  ///< null: no layers 6, 7 and 8 (`recon normals`)
  const Mesh* mesh = nullptr;                    ///< the mesh drawn in layer 7; null: contour->mesh
  const Refinement* refinement = nullptr;        ///< phase V (input coordinates); null: no layer 8 (hoppe92)
};

/// What a report draws of a Reconstruction made with keep_graph and keep_corners (without them,
/// layers 4 and 6 are left out). Layer 7 is its contour's mesh, layer 8 its
/// refinement when it has one. The input points to `r`'s arrays: `r` must outlive it.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] ReportInput report_input(const Reconstruction& r);

/// A mesh as drawn (layers 7 and 8): float positions relative to the
/// layers' centre.
struct ReportMesh {
  std::size_t triangles_total = 0;
  std::size_t triangle_stride = 1;       ///< every triangle_stride-th triangle is drawn
  std::vector<float> vertices;           ///< all, or (when subsampled) those of the drawn triangles, 3 each
  std::vector<std::uint32_t> triangles;  ///< 3 per drawn triangle, indices into `vertices`
  std::vector<std::uint8_t> colors;      ///< r g b per drawn vertex when the mesh has colours, else empty
  std::size_t boundary_edges_total = 0;
  std::size_t boundary_stride = 1;
  std::vector<float> boundary_segments;  ///< every boundary_stride-th boundary edge (of the whole mesh), 6 each
};

/// A graph and its minimum spanning tree as drawn (layer 4, and each graph
/// of the lab panel): six floats per segment, relative to the layers' centre.
struct ReportGraph {
  std::size_t edges_total = 0;
  std::size_t vertex_stride = 1;  ///< edges of every vertex_stride-th vertex are drawn
  std::vector<float> segments;
  std::size_t tree_edges_total = 0;
  std::vector<float> tree_segments;     ///< each drawn point (layer 1's) to its parent
  std::vector<std::uint8_t> tree_flip;  ///< per tree segment: orientation reversed across it
  std::size_t tree_flips_total = 0;     ///< over the whole tree
};

/// One orientation graph of the lab (lab.h's LabGraph) as drawn.
struct ReportLabGraph {
  std::string name;  ///< "complete", "emst", "knn", "mutual-knn", "riemannian"
  ReportGraph drawn;
  std::size_t component_count = 0;       ///< the pieces the graph falls into
  std::vector<std::uint32_t> component;  ///< per drawn point (layer 1's): its piece
  std::size_t flips = 0;                 ///< normals reversed from the PCA ones, over all points
};

/// The lab panel's data (see above).
struct ReportLab {
  std::string runs_json = "{}";        ///< `recon lab`'s --stats text: {"runs": [...], ...}
  std::vector<ReportLabGraph> graphs;  ///< in the order given to make_report_lab
};

/// The layers as drawn: float positions relative to `centre`, three floats
/// per point, six per segment. `*_total` counts what the run had, the array
/// sizes what is drawn.
struct ReportLayers {
  Vec3 centre = Vec3::Zero();  ///< input coordinates of the drawing's origin
  double diagonal = 0.0;       ///< of the points' bounding box
  double rho = 0.0;            ///< phase I's median sampling density (the normals are drawn this long)

  // 1. points
  std::size_t points_total = 0;
  std::size_t point_stride = 1;          ///< every point_stride-th point is drawn
  std::vector<float> points;             ///< 3 per drawn point
  std::vector<std::uint32_t> component;  ///< per drawn point (0 when phase II did not run)
  std::size_t component_count = 1;
  std::vector<std::uint8_t> point_colors;  ///< r g b per drawn point when the input had colours, else empty

  // 2. kd-tree cells: the node boxes down to kdtree_drawn_depth, in pre-order
  int kdtree_depth = 0;  ///< of the whole tree
  int kdtree_drawn_depth = 0;
  std::vector<float> kdtree_boxes;         ///< 6 per node: min xyz, max xyz
  std::vector<std::uint8_t> kdtree_level;  ///< per node: its depth; leaves shallower than the drawn depth + 128

  // 3. and 5. planes and normals, per drawn point
  std::vector<float> origins;  ///< o_i
  std::vector<std::int8_t>
      pca_normals;               ///< n_i before orientation, 3 per point, times 127 (a normal drawn needs no more)
  std::vector<float> planarity;  ///< surface variation lambda_0 / (lambda_0 + lambda_1 + lambda_2), in [0, 1/3]
  std::vector<std::uint8_t> no_plane;  ///< 1 where the sample draws no surface (isolated, or copies only)
  std::vector<std::int8_t> normals;    ///< oriented, as pca_normals
  std::vector<std::uint8_t> flipped;   ///< 1 where the oriented normal is the PCA normal reversed

  // 4. graph and spanning tree
  bool has_graph = false;
  ReportGraph graph;

  // 6. signed distance at the lattice corners
  bool has_corners = false;
  std::size_t corners_total = 0;
  std::size_t undefined_corners_total = 0;
  std::size_t corner_stride = 1;
  std::vector<float> corners;        ///< 3 per drawn corner
  std::vector<float> corner_values;  ///< f, NaN where undefined
  double cell = 0.0;

  // 7. phase IV's mesh
  bool has_mesh = false;
  ReportMesh mesh;

  // 8. phase V's refined mesh, and how far it lies from layer 7's
  bool has_refinement = false;
  ReportMesh refined;
  /// Per drawn vertex of `refined`: its distance to layer 7's mesh (the
  /// nearest point on any of its triangles, all of them, not only those drawn).
  std::vector<float> refined_distance;
  double distance_mean = 0.0;  ///< over the drawn vertices
  double distance_max = 0.0;
  double distance_scale = 0.0;  ///< where the page's colour ramp ends: the 98th percentile of refined_distance

  /// The bounding box of everything drawn, relative to `centre` (the page's
  /// first view frames it).
  Box<3> drawn_box;

  /// The lab panel (see above); absent: no panel.
  std::optional<ReportLab> lab;
};

/// The layers as drawn (see above), each within its budget of `options`.
/// Cost: O(n + E + c + F log F) for the points, graph edges, corners and triangles (the boundary edges sorted);
/// with a refinement, a kd-tree over layer 7's vertices and a nearest-triangle search per drawn vertex of layer 8.
/// Throws: InvalidInputError when input.planes is null or the spans' sizes
/// disagree (planes and normals: one per point, or no normals; colors: one per point, or none; a mesh's colours:
/// one per vertex, or none).
/// Pre: the meshes' indices in range; contour, mesh and refinement from the run of these points.
[[nodiscard]] ReportLayers make_report_layers(const ReportInput& input, const ReportOptions& options = {});

/// The lab panel's data for a report whose layers were made from the same
/// points (ReportInput::points and offset): `graphs` as run_lab keeps them
/// (LabResult::graphs, with keep_graphs), `runs_json` as `recon lab`
/// writes --stats (app/lab_command.cpp). Each graph is drawn as layer 4 is, within
/// options.max_edges, and its components are given for the points layer 1
/// draws. So `recon lab` makes its report as
///   ReportLayers layers = make_report_layers(input, options);  // planes, default_orientation
///   layers.lab = make_report_lab(result.graphs, stats_json, input.points, input.offset, layers, options);
/// Cost: O(n + E) per graph, for its E edges.
/// Throws: InvalidInputError when the points are not as many as the layers
/// were made from, or a graph's vertices, tree, signs or component labels
/// are not one per point.
/// Pre: the points those the layers were made from (only their number is checked).
[[nodiscard]] ReportLab make_report_lab(std::span<const LabGraph> graphs, std::string runs_json,
                                        std::span<const Vec3> points, Vec3 offset, const ReportLayers& layers,
                                        const ReportOptions& options = {});

/// The data as the viewer reads it (web/report/viewer.js, showReport): the
/// JSON block, and array N's bytes (little-endian) as arrays[N]. The arrays
/// lie in `layers`, which must outlive them. The web page (web/webapp/)
/// hands them to its viewer as they are, without base64.
struct ReportData {
  std::string json;
  std::vector<std::span<const std::byte>> arrays;
};
/// The JSON and the arrays of `layers`, as above.
/// Cost: O(size of the layers).
/// Throws: nothing.
/// Pre: options.stats_json and the lab's runs_json are JSON (copied as they are).
[[nodiscard]] ReportData report_data(const ReportLayers& layers, const ReportOptions& options = {});
/// The whole page: the viewer (HTML, CSS, bundled JavaScript) and the data (its arrays base64-encoded).
/// Cost: O(size of the layers + the viewer's).
/// Throws: InvalidInputError in a recon built without the viewer (RECON_REPORT=OFF).
/// Pre: as report_data.
[[nodiscard]] std::string report_html(const ReportLayers& layers, const ReportOptions& options = {});

/// report_html written atomically to `path` (io/atomic_file.h).
/// Cost: as report_html, and the write.
/// Throws: IoError when the file cannot be written; InvalidInputError as report_html.
/// Pre: as report_data.
void write_report(const std::filesystem::path& path, const ReportLayers& layers, const ReportOptions& options = {});

/// The viewer's page around the data, as bundled at build time:
/// the page is head + JSON + tail.
struct ReportPage {
  std::string_view head, tail;
};
/// Cost: O(1).
/// Throws: InvalidInputError in a recon built without the viewer (RECON_REPORT=OFF).
/// Pre: none.
[[nodiscard]] ReportPage report_page();

}  // namespace recon
