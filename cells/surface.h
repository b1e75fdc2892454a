// A triangulation of the cell sheet from the link graph: in one layer for files (edge-manifold), or every
// clique for printed shells.
#pragma once

#include <array>
#include <vector>

#include "cells/cells.h"

namespace cellform::cells {

/// Triangles and edges of the cell sheet, indices into Cells.
struct Surface {
  /// Oriented consistently across manifold edges where possible: each connected piece up (+z) if open, out
  /// if closed or nearly so (a spherical bowl from about a hemisphere on), by a score that changes with the
  /// shape by small steps, so that a growing sheet keeps its faces; where overlapping triangles make a piece
  /// non-orientable, neighbours along a seam on its sharpest creases face opposite ways.
  std::vector<std::array<Index, 3>> triangles;
  std::vector<std::array<Index, 2>> edges;  ///< every link (i < j), including vein parent links
};

/// Edges are pairs linked either way (or vein parent and child). Triangles are 3-cliques of that graph;
/// with `one_layer` (for files a modeller opens), of that graph less each edge crossing a shorter one as
/// the diagonals of a quad do (the k-nearest links often hold both diagonals, whose cliques lay four
/// triangles over the quad in two layers), then at most two on any side, no two folded onto each other
/// (third corners less than 90 degrees apart round their side) and no two lying over each other or crossing
/// round a common corner (over each other: nearly in one plane, their angles there overlapping; greedy,
/// shortest longest side first: a crowded or buckled sheet's cliques overlap), with the 4-cycles then left
/// open closed on their shorter diagonal where neither triangle crosses a triangle, and the small holes left after
/// orienting (a loop of 3 to 12 boundary sides whose triangles face one way, where a fill can face that way too, fold
/// nowhere and cross no triangle) closed by their shortest-diagonal triangulation. So every side of the one-layer
/// surface borders one or two triangles; sheets that meet keep a seam. Without it every clique is kept: overlapping,
/// but with no gap (what a thickened shell wants). Deterministic: triangles sorted by smallest index.
Surface triangulate(const Cells& cells, bool one_layer = true);

/// For a thickened shell, where overlapping triangles cost nothing and every gap is a hole in the print:
/// every clique of the link graph, then the triangles of the one-layer surface that are no clique (closed
/// quads and filled holes). Sorted; each corner triple once (as the first of the two surfaces has it).
std::vector<std::array<Index, 3>> covering_triangles(const Cells& cells);

}  // namespace cellform::cells
