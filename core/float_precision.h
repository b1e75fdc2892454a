// Whether positions survive being written as 32-bit floats.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

#include "core/types.h"

namespace cellform::core {

/// True when writing `points` as 32-bit floats would move one by more than 1e-5 of the points' extent (its
/// longest side): a form far from the origin (an export audit: cells 3,000,000 units out snapped to a grid of
/// 0.25 units, 62 distinct x among 300 cells). PLY writers then use 64-bit doubles.
inline bool needs_double(std::span<const Vec3> points) {
  if (points.empty()) return false;
  Vec3 lo = points.front(), hi = lo;
  double far = 0;
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    far = std::max(far, p.cwiseAbs().maxCoeff());
  }
  return far * 0x1p-24 > 1e-5 * (hi - lo).maxCoeff();  // a float's rounding error at the farthest coordinate
}

/// The PLY type of positions written as needs_double() says: "double" or "float".
inline std::string ply_position_type(bool doubles) { return doubles ? "double" : "float"; }

}  // namespace cellform::core
