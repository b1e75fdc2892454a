// `cellform check FILE`: is a mesh printable? A report a user reads, and an exit code scripts use.
#pragma once

#include <filesystem>
#include <ostream>

namespace cellform::app {

/// Reads an STL, OBJ or PLY file and reports triangles, vertices, parts, boundary and non-manifold edges
/// and vertices, orientation, self-intersections, volume, bounding box (mm) and genus. Returns 0 for a
/// printable mesh, 1 for a mesh that is not, 2 for a file that cannot be read. `json`: machine-readable.
/// `min_wall` (file units; 0 = none): a mesh whose walls are thinner than it over more than 1% of its surface, or
/// whose walls could not be measured, is not printable either.
int check_command(const std::filesystem::path& file, bool json, double min_wall, std::ostream& out, std::ostream& err);

}  // namespace cellform::app
