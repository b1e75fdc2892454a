// Incremental k-d tree over vein nodes: nearest, radius, relative (Eq. 2) and Delaunay neighbourhoods.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/types.h"

namespace cellform::venation {

using core::Index;
using core::kNoIndex;
using core::Vec3;

namespace detail {
struct Lune;  // a lune query (point_tree.cpp)
}

/// The Voronoi cell of a site s in the plane z = 0 among points added by clipping, inside a window
/// square around s: a convex polygon whose edges are labelled with the point whose bisector made them.
/// Points never move, so a cell once computed is kept up to date by clipping it with the points added
/// since; only points within 2 sqrt(r2max) of s can change it.
struct VoronoiCell {
  struct Vertex {
    double x, y;
    std::int64_t label;  ///< the point whose bisector is the edge leaving this vertex; -1 = the window
  };
  std::vector<Vertex> poly;
  double r2max = 0;  ///< squared distance from s to the farthest vertex (model units squared)
  /// The window square of half side `half_extent` (model units) around s.
  void reset(const Vec3& s, double half_extent);
  /// Clips the cell by the half-plane closer to s than to u (label `label`). True if the cell shrank.
  /// `scratch` avoids allocation between calls.
  bool clip(const Vec3& s, const Vec3& u, Index label, std::vector<Vertex>& scratch);
  /// The labels of the edges longer than `tiny`: the Delaunay neighbours of s. Sorted by index.
  void neighbours(double tiny, std::vector<Index>& out) const;
};

/// A k-d tree that only grows: points are appended (index = insertion order) and never move, so the
/// index is updated in O(log^2 n) amortised per vein node instead of being rebuilt every step. Leaves
/// hold up to 16 points and split at the middle of their widest extent; every node keeps the tight box
/// of its points; a subtree whose one child holds over 3/4 of its points is rebuilt with median splits
/// (scapegoat rule), since veins add points in a moving front that would otherwise grow a chain.
/// Works in 3-D; 2-D input simply has z = 0. All queries are exact and break distance ties by index.
///
/// nanoflann (Debian libnanoflann-dev) was considered: its dynamic index answers k-nearest and radius
/// queries, but the relative-neighbourhood query below needs a best-first traversal with cone pruning
/// that nanoflann does not expose.
class PointTree {
 public:
  /// Appends `p` and returns its index.
  Index insert(const Vec3& p);
  /// Appends `points` (indices size(), size() + 1, ... in order), the same as inserting them one by one
  /// but faster: they enter the tree along a Morton curve, so that consecutive insertions descend
  /// through the same, cached, nodes. Query answers do not depend on insertion order (ties go by index);
  /// the tree's shape does, and with it which boxes a sector search skips.
  void insert_batch(std::span<const Vec3> points);
  /// Replaces the content by `points` in one balanced build (median splits), O(n log n).
  void assign(std::span<const Vec3> points);
  /// Removes every point.
  void clear();

  std::size_t size() const { return points_.size(); }
  const std::vector<Vec3>& points() const { return points_; }
  const Vec3& point(Index i) const { return points_[i]; }

  /// The nearest point to `q` (ties: smaller index). Start from a known candidate (`best`, `best_d2`)
  /// to prune: with last step's nearest point as the candidate only newer points are examined.
  /// Returns false if the tree is empty and no candidate was given.
  bool nearest(const Vec3& q, Index& best, double& best_d2) const;

  /// True if a point other than `exclude` lies at squared distance <= r2 from `q`.
  bool any_within(const Vec3& q, double r2, Index exclude = kNoIndex) const;

  /// Appends every point at squared distance <= r2 from `q` to `out` (unsorted).
  void within(const Vec3& q, double r2, std::vector<Index>& out) const;

  /// True if some point u other than `v` lies in the closed lune of `s` and `v`: |u - s| <= |v - s| and
  /// |u - v| <= |v - s|, i.e. u excludes v from the relative neighbourhood of s (Eq. 2 of Runions et al.
  /// 2005 is violated).
  bool lune_occupied(const Vec3& s, Index v) const;

