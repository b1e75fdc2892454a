// The vein graph as polylines: PLY with an edge element and OBJ line elements, for thickening and modelling.
#pragma once

#include <filesystem>

#include "venation/canalisation.h"

namespace cellform::exporters {

/// Binary little-endian PLY: vertices (x, y, z as double; flow, radius as float; order as int; id as uint)
/// and an edge element (vertex1, vertex2: child node, parent node). Atomic; core::FileError on failure.
void write_veins_ply(const std::filesystem::path& path, const venation::VeinGraph& graph, const cells::Cells& cells);

/// OBJ with `v` lines and one `l` polyline per branch (core::polylines: child to parent, from a tip or
/// fork to the next fork or root), plus a comment per vertex giving flow, radius and order (OBJ has no vertex
/// attributes). Atomic.
void write_veins_obj(const std::filesystem::path& path, const venation::VeinGraph& graph);

}  // namespace cellform::exporters
