// The order in which a pen plotter or laser cutter should draw a set of strokes.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "venation/leaf_shape.h"

namespace cellform::venation {

/// A stroke to draw, in the order plot_order() chose.
struct PlotStep {
  std::size_t stroke = 0;  ///< index into the strokes given
  bool reversed = false;   ///< draw it from its last point to its first
};

/// Greedy nearest-next order of open strokes given by their end points (first, last): starting with the
/// pen at `start`, it draws next the stroke with an end nearest to where the pen is (either end: a stroke
/// begun at its last point is drawn reversed), until all are drawn. Ties go to the smaller stroke index,
/// then to the first point. Pen-up travel is what it saves: between paths in generation order a plotter
/// jumps across the whole drawing (a leaf's veins: 35 m of travel for 3.6 m of line, 1.4 m in this order).
/// Any units; time about linear in strokes for ends spread over an area or along a line (a grid of the
/// ends, with counts per block to skip empty space). Strokes with an end that is not a finite number come
/// last, in index order.
std::vector<PlotStep> plot_order(const std::vector<std::array<Vec2, 2>>& ends, const Vec2& start);

}  // namespace cellform::venation