  /// The relative neighbourhood V(s) of a query point s among the tree's points (Eq. 2 of Runions et
  /// al. 2005, evaluated exactly, in 2-D or 3-D): v is in V(s) iff for every other point u,
  /// |v - s| < max(|u - s|, |v - u|). Every candidate is confirmed with lune_occupied(). In the plane
  /// (all points and s with one z) the candidates are the nearest points of six fixed 60-degree sectors
  /// around s (a relative neighbour is the nearest point of its sector). In 3-D points are visited in
  /// order of distance from s and a subtree is skipped when every point in it lies behind a visited
  /// point u within 60 degrees of the direction of u (u excludes them all). Result sorted by index.
  /// `scratch` avoids allocation between calls.
  struct Scratch {
    std::vector<std::pair<double, std::int64_t>> heap;  // (squared distance, node id or ~point id)
    std::vector<Index> found;
    std::vector<double> found_d2;
    std::vector<Vec3> corner_dir;
  };
  void relative_neighbourhood(const Vec3& s, std::vector<Index>& out, Scratch& scratch) const;

  /// Planar sector of a direction (dx, dy): k such that its angle lies in [60 k, 60 (k + 1)) degrees
  /// (exact comparisons, no trigonometry); the zero vector is in sector 0.
  static int sector(double dx, double dy);

  /// In the plane z = s.z: the nearest point of each of the six sectors around s (ties: smaller index),
  /// kNoIndex and infinity for empty sectors, except that a box whose every point another best already
  /// excludes from V(s) (Eq. 2) is skipped: a sector may then keep a farther point, which depends on the
  /// tree's shape. The relative neighbourhood is the subset of these whose lune is empty, whatever the
  /// shape; keeping them per source lets new points be merged in without a new search.
  /// With reset = false the arrays hold bests from elsewhere (positions in `best_pos`) that this tree's
  /// points must beat; indices written are this tree's plus `offset`.
  void sector_nearest(const Vec3& s, Index* best, double* best_d2, Scratch& scratch, bool reset = true,
                      const Vec3* best_pos = nullptr, Index offset = 0) const;

  /// True if a point lies in the closed lune of s and the position v (both distances <= |v - s|).
  bool any_in_lune(const Vec3& s, const Vec3& v) const;

  /// True if every point v other than point n has |v - s| - |v - n| >= t (model units): every other
  /// point is on n's side of the bisector of s and n by that margin. When t > 0 and n is the nearest
  /// point to s, n excludes every other point from the relative neighbourhood of s (Eq. 2); since
  /// |v - n| grows by at most |n - n'| when n moves to n', and a point placed D from its parent changes
  /// both distances by at most D, the margin bounds how long that stays true. Branch and bound over
  /// boxes, ending at the first point below t.
  bool margin_at_least(const Vec3& s, Index n, double t) const;

  /// The Delaunay neighbourhood of a query point s among the tree's points in the plane z = 0: the
  /// points whose Voronoi cells share an edge with the cell of s in the Voronoi diagram of the points
  /// and s. Computed by clipping a square of `half_extent` around s with bisectors in order of
  /// distance (neighbours whose Voronoi edge lies wholly outside that square are missed, so pass a
  /// square that covers the domain generously). Points coinciding with s are ignored. Sorted by index.
  /// `max_points` limits the clipping to that many nearest points (an approximation when it binds).
  void delaunay_neighbourhood(const Vec3& s, double half_extent, std::vector<Index>& out, Scratch& scratch,
                              std::size_t max_points = static_cast<std::size_t>(-1)) const;

  /// Urquhart's approximation of V(s) (Section 5.2 of Runions et al. 2005): the Delaunay neighbours of s
  /// tested with Eq. 2 only against each other, not against every point. A superset of the exact
  /// relative neighbourhood, a subset of the Delaunay neighbourhood. 2-D (z = 0) only.
  void urquhart_neighbourhood(const Vec3& s, double half_extent, std::vector<Index>& out, Scratch& scratch,
                              std::size_t max_points = static_cast<std::size_t>(-1)) const;

  /// The cell behind delaunay_neighbourhood(): s's Voronoi cell clipped from the window square by the
  /// points in order of distance (at most `max_points` of them), to keep and clip further later.
  void voronoi_cell(const Vec3& s, double half_extent, VoronoiCell& cell, Scratch& scratch,
                    std::size_t max_points = static_cast<std::size_t>(-1)) const;

  /// The Urquhart step on Delaunay neighbours `dn` of s (sorted): drops each v that another member u
  /// excludes by Eq. 2 (|u - s| <= |v - s| and |u - v| <= |v - s|). Sorted by index.
  void urquhart_filter(const Vec3& s, const std::vector<Index>& dn, std::vector<Index>& out) const;

