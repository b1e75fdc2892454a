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

/// ASCII PLY: vertices (x, y, z, radius, flow as float; order as int) and an edge element (vertex1 =
/// base-side node, vertex2 = tip-side node), anastomoses last. Atomic; core::FileError on failure.
void write_vein_ply(const std::filesystem::path& path, const VeinTree& tree);

/// OBJ: `v` lines, one `l a b` line per edge (1-based), and a comment header naming the per-vertex
/// radius / order / flow lines ("# r radius order flow" per vertex, OBJ has no vertex attributes). Atomic.
void write_vein_obj(const std::filesystem::path& path, const VeinTree& tree);

}  // namespace cellform::venation
