// The witness grid of the dart b_v test.
#include "venation/dart_grid.h"

#include <algorithm>
#include <cmath>

namespace cellform::venation {

using core::Index;
using core::kNoIndex;
using core::Vec3;

void WitnessGrid::reset(const Vec3& lo, const Vec3& hi, double cell, std::size_t max_cells) {
  const double wx = std::max(hi.x() - lo.x(), 0.0), wy = std::max(hi.y() - lo.y(), 0.0);
  if (!std::isfinite(wx) || !std::isfinite(wy) || !(cell > 0) || !std::isfinite(cell)) {
    clear();  // no grid: every dart goes to the exact test
    return;
  }
  cell_ = cell;
  // coarsen until the grid fits (counted in double: a tiny cell must not overflow a long); +1: the box edges
  const double budget = static_cast<double>(std::max<std::size_t>(max_cells, 1));
  double fx = std::floor(wx / cell_) + 1, fy = std::floor(wy / cell_) + 1;
  while (!(fx * fy <= budget)) {
    cell_ = std::max(cell_ * 1.25, std::sqrt(wx * wy / budget));  // big jumps when far too fine
    fx = std::floor(wx / cell_) + 1;
    fy = std::floor(wy / cell_) + 1;
  }
  nx_ = static_cast<long>(fx);
  ny_ = static_cast<long>(fy);
  inv_ = 1 / cell_;
  lo_ = lo;
  hi_ = hi;
  cells_.assign(static_cast<std::size_t>(nx_ * ny_), kNoIndex);
}

void WitnessGrid::clear() {
  cells_.clear();
  cells_.shrink_to_fit();
  nx_ = ny_ = 0;
}

bool WitnessGrid::covers(const Vec3& lo, const Vec3& hi) const {
  return !cells_.empty() && lo.x() >= lo_.x() && lo.y() >= lo_.y() && hi.x() <= hi_.x() && hi.y() <= hi_.y();
}

void WitnessGrid::insert(Index i, const Vec3& p) {
  if (cells_.empty() || p.z() != 0) return;
  const double fx = (p.x() - lo_.x()) * inv_, fy = (p.y() - lo_.y()) * inv_;
  if (!(fx >= 0 && fy >= 0 && fx < static_cast<double>(nx_) && fy < static_cast<double>(ny_))) return;
  Index& c = cells_[static_cast<std::size_t>(static_cast<long>(fy) * nx_ + static_cast<long>(fx))];
  if (c == kNoIndex) c = i;
}

bool WitnessGrid::witness(const Vec3& q, double r2, const std::vector<Vec3>& points) const {
  if (cells_.empty()) return false;
  const double fx = (q.x() - lo_.x()) * inv_, fy = (q.y() - lo_.y()) * inv_;
  if (!(fx >= -1 && fy >= -1 && fx < static_cast<double>(nx_ + 1) && fy < static_cast<double>(ny_ + 1))) return false;
  const long x = static_cast<long>(std::floor(fx)), y = static_cast<long>(std::floor(fy));
  auto test = [&](long cx, long cy) {
    if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) return false;
    const Index u = cells_[static_cast<std::size_t>(cy * nx_ + cx)];
    return u != kNoIndex && (points[u] - q).squaredNorm() <= r2;
  };
  if (test(x, y)) return true;  // own cell first: covered whenever the cell is at most r / sqrt 2
  for (long dy = -1; dy <= 1; ++dy)
    for (long dx = -1; dx <= 1; ++dx)
      if ((dx != 0 || dy != 0) && test(x + dx, y + dy)) return true;
  return false;
}

}  // namespace cellform::venation
