// Every header path before the folders (compat/recon/): each still
// compiles, to the header at its new path. Compiled, not run, by the CTest
// OldHeaderPathsCompile (tests/CMakeLists.txt) with RECON_ALLOW_OLD_HEADERS
// defined, which silences their deprecation warnings; OldHeaderPathsWarn
// checks that without it they warn.
#include <recon/binary_heap.h>
#include <recon/boruvka.h>
#include <recon/brute_force_search.h>
#include <recon/complete_graph_mst.h>
#include <recon/counting_queue.h>
#include <recon/emst.h>
#include <recon/errors.h>
#include <recon/fibonacci_heap.h>
#include <recon/fp_traps.h>
#include <recon/graph.h>
#include <recon/interruption.h>
#include <recon/kdtree.h>
#include <recon/kruskal.h>
#include <recon/lab.h>
#include <recon/lattice.h>
#include <recon/lattice_table.h>
#include <recon/list_heap.h>
#include <recon/local_quadrics.h>
#include <recon/marching_cubes.h>
#include <recon/marching_cubes_table.h>
#include <recon/marching_squares.h>
#include <recon/memory_budget.h>
#include <recon/mesh.h>
#include <recon/minimum_spanning_tree.h>
#include <recon/operation_counts.h>
#include <recon/orientation.h>
#include <recon/orientation_graphs.h>
#include <recon/pairing_heap.h>
#include <recon/parallel.h>
#include <recon/pca.h>
#include <recon/point_cloud.h>
#include <recon/polyline.h>
#include <recon/progress.h>
#include <recon/reconstruct_curve.h>
#include <recon/reference.h>
#include <recon/refinement.h>
#include <recon/report.h>
#include <recon/resource_usage.h>
#include <recon/riemannian_graph.h>
#include <recon/shapes.h>
#include <recon/signed_distance.h>
#include <recon/simplification.h>
#include <recon/spatial_order.h>
#include <recon/tangent_planes.h>
#include <recon/tiles.h>
#include <recon/timer.h>
#include <recon/uniform_grid.h>
#include <recon/union_find.h>
#include <recon/version.h>
#include <recon/vertex_colors.h>
#include <recon/vertex_normals.h>

// A few names from different layers, through the old paths.
static_assert(sizeof(recon::KdTree<3>) > 0);
static_assert(sizeof(recon::IndexedBinaryHeap<double>) > 0);
static_assert(sizeof(recon::ReconstructionOptions) > 0);
static_assert(sizeof(recon::TilingOptions) > 0);
