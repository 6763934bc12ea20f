#pragma once
// Is a mesh the boundary of a solid? Its triangles must not cross or touch
// except at the edges and vertices they share, and each vertex's triangles
// must form one fan; slicers, booleans and volume meshers reject anything
// else. Every geometric decision here is exact (exact_predicates.h): a
// rounded test would miss the nearly coplanar folds phase V makes, or invent
// crossings between neighbours that only touch.
//
// The textbook test (Moller 1997; Guigue and Devillers 2003) decides a pair
// of triangles by the signs of orientations. Here: two closed triangles meet
// exactly when an edge of one meets the other (their intersection is convex;
// its extreme points lie on an edge of one of them), and a segment meets a
// triangle when its ends are not strictly on one side of the triangle's
// plane and the line through it passes inside the triangle's three edges (or,
// lying in the plane, in the 2D test on a coordinate projection). What the
// triangles share is taken out:
//   - a shared edge (u, v): they meet elsewhere only when coplanar with the
//     opposite vertices on the same side of uv (a fold);
//   - a shared vertex s: when the edge opposite s of one meets the other, or
//     an edge from s of one lies in the other's plane inside its angle at s;
//   - nothing shared: any common point.
// Candidate pairs come from a uniform grid of cells about the size of a
// triangle, each pair tested once, in the cell holding the least corner of
// the overlap of their bounding boxes.

#include "recon/structures/mesh.h"

#include <array>
#include <cstdint>
#include <vector>

namespace recon {

struct MeshEmbedding {
  std::size_t intersecting_pairs = 0;     ///< pairs of triangles meeting other than at what they share
  std::size_t non_manifold_vertices = 0;  ///< vertices whose triangles form two fans or more (pinched)
  std::size_t non_manifold_edges = 0;     ///< edges of three triangles or more
  std::size_t degenerate_triangles = 0;   ///< zero area, exactly (a repeated index or collinear corners)
  /// The intersecting pairs (t1 < t2), the pinched vertices and the degenerate triangles, each sorted.
  std::vector<std::array<std::uint32_t, 2>> pairs;
  std::vector<std::uint32_t> pinched;
  std::vector<std::uint32_t> degenerate;
  /// No intersecting pair, no pinched vertex, no non-manifold edge, no degenerate triangle.
  [[nodiscard]] bool embedded() const {
    return intersecting_pairs == 0 && non_manifold_vertices == 0 && non_manifold_edges == 0 &&
           degenerate_triangles == 0;
  }
};

/// The embedding of `mesh` (#V vertices, #F triangles): the counts above, exactly.
/// Cost: O(V + F log F) for F triangles of about equal size (the grid's sort), plus the pairs sharing a cell:
/// O(F) when no cell holds many triangles; a handful of orientation tests a pair. Parallel over the grid's cells;
/// the result does not depend on the thread count.
/// Throws: InvalidInputError for a vertex index past the end, or a used vertex's coordinate not finite or
/// outside the predicates' exact range (exact_predicates.h: magnitude over 2^290 or under 2^-290, 0 aside).
/// Pre: none.
[[nodiscard]] MeshEmbedding check_embedding(const Mesh& mesh);

/// Whether triangles t1 and t2 of `mesh` meet other than at the vertices (indices) they share, by the rules
/// above; false when either has zero area.
/// Cost: O(1), up to about thirty orientation tests.
/// Throws: nothing.
/// Pre: t1 != t2 and both in range, their indices in range, coordinates in the exact range.
[[nodiscard]] bool triangles_intersect(const Mesh& mesh, std::uint32_t t1, std::uint32_t t2);

}  // namespace recon
