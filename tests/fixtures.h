// Test fixtures built in code: a flat hex sheet of cells with its exact lattice links.
#pragma once

#include <cmath>

#include "cells/cells.h"

namespace cellform::testing {

/// A flat sheet in the z = 0 plane: `rows` rows of `cols` cells, `spacing` apart, odd rows shifted by
/// half a spacing (a triangular lattice: interior cells have six neighbours at distance `spacing`).
inline cells::Cells hex_sheet(int rows, int cols, double spacing = 1.0) {
  cells::Cells c;
  const double row_height = spacing * std::sqrt(3.0) / 2.0;
  for (int r = 0; r < rows; ++r)
    for (int q = 0; q < cols; ++q)
      cells::add_cell(c, core::Vec3((q + (r % 2 ? 0.5 : 0.0)) * spacing, r * row_height, 0.0));
  return c;
}

/// Replaces the links by the lattice edges of hex_sheet (cells within spacing * (1 + 1e-9)), stride 6,
/// sorted by index and padded with kNoIndex. Brute force: for small sheets only.
inline void link_lattice(cells::Cells& c, double spacing = 1.0) {
  const std::size_t n = c.size();
  c.link_stride = 6;
  c.links.assign(n * 6, core::kNoIndex);
  const double r2 = spacing * spacing * (1 + 1e-9);
  for (std::size_t i = 0; i < n; ++i) {
    int k = 0;
    for (std::size_t j = 0; j < n && k < 6; ++j)
      if (j != i && (c.position[i] - c.position[j]).squaredNorm() <= r2)
        c.links[i * 6 + static_cast<std::size_t>(k++)] = static_cast<core::Index>(j);
  }
}

}  // namespace cellform::testing
