// Removing a mesher's micrometre edges from a closed triangle mesh.
#pragma once

#include <cstddef>

#include "export/mesh.h"

namespace cellform::exporters {

/// Collapses every edge shorter than `min_length` (mesh units; dual contouring leaves such edges where
/// two voxels' vertices land at their shared corner) to its midpoint, where the collapse keeps the mesh
/// as it was in kind: the edge is shared by exactly two triangles, both ends are manifold vertices, the
/// two ends have no common neighbour but the two opposite vertices (the link condition), those keep at
/// least three triangles, and no other triangle at either end turns over or degenerates. Shortest edges
/// first, ties by index; deterministic. Removes the two triangles of each collapsed edge and the vertices
/// left unused. Returns how many edges it collapsed. Moves no vertex farther than min_length / 2.
std::size_t collapse_short_edges(PrintableMesh& mesh, double min_length);

}  // namespace cellform::exporters
