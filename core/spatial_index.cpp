// Hashed uniform grid: counting-sort build, expanding-shell exact kNN.
#include "core/spatial_index.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "core/errors.h"

namespace cellform::core {

namespace {

// Keeps the k best (d2, index) pairs in ascending order; k is small (<= 32 in practice).
struct TopK {
  Index* idx;
  double* d2;
  int k;
  int n = 0;

  double worst() const { return n < k ? INFINITY : d2[n - 1]; }

  void offer(Index i, double d) {
    if (n == k && (d > d2[n - 1] || (d == d2[n - 1] && i >= idx[n - 1]))) return;
    for (int j = 0; j < n; ++j)
      if (idx[j] == i) return;  // hashed buckets may be visited twice
    int pos = n < k ? n++ : k - 1;
    while (pos > 0 && (d2[pos - 1] > d || (d2[pos - 1] == d && idx[pos - 1] > i))) {
      d2[pos] = d2[pos - 1];
      idx[pos] = idx[pos - 1];
      --pos;
    }
    d2[pos] = d;
    idx[pos] = i;
  }
};

constexpr long kMaxShell = 12;  // beyond this many grid cells, scanning everything is cheaper

std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

}  // namespace

long PointGrid::coord(double v) const {
  // clamp so that huge, infinite or NaN coordinates cannot overflow the conversion (undefined behaviour)
  constexpr double kLimit = 1e15;
  const double c = std::floor(v * inv_cell_);
  if (!(c > -kLimit)) return static_cast<long>(-kLimit);
  if (!(c < kLimit)) return static_cast<long>(kLimit);
  return static_cast<long>(c);
}

std::size_t PointGrid::bucket_of(long ix, long iy, long iz) const {
  const auto h = static_cast<std::uint64_t>(ix) * 73856093ull ^ static_cast<std::uint64_t>(iy) * 19349663ull ^
                 static_cast<std::uint64_t>(iz) * 83492791ull;
  return static_cast<std::size_t>(h) & mask_;
}

void PointGrid::build(std::span<const Vec3> points, double cell_size) {
  if (!(cell_size > 0) || !std::isfinite(cell_size))
    throw InvalidInput("spatial grid cell size must be positive and finite, got " + std::to_string(cell_size));
  points_ = points;
  cell_size_ = cell_size;
  inv_cell_ = 1.0 / cell_size;
  std::size_t buckets = 16;
  while (buckets < 2 * points.size()) buckets *= 2;
  mask_ = buckets - 1;
  start_.assign(buckets + 1, 0);
  std::vector<Index> bucket(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    bucket[i] = static_cast<Index>(bucket_of(coord(p.x()), coord(p.y()), coord(p.z())));
    ++start_[bucket[i] + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  order_.resize(points.size());
  std::vector<Index> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i) order_[fill[bucket[i]]++] = static_cast<Index>(i);
}

int PointGrid::nearest(const Vec3& q, Index self, int k, Index* out, double* out_d2) const {
  TopK top{out, out_d2, k};
  if (k <= 0) return 0;
  const long cx = coord(q.x()), cy = coord(q.y()), cz = coord(q.z());
  auto scan_cell = [&](long ix, long iy, long iz) {
    const std::size_t b = bucket_of(ix, iy, iz);
    for (Index s = start_[b]; s < start_[b + 1]; ++s) {
      const Index i = order_[s];
      if (i == self) continue;
      top.offer(i, (points_[i] - q).squaredNorm());
    }
  };
  for (long s = 0;; ++s) {
    if (s > kMaxShell) {  // sparse outlier: finish by brute force
      for (std::size_t i = 0; i < points_.size(); ++i)
        if (static_cast<Index>(i) != self) top.offer(static_cast<Index>(i), (points_[i] - q).squaredNorm());
      return top.n;
    }
    // visit the shell of cells at Chebyshev distance exactly s from the centre cell
    for (long dx = -s; dx <= s; ++dx)
      for (long dy = -s; dy <= s; ++dy) {
        const bool edge = std::abs(dx) == s || std::abs(dy) == s;
        if (edge) {
          for (long dz = -s; dz <= s; ++dz) scan_cell(cx + dx, cy + dy, cz + dz);
        } else {
          scan_cell(cx + dx, cy + dy, cz - s);
          if (s > 0) scan_cell(cx + dx, cy + dy, cz + s);
        }
      }
    // every point within s * cell_size of q lies in the scanned cube
    const double covered = static_cast<double>(s) * cell_size_;
    const std::size_t available = points_.size() - (self < points_.size() ? 1 : 0);
    if (top.n == k && top.worst() <= covered * covered) return top.n;
    if (static_cast<std::size_t>(top.n) == available && available < static_cast<std::size_t>(k)) {
      // all points may already be found, but only a full scan proves it; finish by brute force
      for (std::size_t i = 0; i < points_.size(); ++i)
        if (static_cast<Index>(i) != self) top.offer(static_cast<Index>(i), (points_[i] - q).squaredNorm());
      return top.n;
    }
  }
}

void PointGrid::within(const Vec3& q, double radius, Index self, std::vector<Index>& out) const {
  const double r2 = radius * radius;
  const long lo[3] = {coord(q.x() - radius), coord(q.y() - radius), coord(q.z() - radius)};
  const long hi[3] = {coord(q.x() + radius), coord(q.y() + radius), coord(q.z() + radius)};
  const std::size_t start = out.size();
  // cell count in double: the product of three long extents can overflow for a huge radius
  const double cells = static_cast<double>(hi[0] - lo[0] + 1) * static_cast<double>(hi[1] - lo[1] + 1) *
                       static_cast<double>(hi[2] - lo[2] + 1);
  if (!(cells <= static_cast<double>(start_.size()))) {
    for (std::size_t i = 0; i < points_.size(); ++i)
      if (static_cast<Index>(i) != self && (points_[i] - q).squaredNorm() <= r2) out.push_back(static_cast<Index>(i));
    return;
  }
  for (long ix = lo[0]; ix <= hi[0]; ++ix)
    for (long iy = lo[1]; iy <= hi[1]; ++iy)
      for (long iz = lo[2]; iz <= hi[2]; ++iz) {
        const std::size_t b = bucket_of(ix, iy, iz);
        for (Index s = start_[b]; s < start_[b + 1]; ++s) {
          const Index i = order_[s];
          if (i == self || (points_[i] - q).squaredNorm() > r2) continue;
          if (std::find(out.begin() + static_cast<long>(start), out.end(), i) == out.end()) out.push_back(i);
        }
      }
}

int PointGrid::count_within(const Vec3& q, double radius, Index self) const {
  thread_local std::vector<Index> scratch;
  scratch.clear();
  within(q, radius, self, scratch);
  return static_cast<int>(scratch.size());
}

std::vector<Index> spatial_order(std::span<const Vec3> points, double cell_size) {
  if (points.empty()) return {};
  Vec3 lo = points[0];
  for (const Vec3& p : points) lo = lo.cwiseMin(p);
  std::vector<std::uint64_t> key(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 c = ((points[i] - lo) / cell_size).array().floor();
    key[i] = spread_bits(static_cast<std::uint64_t>(c.x())) | spread_bits(static_cast<std::uint64_t>(c.y())) << 1 |
             spread_bits(static_cast<std::uint64_t>(c.z())) << 2;
  }
  std::vector<Index> perm(points.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::stable_sort(perm.begin(), perm.end(), [&](Index a, Index b) { return key[a] < key[b]; });
  return perm;
}

}  // namespace cellform::core
