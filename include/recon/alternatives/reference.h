#pragma once
// The textbook path: Hoppe, DeRose, Duchamp, McDonald and Stuetzle's four
// phases written as plainly as they can be, each in a few dozen lines
// (reference.cpp). Read this first; the optimised phases (tangent_planes.h,
// riemannian_graph.h, orientation.h, signed_distance.h, marching_cubes.h)
// compute the same things faster, and the tests hold them to it: on small
// clouds reconstruct() with Method::hoppe92 and the options of
// plain_options() draws the same mesh as reference::reconstruct.
//
//   I.   Tangent planes. The k nearest samples of each x_i (itself included,
//        found by comparing every pair): their centroid is o_i, and n_i is
//        the eigenvector of their covariance with the smallest eigenvalue.
//   II.  Orientation. The Riemannian graph joins i and j when x_j is among
//        x_i's k nearest or x_i among x_j's, or when the Euclidean minimum
//        spanning tree of the samples (Prim on the complete graph) joins
//        them; an edge costs 1 - |n_i . n_j|. Prim's algorithm (a
//        std::priority_queue) grows the graph's minimum spanning tree from
//        the plane of highest origin, whose normal is made to point to +z;
//        in the order Prim reaches them, a plane whose normal points
//        against its parent's is flipped.
//   III. Signed distance. f(p) = (p - o_i) . n_i for the origin o_i nearest
//        p. f is undefined unless a sample lies within rho + delta of the
//        foot point p - f(p) n_i (Hoppe's rule), or within
//        1.5 rho + delta + |f(p)| of p (signed_distance.h; that ball holds
//        the first, so it alone decides, and the first is a quick try).
//   IV.  Contouring. Marching cubes of side `cell` on the lattice of
//        make_lattice(), walked from the cubes holding a sample through the
//        faces the surface crosses (or touches at a corner where f = 0);
//        corner values are kept in a std::unordered_map. A cube with an
//        undefined corner draws nothing and leads nowhere. Each crossed edge
//        gets one vertex, shared by its cubes, at the linear interpolation
//        of f (kept 1/1000 of an edge off the corners), and the case table
//        (marching_cubes_table.h) joins them.
//
// The optimised path adds what this one leaves out: the estimated and
// local rho, the automatic k, the separation of nearby objects, the
// neighbour vote, isolated samples, the working offset. plain_options()
// turns those off so that the two can be compared. Meant for a few
// thousand points.

#include "recon/core/point_cloud.h"
#include "recon/reconstruct.h"
#include "recon/structures/mesh.h"

#include <cstdint>
#include <span>
#include <vector>

namespace recon::reference {

struct Options {
  int k = 20;          ///< samples per neighbourhood, the sample itself included
  double rho = 0.0;    ///< sampling density (a length, > 0)
  double delta = 0.0;  ///< noise level (a length, >= 0)
  double cell = 0.0;   ///< cube side (a length, > 0)
};

struct Result {
  std::vector<Vec3> origins;          ///< o_i, per input point
  std::vector<Vec3> normals;          ///< n_i, unit, oriented by phase II
  std::vector<Edge> emst;             ///< the samples' Euclidean minimum spanning tree (u < v)
  std::vector<Edge> graph;            ///< the Riemannian graph (u < v, weight 1 - |n_u . n_v|), sorted by (u, v)
  std::vector<std::uint32_t> parent;  ///< phase II's spanning tree; the root is its own parent
  std::size_t flips = 0;              ///< normals turned round by the walk
  Mesh mesh;                          ///< phase IV's
};

/// The four phases in a row, on `points` as given (no renumbering, no offset).
/// Cost: O(n^2 + c n) for c lattice corners: O(n^2) in phases I and II (every pair compared), O(n) per corner in
/// phase III.
/// Throws: InvalidInputError for fewer than k points, k < 3, a rho or cell that is not positive, a negative delta,
/// an infinite cell, or a coordinate that is not finite or beyond +-max_coordinate; ResourceLimitError when the
/// lattice needs more than Lattice<3>::max_cells_per_axis cubes along an axis.
/// Pre: none.
[[nodiscard]] Result reconstruct(std::span<const Vec3> points, const Options& options);

/// The options under which reconstruct() with Method::hoppe92 computes what
/// reference::reconstruct does (see above).
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] ReconstructionOptions plain_options(const Options& options);

}  // namespace recon::reference
