#pragma once
// Colours for the vertices of a reconstructed mesh, from the colours of the
// samples it was reconstructed from (reconstruct() calls it when the cloud
// has colours).
//
// A mesh vertex lies between samples: the lattice cell is about the sample
// spacing, so several samples stand around each vertex. Each vertex gets a
// blend of the colours of its k nearest samples, weighted by inverse
// squared distance (Shepard's interpolation):
//
//   colour(v) = sum_i w_i c_i / sum_i w_i,   w_i = 1 / (|v - p_i|^2 + eps),
//
// over the k samples p_i nearest to v, eps a vanishing floor (a millionth
// of the k-th squared distance) so that a vertex on a sample takes that
// sample's colour, and k samples all at the vertex share their weight.
// Why a blend rather than the nearest sample: a vertex stands for the patch
// of surface around it, which holds several samples; the nearest one alone
// makes a speckle of single samples wherever the colours are noisy (a
// sensor's noise, a texture finer than the cells), and aliases a colour
// border into a staircase of whole samples. The inverse-distance weights
// keep a border sharp to about one sample spacing, and cost k neighbours a
// vertex instead of one (a few per cent of a run: docs/benchmarks.md).
//
// Channels are averaged as the stored 8-bit values (sRGB), as MeshLab and
// Open3D do, and rounded. A limit: where two sheets of a thin part lie
// within k samples of each other, a vertex may take some colour of the
// other sheet.
//
// Each vertex is computed alone, in parallel (parallel.h): the result is
// the same bit for bit for any thread count.

#include "recon/core/point_cloud.h"
#include "recon/structures/kdtree.h"

#include <span>
#include <vector>

namespace recon {

struct VertexColorOptions {
  int k = 8;  ///< samples blended per vertex, 1 to 64 (1: the nearest sample's colour)
};

/// The colour of each of `vertices`, from `samples` (a kd-tree over the
/// sample positions, in the same coordinates as the vertices) and
/// `colors[i]`, the colour of the tree's point i. Shapes: vertices #V,
/// colors #samples; the result #V.
/// Cost: O(V (log n + k)) expected for n samples: a k-nearest query per vertex.
/// Throws: InvalidInputError when colors are not one per sample, the tree is
/// empty (and there are vertices), or k is outside 1 to 64.
/// Pre: finite vertices.
[[nodiscard]] std::vector<Color> vertex_colors(std::span<const Vec3> vertices, const KdTree<3>& samples,
                                               std::span<const Color> colors, const VertexColorOptions& options = {});

}  // namespace recon
