// A witness grid over the vein nodes: rejects most darts of the b_v test (Runions et al. 2005, Section 3.1)
// in O(1), before any k-d tree query.
#pragma once

#include <cstdint>
#include <vector>

#include "core/types.h"

namespace cellform::venation {

/// Vein nodes hashed into a uniform grid of the plane z = 0 that keeps one node per cell (the first to
/// arrive). A dart near a vein almost always has such a node within the vein birth distance in its own
/// cell or one of the 8 around it, which proves it too near without searching the k-d tree: exact, since
/// a witness is a real node tested with the same squared distance as the tree's test, and "no witness"
/// only means "ask the tree". So the grid never changes an answer, only its cost, and may be stale,
/// coarse or partial: nodes outside its box are simply not kept, moved nodes are tested where they are.
///
/// With a cell side of at most r / sqrt 2 every node's own cell is covered by its disc of radius r; the
/// caller resets the grid with a finer cell when r shrinks (isogonic growth), a few times per run.
class WitnessGrid {
 public:
  /// Empties the grid and lays cells of side `cell` over [lo, hi] (model units; at most `max_cells`
  /// cells: a coarser cell is used if needed). With `cover` > 0 (model units) the grid also keeps a map of
  /// the cells that lie wholly within `cover` of a node, which settles any query of r >= cover alone.
  void reset(const core::Vec3& lo, const core::Vec3& hi, double cell, std::size_t max_cells, double cover = 0);
  /// Forgets every node and the box (every query says "ask the tree").
  void clear();
  /// Offers node i at p: kept if its cell has none yet (and p is in the box, in the plane z = 0).
  void insert(core::Index i, const core::Vec3& p);
  /// True if a kept node u has (points[u] - q).squaredNorm() <= r2 among the cells around q, or (q in the
  /// plane, r2 >= cover^2) q's cell is in the map of covered cells: one bit read (8 cells a byte, so that a
  /// large blade's map stays in cache), and no node.
  bool witness(const core::Vec3& q, double r2, const std::vector<core::Vec3>& points) const;
  /// Whether the map of covered cells settles queries of squared radius r2 (cover^2 <= r2).
  bool covers_radius(double r2) const;

  double cell() const { return cell_; }
  bool empty() const { return cells_.empty(); }
  /// True if [lo, hi] lies in the grid's box.
  bool covers(const core::Vec3& lo, const core::Vec3& hi) const;

 private:
  double cell_ = 0, inv_ = 0;
  core::Vec3 lo_ = core::Vec3::Zero(), hi_ = core::Vec3::Zero();
  long nx_ = 0, ny_ = 0;
  std::vector<core::Index> cells_;       // row-major, kNoIndex = no node kept
  std::vector<std::uint64_t> occupied_;  // bit per cell: cells_ holds a node
  std::vector<std::uint64_t> covered_;   // bit per half cell (a cell's quarter): all of it within cover_ of a node
  double cover_ = 0;                     // model units; 0 = no map of covered cells
  bool fine_ = false;                    // cells wide against the rounding of their coordinates
};

}  // namespace cellform::venation
