// Reading triangle meshes back: STL, OBJ and PLY as triangle soups (see read_mesh).
#pragma once

#include <filesystem>

#include "export/mesh.h"

namespace cellform::exporters {

/// Reads a triangle soup from STL (binary or ASCII; vertices welded at exactly equal positions), OBJ
/// (v and f lines; polygons fanned into triangles) or PLY (ASCII, binary little-endian or binary
/// big-endian; polygons fanned). Nothing is dropped or repaired, so non-manifold files come back as they are.
/// Throws core::FileError naming the file for a missing file, an unknown extension or malformed content.
PrintableMesh read_mesh(const std::filesystem::path& path);

}  // namespace cellform::exporters
