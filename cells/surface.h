// A triangulation of the cell sheet from the link graph; non-manifold wherever the sheet is.
#pragma once

#include <array>
#include <vector>

#include "cells/cells.h"

namespace cellform::cells {

/// Triangles and edges of the cell sheet, indices into Cells.
struct Surface {
  std::vector<std::array<Index, 3>> triangles;  ///< oriented consistently across manifold edges where possible
  std::vector<std::array<Index, 2>> edges;      ///< every link (i < j), including vein parent links
};

/// Edges are pairs linked either way (or vein parent and child); triangles are 3-cliques of that graph.
/// Deterministic: sorted by smallest index.
Surface triangulate(const Cells& cells);

}  // namespace cellform::cells
