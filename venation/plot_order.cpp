// Greedy nearest-next ordering of strokes over a two-level grid of their end points.
#include "venation/plot_order.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>

namespace cellform::venation {

std::vector<PlotStep> plot_order(const std::vector<std::array<Vec2, 2>>& ends, const Vec2& start) {
  const std::size_t n = ends.size();
  std::vector<PlotStep> order;
  order.reserve(n);
  if (n == 0) return order;
  // grid of the 2n end points, about two per cell; blocks of kBlock x kBlock cells count the live ends
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& e : ends)
    for (const Vec2& q : e)
      if (q.allFinite()) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
  if (!(lo.x() <= hi.x())) lo = hi = Vec2::Zero();  // no finite end
  // cells about the size that holds one stroke's two ends, and never more cells along a side than
  // strokes (a flat box, all ends on a line, is one row of n cells, not a grid of 1e-300 cells)
  const double wx = hi.x() - lo.x(), wy = hi.y() - lo.y();
  const double nd = static_cast<double>(n);
  double cell = std::sqrt(wx / nd) * std::sqrt(wy);  // sqrt(wx wy / n) without overflow
  cell = std::max(cell, std::max(wx, wy) / nd);
  if (!(cell > 0) || !std::isfinite(cell)) cell = 1;  // all ends at one point (or not finite: see below)
  auto side = [&](double w) { return static_cast<int>(std::clamp(std::floor(w / cell) + 1, 1.0, nd + 1)); };
  const int gx = side(wx), gy = side(wy);
  const double cx = std::max(wx / gx, cell) * (1 + 1e-12), cy = std::max(wy / gy, cell) * (1 + 1e-12);
  auto cell_of = [&](const Vec2& q) {  // clamped before the conversion; NaN goes to cell 0
    const double u = (q.x() - lo.x()) / cx, v = (q.y() - lo.y()) / cy;
    const int i = u >= 0 ? static_cast<int>(std::min(u, gx - 1.0)) : 0;
    const int j = v >= 0 ? static_cast<int>(std::min(v, gy - 1.0)) : 0;
    return std::array<int, 2>{i, j};
  };
  // ends by cell (CSR); an end is 2 * stroke + which
  std::vector<std::uint32_t> start_of(static_cast<std::size_t>(gx) * gy + 1, 0), items(2 * n);
  for (std::size_t e = 0; e < 2 * n; ++e) {
    const auto [i, j] = cell_of(ends[e / 2][e % 2]);
    ++start_of[static_cast<std::size_t>(j) * gx + i + 1];
  }
  for (std::size_t c = 1; c < start_of.size(); ++c) start_of[c] += start_of[c - 1];
  {
    std::vector<std::uint32_t> fill(start_of.begin(), start_of.end() - 1);
    for (std::size_t e = 0; e < 2 * n; ++e) {  // ascending within each cell
      const auto [i, j] = cell_of(ends[e / 2][e % 2]);
      items[fill[static_cast<std::size_t>(j) * gx + i]++] = static_cast<std::uint32_t>(e);
    }
  }
  constexpr int kBlock = 8;
  const int bx = (gx + kBlock - 1) / kBlock, by = (gy + kBlock - 1) / kBlock;
  std::vector<std::uint32_t> live_in_block(static_cast<std::size_t>(bx) * by, 0);
  for (int j = 0; j < gy; ++j)
    for (int i = 0; i < gx; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * gx + i;
      live_in_block[static_cast<std::size_t>(j / kBlock) * bx + i / kBlock] += start_of[c + 1] - start_of[c];
    }
  std::vector<char> drawn(n, 0);

  Vec2 pen = start;
  for (std::size_t k = 0; k < n; ++k) {
    // the best end so far: (squared distance, stroke, which end), compared as a tuple
    std::tuple<double, std::size_t, int> best{std::numeric_limits<double>::infinity(), n, 0};
    // distance from the pen to the box of blocks [b0, b1] x [c0, c1] (in block coordinates)
    auto block_gap2 = [&](int bi, int bj) {
      const double x0 = lo.x() + bi * kBlock * cx, x1 = x0 + kBlock * cx;
      const double y0 = lo.y() + bj * kBlock * cy, y1 = y0 + kBlock * cy;
      const double dx = std::max({x0 - pen.x(), 0.0, pen.x() - x1}), dy = std::max({y0 - pen.y(), 0.0, pen.y() - y1});
      return dx * dx + dy * dy;
    };
    auto scan_block = [&](int bi, int bj) {
      for (int j = bj * kBlock; j < std::min(gy, (bj + 1) * kBlock); ++j)
        for (int i = bi * kBlock; i < std::min(gx, (bi + 1) * kBlock); ++i) {
          const std::size_t c = static_cast<std::size_t>(j) * gx + i;
          for (std::uint32_t at = start_of[c]; at < start_of[c + 1]; ++at) {
            const std::uint32_t e = items[at];
            if (drawn[e / 2]) continue;
            const double d2 = (ends[e / 2][e % 2] - pen).squaredNorm();
            best = std::min(best, std::tuple<double, std::size_t, int>{d2, e / 2, static_cast<int>(e % 2)});
          }
        }
    };
    // rings of blocks around the pen's block, outward, until a ring lies wholly beyond the best
    const auto [pi, pj] = cell_of(pen);
    const int pbi = pi / kBlock, pbj = pj / kBlock;
    for (int r = 0;; ++r) {
      // the blocks at Chebyshev distance r from the pen's block, within the grid: the rows above and
      // below in full, the columns left and right between them
      bool any_in_grid = false, any_near = false;
      auto visit = [&](int bi, int bj) {
        any_in_grid = true;
        if (block_gap2(bi, bj) > std::get<0>(best)) return;
        any_near = true;
        if (live_in_block[static_cast<std::size_t>(bj) * bx + bi] > 0) scan_block(bi, bj);
      };
      const int i0 = std::max(pbi - r, 0), i1 = std::min(pbi + r, bx - 1);
      const int j0 = std::max(pbj - r + 1, 0), j1 = std::min(pbj + r - 1, by - 1);
      for (const int bj : {pbj - r, pbj + r}) {
        if (bj < 0 || bj >= by || (r == 0 && bj != pbj)) continue;
        for (int bi = i0; bi <= i1; ++bi) visit(bi, bj);
        if (r == 0) break;
      }
      for (const int bi : {pbi - r, pbi + r}) {
        if (r == 0 || bi < 0 || bi >= bx) continue;
        for (int bj = j0; bj <= j1; ++bj) visit(bi, bj);
      }
      if (!any_in_grid || (!any_near && std::get<1>(best) < n)) break;
    }
    if (std::get<1>(best) == n)  // only strokes with an end that is not a number are left: in index order
      best = {0.0, static_cast<std::size_t>(std::find(drawn.begin(), drawn.end(), 0) - drawn.begin()), 0};
    const auto [d2, s, which] = best;
    (void)d2;
    drawn[s] = 1;
    for (int w = 0; w < 2; ++w) {
      const auto [i, j] = cell_of(ends[s][w]);
      --live_in_block[static_cast<std::size_t>(j / kBlock) * bx + i / kBlock];
    }
    order.push_back({s, which == 1});
    pen = ends[s][1 - which];
  }
  return order;
}

}  // namespace cellform::venation
