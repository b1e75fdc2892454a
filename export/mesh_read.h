// Reading triangle meshes back: STL, OBJ and PLY as triangle soups (see read_mesh).
#pragma once

#include <filesystem>

#include "export/mesh.h"

namespace cellform::exporters {

/// Reads a triangle soup from STL (binary or ASCII; vertices welded at exactly equal positions; a binary one whose
/// header says 0 triangles, as some exporters leave it, by the facets that fill it), OBJ
/// (v and f lines) or PLY (ASCII, binary little-endian or binary big-endian); polygons are split into
/// triangles where they lie (core::triangulate_polygon: convex ones fanned, concave ones ear-clipped). Nothing
/// is dropped or repaired, so non-manifold files come back as they are. Throws core::FileError naming the
/// file for a missing file, an unknown extension or malformed content (a concave face of more than
/// core::kMaxConcaveCorners corners, too).
PrintableMesh read_mesh(const std::filesystem::path& path);

/// What a mesh file says beyond its triangles.
struct MeshFileNotes {
  bool normals_checked = false;             ///< an STL whose stored normals were paired with its facets
  std::size_t stored_normals = 0;           ///< STL: facets whose stored normal is not zero
  std::size_t normals_against_winding = 0;  ///< STL: of those, the facets whose stored normal points against
                                            ///< the normal of their corners' winding (right-hand rule)
  std::size_t stl_padding = 0;  ///< binary STL: bytes after its last facet (fewer than a facet's 50), ignored
  bool stl_count_zero = false;  ///< binary STL whose header says 0 triangles: the facets that fill it were read
};

/// As read_mesh(path), also filling `notes` (STL facet normals are otherwise ignored: the winding decides).
PrintableMesh read_mesh(const std::filesystem::path& path, MeshFileNotes& notes);

}  // namespace cellform::exporters
