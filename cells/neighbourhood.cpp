// The dynamic neighbourhood: exact k nearest cells of every cell, recomputed each step.
#include <algorithm>
#include <cmath>

#include "cells/simulation.h"

namespace cellform::cells {

namespace {

// Grid cell size for the k-nearest search: 1.5 times the typical distance to the k-th neighbour, so
// the k nearest almost always lie in the 27 grid cells around a cell (gathered once per grid cell).
// The typical distance comes from the previous links of every 64th cell; the size only affects speed,
// never the (exact) result, and depends on the cells alone, not on the thread count.
double link_grid_cell(const Cells& cells, const Params& params) {
  const double rest = params.rest_length;
  const std::size_t n = cells.size();
  const auto stride = static_cast<std::size_t>(cells.link_stride);
  if (stride == 0 || cells.links.size() != n * stride) return 1.5 * rest;
  double sample[256];
  std::size_t m = 0;
  const std::size_t step = std::max<std::size_t>(64, n / 256 + 1);
  for (std::size_t i = 0; i < n && m < 256; i += step) {
    const Index last = cells.links[i * stride + stride - 1];
    if (last == kNoIndex || last >= n) continue;
    const double d = (cells.position[last] - cells.position[i]).norm();
    if (std::isfinite(d)) sample[m++] = d;
  }
  if (m < 8) return 1.5 * rest;
  std::nth_element(sample, sample + m / 2, sample + m);
  return std::clamp(1.5 * sample[m / 2], 0.25 * rest, 2.0 * rest);
}

}  // namespace

void update_links(Cells& cells, const Params& params, core::PointGrid& grid, int threads) {
  const std::size_t n = cells.size();
  const int k = params.neighbours;
  const double cell = link_grid_cell(cells, params);
  cells.link_stride = k;
  cells.links.resize(n * static_cast<std::size_t>(k));
  grid.build(cells.position, cell);
  grid.nearest_all(k, cells.links.data(), threads);
}

}  // namespace cellform::cells
