// Private to cells/: the filling of small holes in the one-layer cell surface (surface_holes.cpp) and the
// tests of a new triangle against the sheet, stacked round a corner or crossing (surface_index.cpp), used by
// triangulate() in surface.cpp. Not installed, not for users.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "cells/cells.h"
#include "core/spatial_index.h"

namespace cellform::cells::detail {

/// Whether segments pq and rs cross as the two diagonals of a quad do: their closest points lie inside
/// both (not at an end: parameters in (0.02, 0.98)) and are nearer each other than a quarter of the shorter
/// (a folded quad still counts; two edges of a thick clump, far apart, do not). Parallel segments do not.
bool diagonals_cross(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s);

/// Whether triangles t1 and t2, which share corner v and no side, lie over each other round v: nearly in
/// one plane (normals within 35 degrees, either way round) and, seen in t1's plane, their angles at v
/// overlapping by more than a fifth of the smaller. A sheet of one layer never does; the cliques of a
/// crowded sheet do where they are not folded along a common side.
bool stacked_at(const std::vector<Vec3>& pos, const std::array<Index, 3>& t1, const std::array<Index, 3>& t2, Index v);

/// The triangles of a growing list at each of their corners, to find a new one stacked on one of them.
/// Each corner's triangles lie together (room for those of `room` that may come, then a spill list).
class CornerIndex {
 public:
  /// `room`: triangles that may be added later; `tris`: added now.
  CornerIndex(std::size_t cells, const std::vector<std::array<Index, 3>>& room,
              const std::vector<std::array<Index, 3>>& tris);
  void add(const std::array<Index, 3>& t);
  /// Whether `t` lies over a triangle added before that it shares a corner but no side with (stacked_at).
  bool stacks(const std::vector<Vec3>& pos, const std::array<Index, 3>& t) const;
  /// Whether `t` crosses, beyond their common corner, a triangle added before that it shares one corner
  /// with (the side of one opposite that corner meets the other: core::segment_meets_triangle).
  bool crosses_at_corner(const std::vector<Vec3>& pos, const std::array<Index, 3>& t) const;
  /// Calls f(triangle) for every triangle added with corner v.
  template <class F>
  void for_each_at(Index v, F&& f) const {
    for (std::size_t x = start_[v]; x < fill_[v]; ++x) f(slot_[x]);
    for (std::uint32_t x = head_[v]; x != kNone; x = spill_[x].first) f(spill_[x].second);
  }

 private:
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::size_t> start_, fill_;  // per cell: its slots, and the first free one
  std::vector<std::array<Index, 3>> slot_;
  std::vector<std::uint32_t> head_;                                    // per cell: its latest spilled entry, or kNone
  std::vector<std::pair<std::uint32_t, std::array<Index, 3>>> spill_;  // (previous entry, triangle)
};

/// The triangles of a growing one-layer sheet, to test a new triangle against: stacked on one round a
/// corner (CornerIndex), or crossing one. A triangle that meets a new one F has a corner within F's radius
/// plus its own longest side of F's centre: the cells that near (a grid of every cell, made at the first
/// crossing test) hold every triangle with sides up to kLongSides typical sides (the mean side of the sheet
/// given first); the longer ones are kept in a list that every test goes through.
class SheetIndex {
 public:
  static constexpr double kLongSides = 4;
  /// `pos` is kept by reference; `tris`: the sheet now. `typical_side`: the typical side (model units; 0: the mean
  /// side of `tris`, or 1 if it has none). Only the cost depends on it, never an answer.
  SheetIndex(const std::vector<Vec3>& pos, const std::vector<std::array<Index, 3>>& tris, double typical_side = 0);
  void add(const std::array<Index, 3>& t);
  /// Whether `t` lies over a triangle of the sheet round a corner they share (CornerIndex::stacks).
  bool stacks(const std::array<Index, 3>& t) const { return corners_.stacks(pos_, t); }
  /// Whether `f` crosses a triangle of the sheet or of `others` (not in the sheet yet) with no common side:
  /// with no common corner, they meet (core::triangles_intersect); with one, they meet beyond it (the side of
  /// one opposite it meets the other). Two with a common side are the fold tests' case: never.
  bool crosses(const std::array<Index, 3>& f, const std::vector<std::array<Index, 3>>& others);

 private:
  void note_long(const std::array<Index, 3>& t);
  const std::vector<Vec3>& pos_;
  CornerIndex corners_;
  double reach_ = 1;                        // model units: kLongSides typical sides
  std::vector<std::array<Index, 3>> long_;  // triangles with a side longer than reach_
  double longest_short_ = 0;                // the longest side of the others: the grid search reaches that far
  core::PointGrid grid_;
  bool grid_built_ = false;
  std::vector<Index> near_;
};

/// Fills the small holes (loops of up to 12 boundary sides) the one-layer surface leaves (see
/// surface_holes.cpp): `sides` are the links the triangles are made of (with or without a triangle) and the
/// diagonals of closed quads, sorted; `incidence` the (side, triangle) pairs sorted by side, `inc_start`
/// where each side's pairs begin. New triangles are appended to `tris`, which is then sorted by smallest
/// index (stable); a hole whose fill would fold, lie over a triangle round a corner (stacked_at) or cross
/// one stays open.
void fill_small_holes(const std::vector<Vec3>& pos, const std::vector<std::array<Index, 2>>& sides,
                      const std::vector<std::size_t>& inc_start,
                      const std::vector<std::pair<std::size_t, std::size_t>>& incidence,
                      std::vector<std::array<Index, 3>>& tris);

}  // namespace cellform::cells::detail
