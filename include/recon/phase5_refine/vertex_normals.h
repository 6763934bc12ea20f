#pragma once
// Vertex normals for smooth shading (PLY nx ny nz, OBJ vn, GLB NORMAL),
// made only when asked (ReconstructionOptions::vertex_normals).
//
// Two sources, in two steps:
//   1. Phase V (refinement.h) projects most vertices onto a fitted local
//      quadric; the surface's normal there (the quadric's gradient at the
//      projected point, turned to the side the triangles face) is the best
//      normal the data give, and phase V records it in Mesh::normals. The
//      vertices it does not project (crease and corner vertices, whose
//      surface has no single normal; vertices it left unmoved) get (0, 0, 0).
//   2. fill_face_normals, run last (after any simplification), gives every
//      zero entry the area-weighted mean of its triangles' normals: the sum
//      of their cross products, normalised. At a crease that is the mean of
//      the faces meeting there, which is what a viewer shades with.
//
// Why area and not angle weights: the area-weighted sum is what the
// issue asks for, and it is the robust one here: phase V's crease splits
// leave a few near-slivers, whose normal is ill-defined; their area (and so
// their weight) is nearly zero, while an angle weight would give a sliver's
// wide angle a full share of its noisy direction. It also needs no acos.

#include "recon/structures/mesh.h"

#include <cstddef>

namespace recon {

struct FaceNormalFill {
  std::size_t filled = 0;  ///< zero entries given the mean of their triangles' normals
  /// Zero entries whose triangles all have zero area (or no triangle):
  /// given their neighbours' mean, or (0, 0, 1) when that is zero too.
  std::size_t undefined = 0;
};

/// Makes mesh.normals one unit normal per vertex: entries that are zero
/// (all of them when mesh.normals is empty) get the area-weighted mean of
/// the normals of the triangles around them (see above); the others are
/// kept as they are. The result does not depend on the thread count (it
/// runs serially).
/// Cost: O(V + F), one pass over the triangles.
/// Throws: InvalidInputError when mesh.normals is neither empty nor one per
/// vertex, or a triangle names a vertex the mesh does not have.
/// Pre: the non-zero normals given are unit (they are kept).
FaceNormalFill fill_face_normals(Mesh& mesh);

}  // namespace recon
