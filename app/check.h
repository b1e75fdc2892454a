// `cellform check FILE`: is a mesh printable? A report a user reads, and an exit code scripts use.
#pragma once

#include <filesystem>
#include <ostream>

namespace cellform::app {

/// Reads an STL, OBJ or PLY file and reports triangles, vertices, parts, boundary and non-manifold edges
/// and vertices, orientation, self-intersections, volume, bounding box (mm) and genus. Returns 0 for a
/// printable mesh, 1 for a mesh that is not, 2 for a file that cannot be read. `json`: machine-readable.
int check_command(const std::filesystem::path& file, bool json, std::ostream& out, std::ostream& err);

}  // namespace cellform::app
