// Writers for colonisation results: SVG drawings and PLY / OBJ vein polylines with radius, order, flow.
#pragma once

#include <filesystem>
#include <utility>

#include "venation/colonisation.h"

namespace cellform::venation {

/// The box of a top-view drawing (x, y): the outline and every vein node with its radius (as far as its
/// round stroke reaches); lo = hi = 0 when both are empty.
std::pair<Vec2, Vec2> drawing_bounds(const VeinTree& tree, const Outline& outline);

/// Drawing options for write_svg().
/// The drawing is in millimetres, for plotters and laser cutters: the file's width and height carry "mm"
/// and one user unit of the viewBox is one millimetre.
struct SvgParams {
  double size = 200;            ///< mm: longer side of the drawn box (outline and veins' strokes), margin excluded
  double scale = 0;             ///< mm per model unit; when > 0 it replaces `size` (e.g. a print's scale)
  double margin = 5;            ///< mm: blank border around the drawing
  double min_stroke = 0.1;      ///< mm: thinnest drawn vein (radius 0 or before compute_widths)
  double outline_stroke = 0.2;  ///< mm: width of the outline's line
  bool draw_sources = false;    ///< draw the sources passed in as dots of 1 mm diameter
  /// One path per vein, from where it leaves its parent vein along its main child (the child of its own
  /// order, the widest) to its tip, at its length-weighted mean width: about half the paths, so half the
  /// pen lifts of a plotter, which draws every width alike. Off: a path per run between branch points.
  bool join_veins = false;
};

/// The page write_svg() drew.
struct SvgPage {
  double scale = 0;              ///< mm per model unit
  double width = 0, height = 0;  ///< mm, margins included
};

/// SVG of the veins as stroked paths of width 2 * radius of each segment's child node (an anastomosis: of the
/// finer of the two nodes it joins; at least min_stroke) and the outline as a line. One path runs through every node
/// with a single child while the width stays the same, so a plotter lifts its pen only at branch points, width changes
/// and tips (with join_veins, a path runs a whole vein); anastomoses are one path each. Inkscape layers, their names
/// beginning with their number (AxiDraw plots one layer by number): "1 veins of order 1", "2 veins of order 2", ... (an
/// anastomosis joins the higher order of its ends), each in its own stroke colour from LightBurn's layer palette (00,
/// 01, ...: a laser program that separates operations by colour gives each order its own layer), then the outline last,
/// "100 outline" in LightBurn's colour 09 (a laser cutter cuts it after engraving the veins; a plotter plots it as
/// layer 100 whatever the leaf); the sources, when drawn, in a layer "% sources" that AxiDraw skips.
/// Within a layer the paths come in plot_order() from where the pen is (the page's top-left corner, then
/// the end of the previous layer), each drawn from the end nearer the pen. All is scaled by the same
/// factor (`scale`, or else size / the box's longer side: mm per model unit), y pointing up. Written
/// atomically; core::FileError on failure. Returns the page drawn.
SvgPage write_svg(const std::filesystem::path& path, const VeinTree& tree, const Outline& outline,
                  const SvgParams& params = {}, const std::vector<Vec3>& sources = {});

/// Binary little-endian PLY in the layout of the cell runs' veins.ply (exporters::write_veins_ply, less the
/// cell id): vertices (x, y, z as double; flow, radius as float; order as int) and an edge element (vertex1 = the
/// tip-side node, vertex2 = its parent), the anastomoses last. Atomic; core::FileError on failure.
void write_vein_ply(const std::filesystem::path& path, const VeinTree& tree);

/// OBJ: `v` lines, each followed by "#a flow radius order" (OBJ has no vertex attributes), and `l` polylines
/// (1-based) that run through every node of one child, a curve per branch (core::polylines of the edges child
/// -> parent, then the anastomoses); as the cell runs' veins.obj. Atomic.
void write_vein_obj(const std::filesystem::path& path, const VeinTree& tree);

}  // namespace cellform::venation
