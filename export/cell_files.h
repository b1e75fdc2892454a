// Writing the cell sheet as PLY and OBJ files for Rhino, Blender and Houdini.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "cells/cells.h"
#include "cells/surface.h"

namespace cellform::exporters {

/// Writes the cells as a binary little-endian PLY file.
/// Elements, in this order:
/// - `vertex` (one per cell, in index order): double x y z (model units), uchar type (CellType value),
///   uint age (steps), uint generation, uint id (the low 32 bits of the 64-bit cell id: PLY has no 64-bit
///   integer type), uchar fixed (0 or 1), then one float property per entry of cells.attributes in name
///   order, the name sanitised to [A-Za-z0-9_] (other characters become '_', a leading digit gets a leading
///   '_', a name already taken gets a suffix "_2", "_3", ...);
/// - `face` (surface.triangles): list uchar int vertex_indices;
/// - `edge` (surface.edges, the links): int vertex1, int vertex2. Blender imports these as mesh edges;
///   readers that know only vertices and faces skip the element (OpenMesh warns about it and reads the rest).
/// The file appears complete or not at all. Throws core::FileError naming the path if it cannot be written,
/// core::InvalidInput if the surface refers to a cell that does not exist or an attribute has the wrong size.
void write_cells_ply(const std::filesystem::path& path, const cells::Cells& cells, const cells::Surface& surface);

/// Writes the cells as an OBJ file: a comment header with the counts, one `v x y z` line per cell (model
/// units, "%.9g" about the origin, more digits far from it: core::coordinate_digits), one `f a b c` line per
/// triangle and one `l a b` line per link that is not a side of any triangle (indices 1-based). Atomic; throws as
/// write_cells_ply does.
void write_cells_obj(const std::filesystem::path& path, const cells::Cells& cells, const cells::Surface& surface);

/// File name of one frame of a sequence: stem, '_', the step zero-padded to six digits (more if needed),
/// '.', the extension (given with or without its dot). frame_name("cells", 120, "ply") == "cells_000120.ply".
std::string frame_name(const std::string& stem, std::uint64_t step, const std::string& ext);

}  // namespace cellform::exporters
