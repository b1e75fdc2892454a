// Test helper: one step of closed space colonisation (Eq. 1 with Eq. 2 neighbourhoods) by brute force,
// for the tests that recompute a Colonisation's step from outside (colonisation_test, domain_test).
#pragma once

#include <cmath>
#include <map>
#include <vector>

#include "venation/colonisation.h"
#include "venation/point_tree.h"

namespace cellform::venation::testing {

/// Per vein node before a step: the summed unit vectors towards the sources whose relative
/// neighbourhood (brute force) holds it, except sources it has reached (closer than kill_distance);
/// whether any source pulls it; and the nearest such source (kNoIndex if none).
struct Eq1Pulls {
  std::vector<core::Vec3> sum;
  std::vector<char> pulled;
  std::vector<core::Index> nearest_source;
};

inline Eq1Pulls eq1_pulls(const std::vector<core::Vec3>& nodes, const std::vector<core::Vec3>& sources,
                          double kill_distance) {
  Eq1Pulls e{std::vector<core::Vec3>(nodes.size(), core::Vec3::Zero()), std::vector<char>(nodes.size(), 0),
             std::vector<core::Index>(nodes.size(), core::kNoIndex)};
  for (core::Index k = 0; k < sources.size(); ++k)
    for (core::Index u : relative_neighbourhood_brute_force(nodes, sources[k])) {
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
