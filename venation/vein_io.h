// Writers for colonisation results: SVG drawings and PLY / OBJ vein polylines with radius, order, flow.
#pragma once

#include <filesystem>
#include <utility>

#include "venation/colonisation.h"

namespace cellform::venation {

/// The box of a top-view drawing (x, y): the outline and every vein node; lo = hi = 0 when both are empty.
std::pair<Vec2, Vec2> drawing_bounds(const VeinTree& tree, const Outline& outline);

/// Drawing options for write_svg().
struct SvgParams {
  double pixels_per_unit = 0;  ///< 0 = fit the leaf into about 1000 pixels
  double margin = 10;          ///< pixels around the drawing
  double min_stroke = 0.5;     ///< pixels: thinnest drawn vein (radius 0 or before compute_widths)
  bool draw_sources = false;   ///< draw the sources passed in as small dots
};

/// SVG of the outline (filled light green) and every vein segment as a stroked path of width 2 * radius
/// of its child node (tip radius for anastomoses; min_stroke if widths were not computed), y pointing
/// up. Written atomically; core::FileError on failure.
void write_svg(const std::filesystem::path& path, const VeinTree& tree, const Outline& outline,
               const SvgParams& params = {}, const std::vector<Vec3>& sources = {});

/// Binary little-endian PLY in the layout of the cell runs' veins.ply (exporters::write_veins_ply, less the
/// cell id): vertices (x, y, z, flow, radius as float; order as int) and an edge element (vertex1 = the
/// tip-side node, vertex2 = its parent), the anastomoses last. Atomic; core::FileError on failure.
void write_vein_ply(const std::filesystem::path& path, const VeinTree& tree);

/// OBJ: `v` lines, each followed by "#a flow radius order" (OBJ has no vertex attributes), and one
/// `l child parent` line per edge (1-based), anastomoses last; as the cell runs' veins.obj. Atomic.
void write_vein_obj(const std::filesystem::path& path, const VeinTree& tree);

}  // namespace cellform::venation