 private:
  struct Node {
    Vec3 lo, hi;  // tight box of the points below
    int child[2] = {-1, -1};
    int dim = 0;
    double split = 0;
    std::vector<Index> pts;   // leaves only
    std::uint32_t count = 0;  // points below
  };
  void index(Index id);  // inserts the appended point id into the tree
  void split_leaf(int n);
  void rebuild(int n);
  void collect(int n, std::vector<Index>& out);
  void build(int n, Index* first, Index* last);
  bool nearest_rec(int n, const Vec3& q, Index& best, double& best_d2) const;
  bool any_within_rec(int n, const Vec3& q, double r2, Index exclude) const;
  bool lune_rec(int n, const detail::Lune& l, Index v) const;  // v: the point excluded from the test, or kNoIndex
  bool margin_rec(int n, const Vec3& s, Index c, const Vec3& pc, double t) const;
  void relative_neighbourhood_planar(const Vec3& s, std::vector<Index>& out, Scratch& scratch) const;
  double mindist2(const Node& nd, const Vec3& q) const;
  /// Best-first search step: pushes a leaf's points (as ~index) or an inner node's children onto a min-heap.
  void expand(const Node& nd, const Vec3& s, std::vector<std::pair<double, std::int64_t>>& heap) const;

  static constexpr int kBucket = 16;
  std::vector<Vec3> points_;
  std::vector<Node> nodes_;
  std::size_t garbage_ = 0;  // nodes orphaned by rebuilds; compacted when they are half the array
  std::vector<int> path_;
  std::vector<Index> scratch_ids_;
};

/// A static set of points numbered from an offset, queried by many points in a row: the vein nodes added
/// in one step, against which every source updates what it knows (its nearest node, its six sector bests,
/// its lunes). A k-d tree built once with median splits whose leaves (up to 16 points) are stored
/// contiguously; every query is exact, gives the same squared distances (bit for bit) as PointTree, and
/// breaks distance ties by index.
class PointBatch {
 public:
  /// Replaces the content by `points`, numbered offset, offset + 1, ...
  void assign(std::span<const Vec3> points, Index offset);
  std::size_t size() const { return id_.size(); }

  /// As PointTree::nearest: improves the candidate (best, best_d2) if a point is nearer (ties: smaller index).
  /// With `tie`, also says whether a point other than the final best is exactly as near (the candidate
  /// given is assumed to have no tie among points outside this batch).
  void nearest(const Vec3& q, Index& best, double& best_d2, bool* tie = nullptr) const;
  /// True if a point lies at squared distance <= r2 from q.
  bool any_within(const Vec3& q, double r2) const;
  /// Appends (squared distance from s, index) of every point that can clip `cell`, the Voronoi cell of
  /// s: those nearer to some vertex of the cell than s is (or as near). Unsorted.
  void clippers(const Vec3& s, const VoronoiCell& cell, std::vector<std::pair<double, Index>>& out) const;
  /// True if a point lies in the closed lune of s and the position v (both distances <= |v - s|).
  bool any_in_lune(const Vec3& s, const Vec3& v) const;
  /// Merges the points into the six sector bests of s (PointTree::sector_nearest's arrays, kNoIndex and
  /// infinity for an empty sector): a point replaces the best of its sector if nearer (ties: smaller
  /// index). A box is skipped when no sector it can reach has a best as far as the box.
  /// With `ties`, bit k is set when another point of the batch is exactly as near as the final best of
  /// sector k (a best from outside the batch is assumed to have no such tie outside it).
  void sector_merge(const Vec3& s, Index* best, double* best_d2, unsigned* ties = nullptr) const;

  /// Bit k set if PointTree::sector() can give sector k to a point of the box [lo, hi] seen from s.
  static unsigned sector_mask(const Vec3& lo, const Vec3& hi, const Vec3& s);

 private:
  static constexpr int kLeaf = 16;
  struct Node {
    Vec3 lo, hi;    // tight box of the points below
    int first = 0;  // the points [first, last) of pos_ and id_ lie below
    int last = 0;
    int child = -1;  // inner nodes: children child and child + 1
    int dim = 0;
    double split = 0;  // inner nodes: the lower child holds coordinates <= split, the upper >= split
  };
  void build(int n, int first, int last);
  double mindist2(const Node& nd, const Vec3& q) const;
  std::vector<Vec3> pos_;
  std::vector<Index> id_;
  std::vector<Node> nodes_;
  std::vector<int> order_;  // build scratch
  std::vector<Vec3> tmp_pos_;
  std::vector<Index> tmp_id_;
};

}  // namespace cellform::venation
