// Exact k-nearest and radius queries on a point set through a hashed uniform grid.
#pragma once

#include <span>
#include <vector>

#include "core/types.h"

namespace cellform::core {

/// A uniform grid hashed into a table of about two buckets per point. Rebuilding costs O(n)
/// (a counting sort), so it can be rebuilt every step of a simulation. Queries are exact:
/// results equal a brute-force scan, with distance ties broken by the smaller index.
class PointGrid {
 public:
  /// Indexes `points` (kept by reference: they must outlive the queries) with grid cells of
  /// `cell_size` model units; about the typical neighbour distance is best. Throws InvalidInput
  /// for a cell size that is not positive and finite.
  void build(std::span<const Vec3> points, double cell_size);

  /// The up-to-k points nearest to `query`, skipping index `self` (kNoIndex to skip none), sorted by
  /// distance then index. Writes indices to `out` and squared distances to `out_d2` (both size >= k)
  /// and returns how many were found (fewer than k only when the set has fewer points).
  int nearest(const Vec3& query, Index self, int k, Index* out, double* out_d2) const;

  /// nearest() for every indexed point, excluding the point itself: row i of `out` (k entries) holds the
  /// k nearest of point i, padded with kNoIndex. Same results as calling nearest() per point, but the
  /// candidates of a grid cell are gathered once for all points in it. Uses up to `threads` threads
  /// (0 = all); each row is written by one thread only, so the result does not depend on the count.
  void nearest_all(int k, Index* out, int threads) const;

  /// Number of points within `radius` of `query` (distance <= radius), not counting `self`.
  int count_within(const Vec3& query, double radius, Index self) const;

  /// Appends to `out` every point within `radius` of `query` (unsorted), not counting `self`.
  void within(const Vec3& query, double radius, Index self, std::vector<Index>& out) const;

  std::size_t size() const { return points_.size(); }
  double cell_size() const { return cell_size_; }

 private:
  std::size_t bucket_of(long ix, long iy, long iz) const;
  long coord(double v) const;

  std::span<const Vec3> points_;
  double cell_size_ = 1.0;
  double inv_cell_ = 1.0;
  std::size_t mask_ = 0;
  std::vector<Index> start_;  // bucket -> first slot in order_
  std::vector<Index> order_;  // point indices grouped by bucket
};

/// A permutation that sorts points along a Z-order (Morton) curve of grid cells of `cell_size`;
/// storing data in this order keeps neighbours close in memory. perm[new] = old.
std::vector<Index> spatial_order(std::span<const Vec3> points, double cell_size);

}  // namespace cellform::core
