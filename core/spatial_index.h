// Exact k-nearest and radius queries on a point set through a hashed uniform grid.
#pragma once

#include <limits>
#include <span>
#include <vector>

#include "core/types.h"

namespace cellform::core {

/// A uniform grid: dense (one bucket per grid cell of the bounding box, rows along x contiguous) when
/// the box has at most about eight grid cells per point, otherwise hashed into about four buckets per
/// point. Rebuilding costs O(n) (a counting sort), so it can be rebuilt every step of a simulation.
/// Queries are exact: results equal a brute-force scan, with distance ties broken by the smaller index.
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

  /// nearest_all() with a hint: row i of `hint` (k entries, may be the same memory as `out`) names k
  /// points, e.g. last step's neighbours of point i. Their distances bound the search radius, so a
  /// good hint makes the search much cheaper; a stale or invalid hint (repeats, kNoIndex, i itself)
  /// only costs time, never changes the result.
  void nearest_all(int k, Index* out, int threads, const Index* hint) const;

  /// Number of points within `radius` of `query` (distance <= radius), not counting `self`; the count
  /// stops at `limit` (so a wide radius costs only until `limit` points are found).
  int count_within(const Vec3& query, double radius, Index self, int limit = std::numeric_limits<int>::max()) const;

  /// Appends to `out` every point within `radius` of `query` (unsorted), not counting `self`.
  void within(const Vec3& query, double radius, Index self, std::vector<Index>& out) const;

  std::size_t size() const { return points_.size(); }
  double cell_size() const { return cell_size_; }
  /// True if the last build() chose the dense layout (small bounding box, all points finite).
  bool dense() const { return dense_; }

 private:
  std::size_t bucket_of(long ix, long iy, long iz) const;
  template <class Visit>
  void for_each_within(const Vec3& query, double radius, Index self, Visit&& visit) const;
  long coord(double v) const;
  void nearest_all_hashed(int k, Index* out, int threads) const;
  void nearest_all_dense(int k, Index* out, int threads, const Index* hint) const;

  std::span<const Vec3> points_;
  double cell_size_ = 1.0;
  double inv_cell_ = 1.0;
  std::size_t mask_ = 0;
  std::vector<Index> start_;  // bucket -> first slot in order_
  std::vector<Index> order_;  // point indices grouped by bucket
  // dense layout: bucket = ((z - lo_z) * dim_y + (y - lo_y)) * dim_x + (x - lo_x); one empty bucket past
  // the box answers every coordinate outside it
  bool dense_ = false;
  long lo_[3] = {0, 0, 0};
  long dim_[3] = {0, 0, 0};
  std::size_t outside_ = 0;
  // dense layout: coordinates of points_[order_[s]] by slot s, so row scans read memory in order (and vectorise)
  std::vector<double> slot_x_, slot_y_, slot_z_;
  std::vector<Index> bucket_;  // build scratch, kept to avoid reallocating every step
};

/// A permutation that sorts points along a Z-order (Morton) curve of grid cells of `cell_size`;
/// storing data in this order keeps neighbours close in memory. perm[new] = old.
std::vector<Index> spatial_order(std::span<const Vec3> points, double cell_size);

}  // namespace cellform::core
