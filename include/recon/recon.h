#pragma once
// All of recon's public headers, one include for a program that wants the
// whole library. A header's path says where it stands: a folder per phase
// of the paper (phase1_planes/ ... phase4_contour/), the phases beyond it
// (phase5_refine/, phase6_simplify/), the data structures (structures/),
// the formats (io/), the lab's alternatives (alternatives/), the 2D curves
// (curves/), tiled runs (tiles/), the report (report/), what everything
// uses (core/), and the front door at the top (reconstruct.h).
//
// The paths before the folders (<recon/kdtree.h> ...) still compile, each
// with a deprecation warning naming its new path (compat/ in the source).

// core/
#include "recon/core/errors.h"
#include "recon/core/fp_traps.h"
#include "recon/core/interruption.h"
#include "recon/core/memory_budget.h"
#include "recon/core/operation_counts.h"
#include "recon/core/parallel.h"
#include "recon/core/point_cloud.h"
#include "recon/core/progress.h"
#include "recon/core/resource_usage.h"
#include "recon/core/shapes.h"
#include "recon/core/timer.h"
#include "recon/core/version.h"

// structures/
#include "recon/structures/binary_heap.h"
#include "recon/structures/exact_predicates.h"
#include "recon/structures/fibonacci_heap.h"
#include "recon/structures/graph.h"
#include "recon/structures/kdtree.h"
#include "recon/structures/lattice.h"
#include "recon/structures/lattice_table.h"
#include "recon/structures/list_heap.h"
#include "recon/structures/mesh.h"
#include "recon/structures/mesh_embedding.h"
#include "recon/structures/pairing_heap.h"
#include "recon/structures/polyline.h"
#include "recon/structures/spatial_order.h"
#include "recon/structures/union_find.h"

// phase1_planes/
#include "recon/phase1_planes/local_quadrics.h"
#include "recon/phase1_planes/pca.h"
#include "recon/phase1_planes/tangent_planes.h"

// phase2_orientation/
#include "recon/phase2_orientation/emst.h"
#include "recon/phase2_orientation/minimum_spanning_tree.h"
#include "recon/phase2_orientation/orientation.h"
#include "recon/phase2_orientation/riemannian_graph.h"

// phase3_distance/
#include "recon/phase3_distance/signed_distance.h"

// phase4_contour/
#include "recon/phase4_contour/marching_cubes.h"
#include "recon/phase4_contour/marching_cubes_table.h"
#include "recon/phase4_contour/marching_squares.h"

// phase5_refine/
#include "recon/phase5_refine/refinement.h"
#include "recon/phase5_refine/vertex_colors.h"
#include "recon/phase5_refine/vertex_normals.h"

// phase6_simplify/
#include "recon/phase6_simplify/simplification.h"

// io/
#include "recon/io/atomic_file.h"
#include "recon/io/curve_io.h"
#include "recon/io/mesh_io.h"
#include "recon/io/mesh_stream.h"
#include "recon/io/point_io.h"
#include "recon/io/point_stream.h"

// The front door
#include "recon/estimate_normals.h"
#include "recon/reconstruct.h"
#include "recon/reconstruct_parts.h"

// alternatives/
#include "recon/alternatives/boruvka.h"
#include "recon/alternatives/brute_force_search.h"
#include "recon/alternatives/complete_graph_mst.h"
#include "recon/alternatives/counting_queue.h"
#include "recon/alternatives/kruskal.h"
#include "recon/alternatives/lab.h"
#include "recon/alternatives/orientation_graphs.h"
#include "recon/alternatives/reference.h"
#include "recon/alternatives/uniform_grid.h"

// curves/
#include "recon/curves/reconstruct_curve.h"

// tiles/
#include "recon/tiles/tiles.h"

// report/
#include "recon/report/report.h"
