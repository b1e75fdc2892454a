// Removing a mesher's micrometre edges from a closed triangle mesh, and vertices no triangle uses.
#pragma once

#include <cstddef>

#include "export/mesh.h"

namespace cellform::exporters {

/// Collapses every edge shorter than `min_length` (mesh units; dual contouring leaves such edges where
/// two voxels' vertices land at their shared corner) to its midpoint, where the collapse keeps the mesh
/// as it was in kind: the edge is shared by exactly two triangles, both ends are manifold vertices of
/// consistently oriented fans (each vertex's triangles chain into one cycle), the two ends have no common
/// neighbour but the two opposite vertices (the link condition), those keep at least three triangles, and
/// no other triangle at either end turns over or degenerates. Shortest edges first, ties by index, in
/// rounds (a vertex moved in one waits for the next); deterministic. Each collapse moves its two vertices
/// by half the edge, under min_length / 2 (a vertex collapsed in several rounds moves a little more).
/// Removes the two triangles of each collapsed edge and the vertices left unused; returns how many edges
/// it collapsed. A mesh with a triangle that repeats a corner is left as it is (returns 0).
std::size_t collapse_short_edges(PrintableMesh& mesh, double min_length);

/// Removes the vertices no triangle uses, keeping the others in order, and renumbers the triangles.
void drop_unused_vertices(PrintableMesh& mesh);

}  // namespace cellform::exporters
