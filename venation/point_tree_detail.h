// Private to venation/: the pieces point_tree.cpp (PointTree) and point_batch.cpp (PointBatch) share.
#pragma once

#include <algorithm>

#include "venation/point_tree.h"

namespace cellform::venation {

/// Squared distance from q to the box [lo, hi] (0 inside); the pruning bound of both trees.
inline double box_distance2(const Vec3& lo, const Vec3& hi, const Vec3& q) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double a = lo[k] - q[k], b = q[k] - hi[k];
    const double e = a > 0 ? a : (b > 0 ? b : 0.0);
    d2 += e * e;
  }
  return d2;
}

// r sqrt(3) / 2: |u - m|^2 = (|u - s|^2 + |u - v|^2) / 2 - r^2 / 4 <= 3 r^2 / 4. That third disc prunes
// boxes the two lune discs let through; it is padded so that rounding never prunes a point of the
// lune (the point tests themselves are the exact ones). Children nearer to m go first: an occupied lune
// is then found after few boxes.
struct detail::Lune {
  Vec3 s, v, m;
  double r2, m2;
  Lune(const Vec3& s_, const Vec3& v_) : s(s_), v(v_), m(0.5 * (s_ + v_)), r2((v_ - s_).squaredNorm()) {
    const double mag = std::max(s.cwiseAbs().maxCoeff(), v.cwiseAbs().maxCoeff());
    m2 = (0.75 + 1e-6) * r2 + 1e-12 * mag * mag;
  }
  bool holds(const Vec3& u) const { return (u - s).squaredNorm() <= r2 && (u - v).squaredNorm() <= r2; }
};

}  // namespace cellform::venation
