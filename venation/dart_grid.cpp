// The witness grid of the dart b_v test.
#include "venation/dart_grid.h"

#include <algorithm>
#include <cmath>

namespace cellform::venation {

using core::Index;
using core::kNoIndex;
using core::Vec3;

namespace {
constexpr long kSub = 2;  // the map of covered cells has kSub x kSub cells to a cell of the grid
}  // namespace

void WitnessGrid::reset(const Vec3& lo, const Vec3& hi, double cell, std::size_t max_cells, double cover) {
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
  occupied_.assign((cells_.size() + 63) / 64, 0);
  // a point's cell is floor((x - lo) / cell): off by at most about 1e-16 of the coordinates in cells
  const double reach = std::max({std::abs(lo.x()), std::abs(lo.y()), std::abs(hi.x()), std::abs(hi.y())});
  fine_ = reach < 1e6 * cell_;
  cover_ = fine_ && cover > 0 && std::isfinite(cover) && cover <= 4 * cell_ ? cover : 0;  // (49 cells a node at 1.43)
  covered_.assign(cover_ > 0 ? (static_cast<std::size_t>(nx_ * ny_) * kSub * kSub + 63) / 64 : 0, 0);
}

void WitnessGrid::clear() {
  cells_.clear();
  cells_.shrink_to_fit();
  occupied_.clear();
  occupied_.shrink_to_fit();
  covered_.clear();
  covered_.shrink_to_fit();
  cover_ = 0;
  nx_ = ny_ = 0;
}

bool WitnessGrid::covers(const Vec3& lo, const Vec3& hi) const {
  return !cells_.empty() && lo.x() >= lo_.x() && lo.y() >= lo_.y() && hi.x() <= hi_.x() && hi.y() <= hi_.y();
}

void WitnessGrid::insert(Index i, const Vec3& p) {
  if (cells_.empty() || p.z() != 0) return;
  const double fx = (p.x() - lo_.x()) * inv_, fy = (p.y() - lo_.y()) * inv_;
  if (!(fx >= 0 && fy >= 0 && fx < static_cast<double>(nx_) && fy < static_cast<double>(ny_))) return;
  const auto at = static_cast<std::size_t>(static_cast<long>(fy) * nx_ + static_cast<long>(fx));
  if (cells_[at] == kNoIndex) {
    cells_[at] = i;
    occupied_[at >> 6] |= std::uint64_t{1} << (at & 63);
  }
  if (cover_ == 0) return;
  // the cells whose farthest corner is within cover of p (a disc holds a square with its corners), less
  // 1e-6 of it: far beyond the rounding of the corners, of a point's cell (fine_) and of a squared distance
  const double c2 = cover_ * cover_ * (1 - 1e-6);
  const double sub = cell_ / kSub, inv = inv_ * kSub;
  const long sx = nx_ * kSub, sy = ny_ * kSub;
  const long x0 = std::max(0L, static_cast<long>(std::floor((p.x() - cover_ - lo_.x()) * inv)));
  const long x1 = std::min(sx - 1, static_cast<long>(std::floor((p.x() + cover_ - lo_.x()) * inv)));
  const long y0 = std::max(0L, static_cast<long>(std::floor((p.y() - cover_ - lo_.y()) * inv)));
  const long y1 = std::min(sy - 1, static_cast<long>(std::floor((p.y() + cover_ - lo_.y()) * inv)));
  for (long y = y0; y <= y1; ++y) {
    const double ya = lo_.y() + static_cast<double>(y) * sub - p.y(), yb = ya + sub;
    const double dy2 = std::max(ya * ya, yb * yb);
    if (dy2 > c2) continue;
    for (long x = x0; x <= x1; ++x) {
      const double xa = lo_.x() + static_cast<double>(x) * sub - p.x(), xb = xa + sub;
      if (dy2 + std::max(xa * xa, xb * xb) > c2) continue;
      const auto k = static_cast<std::size_t>(y * sx + x);
      covered_[k >> 6] |= std::uint64_t{1} << (k & 63);
    }
  }
}

bool WitnessGrid::covers_radius(double r2) const {
  // (a covered cell lies within cover (1 - 5e-7) of its node; r2 may round a little below cover^2)
  return cover_ > 0 && !cells_.empty() && cover_ * cover_ * (1 - 1e-7) <= r2;
}

bool WitnessGrid::witness(const Vec3& q, double r2, const std::vector<Vec3>& points) const {
  if (cells_.empty()) return false;
  const double fx = (q.x() - lo_.x()) * inv_, fy = (q.y() - lo_.y()) * inv_;
  if (!(fx >= -1 && fy >= -1 && fx < static_cast<double>(nx_ + 1) && fy < static_cast<double>(ny_ + 1))) return false;
  const long x = static_cast<long>(std::floor(fx)), y = static_cast<long>(std::floor(fy));
  // the map of occupied cells before the nodes: it is 32 times smaller than cells_
  auto occupied = [&](long cx, long cy) {
    if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) return false;
    const auto at = static_cast<std::size_t>(cy * nx_ + cx);
    return (occupied_[at >> 6] >> (at & 63) & 1) != 0;
  };
  auto test = [&](long cx, long cy) {
    if (!occupied(cx, cy)) return false;
    const Index u = cells_[static_cast<std::size_t>(cy * nx_ + cx)];
    return (points[u] - q).squaredNorm() <= r2;
  };
  if (q.z() == 0 && covers_radius(r2) && x >= 0 && y >= 0 && x < nx_ && y < ny_) {
    const long u = std::min(nx_ * kSub - 1, std::max(0L, static_cast<long>(fx * kSub)));
    const long v = std::min(ny_ * kSub - 1, std::max(0L, static_cast<long>(fy * kSub)));
    const auto at = static_cast<std::size_t>(v * nx_ * kSub + u);
    if (covered_[at >> 6] >> (at & 63) & 1) return true;
  }
  if (test(x, y)) return true;  // own cell first: covered whenever the cell is at most r / sqrt 2
  for (long dy = -1; dy <= 1; ++dy)
    for (long dx = -1; dx <= 1; ++dx)
      if ((dx != 0 || dy != 0) && test(x + dx, y + dy)) return true;
  return false;
}

}  // namespace cellform::venation
