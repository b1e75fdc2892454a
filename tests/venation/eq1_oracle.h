// Test helper: one step of space colonisation (Eq. 1 with nearest, Eq. 2 or Urquhart neighbourhoods) by brute force,
// for the tests that recompute a Colonisation's step from outside (colonisation_test, domain_test).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "venation/colonisation.h"
#include "venation/point_tree.h"

namespace cellform::venation::testing {

/// Eq. 2 by brute force, O(n^2): v is in the relative neighbourhood of s unless some other point u lies in
/// the closed lune of s and v (|u - s| <= |v - s| and |v - u| <= |v - s|). Sorted by index.
inline std::vector<core::Index> relative_neighbourhood_brute_force(const std::vector<core::Vec3>& points,
                                                                   const core::Vec3& s) {
  std::vector<core::Index> out;
  for (std::size_t v = 0; v < points.size(); ++v) {
    // squared, as in PointTree, so that exact ties agree
    const double r2 = (points[v] - s).squaredNorm();
    bool ok = true;
    for (std::size_t u = 0; u < points.size() && ok; ++u)
      if (u != v && (points[u] - s).squaredNorm() <= r2 && (points[v] - points[u]).squaredNorm() <= r2) ok = false;
    if (ok) out.push_back(static_cast<core::Index>(v));
  }
  return out;
}

/// Brute-force Delaunay neighbourhood of s in the plane: v is one iff the part of the s-v bisector
/// closer to s than to every other point has positive length (a Voronoi edge exists).
inline std::vector<core::Index> delaunay_brute_force(const std::vector<core::Vec3>& pts, const core::Vec3& s) {
  std::vector<core::Index> out;
  for (core::Index v = 0; v < pts.size(); ++v) {
    const Eigen::Vector2d S(s.x(), s.y()), V(pts[v].x(), pts[v].y());
    if ((V - S).norm() == 0) continue;
    const Eigen::Vector2d m = 0.5 * (S + V), d((V - S).y() * -1, (V - S).x());
    double lo = -1e300, hi = 1e300;
    for (core::Index u = 0; u < pts.size(); ++u) {
      if (u == v) continue;
      const Eigen::Vector2d U(pts[u].x(), pts[u].y());
      // |c - s|^2 <= |c - u|^2  <=>  2 c.(u - s) <= |u|^2 - |s|^2, with c = m + t d
      const double a = 2 * d.dot(U - S), b = U.squaredNorm() - S.squaredNorm() - 2 * m.dot(U - S);
      if (a > 0)
        hi = std::min(hi, b / a);
      else if (a < 0)
        lo = std::max(lo, b / a);
      else if (b < 0) {
        lo = 1;
        hi = -1;
      }
    }
    if (hi - lo > 1e-9) out.push_back(v);
  }
  return out;
}

/// Brute-force Urquhart neighbourhood (Section 5): the Delaunay neighbours of s less those v that another
/// Delaunay neighbour u excludes, u lying in the closed lune of s and v (|u - s| <= |v - s|, |u - v| <= |v - s|).
inline std::vector<core::Index> urquhart_brute_force(const std::vector<core::Vec3>& pts, const core::Vec3& s) {
  const std::vector<core::Index> dn = delaunay_brute_force(pts, s);
  std::vector<core::Index> out;
  for (core::Index v : dn) {
    const double r2 = (pts[v] - s).squaredNorm();
    bool excluded = false;
    for (core::Index u : dn)
      excluded |= u != v && (pts[u] - s).squaredNorm() <= r2 && (pts[u] - pts[v]).squaredNorm() <= r2;
    if (!excluded) out.push_back(v);
  }
  return out;
}

/// Which vein nodes a source pulls: open patterns its nearest (ties: the smaller index); closed patterns
/// its relative neighbourhood (Eq. 2), or Urquhart's approximation of it (in the plane).
enum class Pulled { nearest, relative, urquhart };

/// Per vein node before a step: the summed unit vectors towards the sources that pull it (`pulled`, by
/// brute force), except sources it has reached (closer than kill_distance); whether any source pulls
/// it; and the nearest such source (kNoIndex if none).
struct Eq1Pulls {
  std::vector<core::Vec3> sum;
  std::vector<char> pulled;
  std::vector<core::Index> nearest_source;
};

inline Eq1Pulls eq1_pulls(const std::vector<core::Vec3>& nodes, const std::vector<core::Vec3>& sources,
                          double kill_distance, Pulled pulled = Pulled::relative) {
  Eq1Pulls e{std::vector<core::Vec3>(nodes.size(), core::Vec3::Zero()), std::vector<char>(nodes.size(), 0),
             std::vector<core::Index>(nodes.size(), core::kNoIndex)};
  auto influenced = [&](const core::Vec3& s) {
    if (pulled == Pulled::relative) return relative_neighbourhood_brute_force(nodes, s);
    if (pulled == Pulled::urquhart) return urquhart_brute_force(nodes, s);
    core::Index best = 0;
    for (core::Index u = 1; u < nodes.size(); ++u)
      if ((nodes[u] - s).squaredNorm() < (nodes[best] - s).squaredNorm()) best = u;
    return std::vector<core::Index>{best};
  };
  for (core::Index k = 0; k < sources.size(); ++k)
    for (core::Index u : influenced(sources[k])) {
      const core::Vec3 dir = sources[k] - nodes[u];
      if (dir.squaredNorm() < kill_distance * kill_distance) continue;  // reached veins stop
      e.sum[u] += dir / dir.norm();
      e.pulled[u] = 1;
      if (e.nearest_source[u] == core::kNoIndex ||
          dir.squaredNorm() < (sources[e.nearest_source[u]] - nodes[u]).squaredNorm())
        e.nearest_source[u] = k;
    }
  return e;
}

/// The nodes a step added, by parent (each node grows at most one child per step).
inline std::map<core::Index, core::Vec3> grown_by_parent(const VeinTree& before, const VeinTree& after) {
  std::map<core::Index, core::Vec3> grown;
  for (core::Index i = static_cast<core::Index>(before.size()); i < after.size(); ++i)
    grown[after.parent[i]] = after.positions[i];
  return grown;
}

/// True if the segment u -> q runs within 5 degrees of one of u's tree segments (to a child or to its
/// parent): Eq. 1 then only retraces the vein and adds no node.
inline bool retraces(const VeinTree& t, core::Index u, const core::Vec3& q) {
  auto degrees = [](const core::Vec3& a, const core::Vec3& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / 3.14159265358979323846;
  };
  for (core::Index k = 0; k < t.size(); ++k)
    if ((t.parent[k] == u || t.parent[u] == k) && degrees(t.positions[k] - t.positions[u], q - t.positions[u]) < 5)
      return true;
  return false;
}

}  // namespace cellform::venation::testing
