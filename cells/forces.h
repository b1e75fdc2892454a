// The intercellular force terms (Eqs. 2-5 of the cell-division venation paper) as pure per-cell kernels.
#pragma once

#include <Eigen/Geometry>  // cross products
#include <span>
#include <vector>

#include "cells/cells.h"
#include "cells/params.h"

namespace cellform::cells {

/// Eq. 2, spring towards the rest length, unweighted: (1/n) sum_r (|P_r - C| - d) (P_r - C) / |P_r - C|
/// over the cells `neighbours` (indices into `positions`). A compressed pair pushes apart, a stretched
/// pair pulls together (the printed formula lost its signs; this is what the paper's text says).
/// A neighbour at exactly the position of C pushes C along -x if its index is larger than `self`, +x
/// otherwise, so coincident cells separate symmetrically instead of producing NaN.
Vec3 spring_kernel(std::span<const Vec3> positions, Index self, std::span<const Index> neighbours, double rest_length);

/// Eq. 3, planarisation, unweighted: -((C - P1) . u) u, the vector from C to the plane through P1, P2, P3
/// (u its unit normal). Zero when the three points are (nearly) collinear or coincident. The printed
/// ((C - P1) . N / |N|^2) N points from the plane to C, away from it; the sign is turned to what the text
/// says, a force that pulls the cell towards the plane.
Vec3 planar_kernel(const Vec3& c, const Vec3& p1, const Vec3& p2, const Vec3& p3);

/// Eq. 4, cohesion, unweighted: (1/n) sum_r (P_r - C) / max(|P_r - C|, near)^2. Coincident neighbours are
/// skipped (they still count in n). Units: 1 / model unit. `near` (model units) departs from the printed
/// formula: closer than that, the pull weakens in proportion to the distance instead of growing as
/// 1 / distance, so the spring, which the paper says keeps attracted cells apart, can: without it a
/// vein cell pulled by cohesion towards its vein parent could overcome the spring's bounded push,
/// collapse onto the parent and then be thrown off by the singular pull. 0 = the formula as printed.
Vec3 cohesion_kernel(std::span<const Vec3> positions, Index self, std::span<const Index> neighbours, double near = 0);

/// `near` of the cohesion kernel in the cell step, in rest lengths. Not a guard for rare cases: most links are
/// shorter than the rest length (examples/leaf.lua: 89% of them, the median 0.8), so for most links the pull
/// is linear in the distance (at 0.8 rest lengths a pull of 0.8 / d, where Eq. 4 gives 1 / (0.8 d) = 1.25 / d;
/// d the rest length). That packing is not an effect of growth alone: a sheet packed closer than
/// 1.5 / sqrt(3) = 0.87 rest lengths (its second ring then within the default link_range of 1.5) stays packed,
/// because its rim cells link into the second ring and those stretched links pull the rim in. A disc placed at
/// 0.8 rest lengths that never divides still has a median link of 0.80 (radius 8; 0.86 at radius 2) after 1,500 steps,
/// with link_range 1.5 or 0 (the paper's six nearest at any distance).
inline constexpr double kCohesionNear = 1.0;

/// Eq. 5, separation, unweighted: (1/m) sum_r (C - P_r) / |C - P_r|^2 over `others`. Coincident ones are
/// skipped (they still count in m). Units: 1 / model unit.
Vec3 separation_kernel(std::span<const Vec3> positions, Index self, std::span<const Index> others);

/// Direct neighbours of cell i: its links (kNoIndex padding dropped), then its vein parent and vein
/// children that are not already linked. Appends to `out` (cleared first) in that order.
void direct_neighbours(const Cells& cells, const VeinChildren& children, Index i, std::vector<Index>& out);

/// Neighbours of the direct neighbours (their links only), excluding i and its direct neighbours
/// `direct`, deduplicated, in first-seen order. Appends to `out` (cleared first).
void second_ring(const Cells& cells, Index i, std::span<const Index> direct, std::vector<Index>& out);

/// Vein grandparent and grandchildren of i (the cells a vein cell straightens against). Appends to
/// `out` (cleared first).
void vein_second_ring(const Cells& cells, const VeinChildren& children, Index i, std::vector<Index>& out);

/// Scratch reused between cells (and steps) so the force loop does not allocate per cell.
struct ForceScratch {
  std::vector<Index> direct, ring, vein, vein_ring;
  std::vector<std::uint32_t> mark;  ///< one entry per cell: equal to `stamp` once seen by the current second_ring
  std::uint32_t stamp = 0;
};

/// second_ring() with a reusable per-cell stamp array: same result, O(candidates) instead of
/// O(candidates^2), with no clearing between calls (the array grows to the cell count once).
void second_ring(const Cells& cells, Index i, std::span<const Index> direct, std::vector<Index>& out,
                 ForceScratch& scratch);

/// Total acceleration of one cell from Eqs. 2-6 with the weights of its type plus the vein
/// straightening terms (cohesion * vein_cohesion_factor towards the vein parent and children,
/// separation * vein_separation_factor from the vein grandparent and grandchildren). Zero for fixed cells.
Vec3 cell_acceleration(const Cells& cells, const Params& params, const VeinChildren& children, Index i,
                       ForceScratch& scratch);

}  // namespace cellform::cells
