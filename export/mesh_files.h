// Printable mesh files: binary STL, OBJ, PLY and an OpenSCAD polyhedron, all written atomically.
#pragma once

#include <filesystem>

#include "export/mesh.h"

namespace cellform::exporters {

/// Binary STL (little-endian float32; units as the mesh: mm for thicken() output), with facet normals.
/// Atomic; core::FileError on failure; core::InvalidInput beyond 2^32 - 1 triangles.
void write_stl(const std::filesystem::path& path, const PrintableMesh& mesh);

/// Wavefront OBJ: `v` and `f` lines (1-based), counter-clockwise faces. Atomic; core::FileError on failure.
void write_obj(const std::filesystem::path& path, const PrintableMesh& mesh);

/// Binary little-endian PLY: float x, y, z; faces as uchar-counted int lists. Atomic; core::FileError;
/// core::InvalidInput beyond 2^31 - 1 vertices (the int indices).
void write_ply(const std::filesystem::path& path, const PrintableMesh& mesh);

/// OpenSCAD source with one `polyhedron(points = [...], faces = [...])`. OpenSCAD wants faces clockwise
/// seen from outside, so each triangle is written reversed. Renders headless with
/// `openscad -o out.stl file.scad`. Atomic; core::FileError on failure.
void write_scad(const std::filesystem::path& path, const PrintableMesh& mesh);

/// Picks the writer from the extension (.stl, .obj, .ply, .scad, case-insensitive); core::InvalidInput
/// for any other extension.
void write_mesh(const std::filesystem::path& path, const PrintableMesh& mesh);

}  // namespace cellform::exporters
