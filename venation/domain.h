// Where space colonisation throws its darts: a planar leaf blade, a 3-D volume, or a triangle surface.
#pragma once

#include <algorithm>
#include <array>
#include <memory>
#include <numeric>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "core/random.h"
#include "core/triangle_intersection.h"
#include "core/types.h"
#include "venation/colonisation.h"

namespace cellform::venation {

/// A triangle soup in model units (the venation library's own copy of forms::TriangleMesh, which it
/// cannot depend on). Orientation does not matter.
struct Mesh {
  std::vector<Vec3> vertices;                   ///< model units
  std::vector<std::array<Index, 3>> triangles;  ///< indices into vertices
};

/// The kind of region auxin sources are placed in.
enum class DomainKind {
  leaf,    ///< the planar blade of Runions et al. 2005 (Domain::leaf, z = 0), with its growth modes
  box,     ///< the axis-aligned box [box_min, box_max]
  ball,    ///< the ball of `radius` about `centre`
  volume,  ///< the inside of the closed triangle mesh `mesh` (even-odd rule)
  surface  ///< the triangles of `mesh` (any soup: open, closed, non-manifold)
};

/// The source domain of space colonisation. The 3-D kinds use the same algorithm as the leaf (Eq. 1 to
/// 3, Euclidean distances in 3-D) with these differences:
/// - darts: rho (ColonisationParams::darts_per_area) counts darts per unit volume (box, ball, volume) or
///   per unit area (surface) per step. Volumes throw darts uniformly in their bounding box at that rate
///   and drop the ones outside, so rho x volume darts fall inside on average; a surface throws
///   floor(rho A) darts (plus one with probability of the remainder) at area-weighted uniform points of
///   its triangles (A = total area);
/// - vein nodes: a new node (Eq. 1) that falls outside a volume is moved to the closest point of its
///   boundary; on a surface every new node is moved to the closest point of the surface, so the veins
///   stay in the shell (segments between nodes are straight chords; sheets closer than D apart may be
///   bridged; a node the projection brings back within D / 10 of its parent is not added, as the vein
///   cannot advance there);
/// - where the pulls on a node cancel, or sources pulling it apart would only retrace one of its
///   segments (within 5 degrees, Colonisation::step(): usually its existing Eq. 1 child, which is farther
///   from each of them than the node, so the node stays their nearest), the node grows towards its
///   nearest influencing source alone (unless that retraces a segment too); in 3-D such pairs are common
///   and would otherwise stall the pattern with many sources left (a leaf does the same);
/// - no blade growth (ColonisationParams::growth must be none, initial_scale 1) and, for closed patterns,
///   the exact 3-D relative neighbourhood only (Urquhart's approximation is planar).
struct Domain {
  DomainKind kind = DomainKind::leaf;
  Leaf leaf;                          ///< kind leaf: the blade and its seeds
  Vec3 box_min = Vec3::Zero();        ///< box: lowest corner, model units
  Vec3 box_max = Vec3::Ones();        ///< box: highest corner, model units (> box_min in x, y and z)
  Vec3 centre = Vec3::Zero();         ///< ball: centre, model units
  double radius = 1;                  ///< ball: radius, model units (> 0)
  Mesh mesh;                          ///< volume (closed) or surface
  std::vector<Vec3> initial_nodes;    ///< 3-D kinds: seed vein nodes (at least one), model units
  std::vector<Vec3> initial_sources;  ///< 3-D kinds: sources at step 0 (no birth-distance test), model units
};

/// Throws core::InvalidInput naming "domain.<field>" and what is allowed: for a leaf as validate(Leaf);
/// for the 3-D kinds a box with min >= max, a radius <= 0, non-finite coordinates, an empty mesh or a
/// triangle index out of range, a volume mesh that is not closed (an edge used by an odd number of
/// triangles), no seed node, or a seed node or source outside the domain (farther than 1e-6 of the
/// bounding-box diagonal from a volume, or from a surface).
void validate(const Domain& domain);

/// Bounding box of a 3-D domain, model units: the box, the ball's box, or the mesh's vertices (empty for a leaf,
/// whose blade grows, and for a mesh with no vertices).
Eigen::AlignedBox3d bounding_box(const Domain& domain);

/// Throws core::InvalidInput naming the colonisation parameter when `params` cannot be used with the
/// domain's kind: a 3-D domain needs growth none, initial_scale 1 and, for closed venation, the exact
/// neighbourhood and distinct seed vein nodes.
void validate(const Domain& domain, const ColonisationParams& params);
/// The same for a leaf: a closed pattern's seed vein nodes must be distinct points (seeds on one point never
/// grow apart; an open pattern grows from the first of them).
void validate(const Leaf& leaf, const ColonisationParams& params);

/// A 3-D domain prepared for repeated queries: dart throwing, inside tests and closest points (a
/// bounding-volume hierarchy over the triangles; a uniform xy grid for the inside test of a mesh).
class PreparedDomain {
 public:
  /// Validates the domain (as validate(Domain)) and builds the indexes. Not for kind leaf.
  explicit PreparedDomain(const Domain& domain);
  ~PreparedDomain();
  PreparedDomain(PreparedDomain&&) noexcept;
  PreparedDomain& operator=(PreparedDomain&&) noexcept;

  /// Darts of one step at `rho` per unit volume or area (see Domain), appended to `out` in the order
  /// thrown; only darts inside the domain are kept. Uses only `rng`: same seed, same darts.
  void throw_darts(double rho, core::Rng& rng, std::vector<Vec3>& out) const;

  /// Volume (box, ball; for a mesh volume its bounding box's) or surface area that darts are thrown
  /// over, model units cubed or squared.
  double dart_measure() const;
  /// Volume (a mesh volume's to within a few percent, from a lattice of inside tests) or surface area of the
  /// domain itself, model units cubed or squared.
  double measure() const;

  /// True if `q` is inside the volume or within `tolerance` (model units) of it, or within `tolerance`
  /// of the surface.
  bool contains(const Vec3& q, double tolerance) const;

  /// Volume: `q` itself if inside, else the closest point of the boundary. Surface: the closest point
  /// of the surface (ties: the triangle with the smaller index).
  Vec3 project(const Vec3& q) const;

  /// The closest point of the mesh's triangles to `q` (volume and surface kinds; box and ball: project()).
  Vec3 closest_point(const Vec3& q) const;

  /// Bounding box of the domain, model units.
  const Vec3& lo() const;
  const Vec3& hi() const;

  const Domain& domain() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

using core::closest_point_on_triangle;

/// The first point of `points` (in order) equal to an earlier one (== in every coordinate), as the 0-based
/// indices (earlier, later); none if all differ. Seed vein nodes on one point cannot grow apart: every
/// source pulls them alike. O(n log n).
template <class Point>
std::optional<std::pair<std::size_t, std::size_t>> first_repeat(const std::vector<Point>& points) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto less = [&](std::size_t a, std::size_t b) {
    for (int k = 0; k < points[a].size(); ++k)
      if (points[a][k] != points[b][k]) return points[a][k] < points[b][k];
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  // equal points are together, in index order: each group's first two are its earliest repeat
  std::optional<std::pair<std::size_t, std::size_t>> best;
  for (std::size_t k = 1; k < order.size(); ++k)
    if (points[order[k - 1]] == points[order[k]] && (k < 2 || points[order[k - 2]] != points[order[k]]) &&
        (!best || order[k] < best->second))
      best = std::pair{order[k - 1], order[k]};
  return best;
}

}  // namespace cellform::venation
