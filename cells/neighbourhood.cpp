// The dynamic neighbourhood: exact k nearest cells of every cell, recomputed each step.
#include <algorithm>
#include <cmath>

#include "cells/simulation.h"
#include "core/parallel.h"

namespace cellform::cells {

namespace {

// Typical distance to the k-th neighbour, from the previous links of every 64th cell (rest length when
// there are none). It sets the grid cell size, which only affects speed, never the (exact) result, and
// depends on the cells alone, not on the thread count.
double typical_kth_distance(const Cells& cells, const Params& params) {
  const double rest = params.rest_length;
  const std::size_t n = cells.size();
  const auto stride = static_cast<std::size_t>(cells.link_stride);
  if (stride == 0 || cells.links.size() != n * stride) return rest;
  double sample[256];
  std::size_t m = 0;
  const std::size_t step = std::max<std::size_t>(64, n / 256 + 1);
  for (std::size_t i = 0; i < n && m < 256; i += step) {
    const Index last = cells.links[i * stride + stride - 1];
    if (last == kNoIndex || last >= n) continue;
    const double d = (cells.position[last] - cells.position[i]).norm();
    if (std::isfinite(d)) sample[m++] = d;
  }
  if (m < 8) return rest;
  std::nth_element(sample, sample + m / 2, sample + m);
  return std::clamp(sample[m / 2], rest / 6, 4.0 * rest / 3);
}

}  // namespace

void update_links(Cells& cells, const Params& params, core::PointGrid& grid, int threads) {
  const std::size_t n = cells.size();
  const int k = params.neighbours;
  const double kth = typical_kth_distance(cells, params);
  // Last step's links (still k distinct cells each) bound every search radius; the dense grid scans the
  // box of that ball, so cells about as large as the k-th distance keep the box small. The hashed grid
  // gathers the 27 cells around each cell instead, which must usually hold the k nearest: 1.5 times.
  const bool hinted = cells.link_stride == k && cells.links.size() == n * static_cast<std::size_t>(k);
  cells.link_stride = k;
  cells.links.resize(n * static_cast<std::size_t>(k));
  grid.build(cells.position, kth);
  if (!grid.dense()) grid.build(cells.position, 1.5 * kth);
  grid.nearest_all(k, cells.links.data(), threads, hinted ? cells.links.data() : nullptr);
  if (params.link_range > 0) {
    // links are sorted by distance: drop the tail beyond the range (each cell writes its own row)
    const double r2 = params.link_range * params.link_range * params.rest_length * params.rest_length;
    core::parallel_for(n, threads, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        for (int s = k - 1; s >= 0; --s) {
          Index& j = cells.links[i * static_cast<std::size_t>(k) + static_cast<std::size_t>(s)];
          if (j == kNoIndex) continue;
          if ((cells.position[j] - cells.position[i]).squaredNorm() <= r2) break;
          j = kNoIndex;
        }
    });
  }
}

}  // namespace cellform::cells
