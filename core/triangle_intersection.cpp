// Exact-predicate style triangle-triangle intersection, with a rounding tolerance.
#include "core/triangle_intersection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Core>

namespace cellform::core {

namespace {

double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) { return (b - a).cross(c - a).dot(d - a); }

int sign(double x) { return (x > 0) - (x < 0); }

using P2 = Eigen::Vector2d;
double cross2(const P2& a, const P2& b, const P2& c) { return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x(); }

bool segments_cross_2d(const P2& p, const P2& q, const P2& a, const P2& b) {
  const int o1 = sign(cross2(p, q, a)), o2 = sign(cross2(p, q, b)), o3 = sign(cross2(a, b, p)),
            o4 = sign(cross2(a, b, q));
  return o1 * o2 < 0 && o3 * o4 < 0;
}

bool inside_2d(const P2& p, const P2& a, const P2& b, const P2& c) {
  const int s1 = sign(cross2(a, b, p)), s2 = sign(cross2(b, c, p)), s3 = sign(cross2(c, a, p));
  return (s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0);
}

// Projection dropping the dominant axis of the normal of triangle T.
struct Projection {
  int drop = 2;
  explicit Projection(const Vec3* T) {
    const Vec3 n = (T[1] - T[0]).cross(T[2] - T[0]).cwiseAbs();
    drop = n.x() >= n.y() && n.x() >= n.z() ? 0 : (n.y() >= n.z() ? 1 : 2);
  }
  P2 operator()(const Vec3& v) const {
    return drop == 0 ? P2(v.y(), v.z()) : drop == 1 ? P2(v.x(), v.z()) : P2(v.x(), v.y());
  }
};

// Does segment pq meet triangle T? dp, dq: sides of p and q relative to T's plane, 0 when within the
// tolerance; a point on the plane meets T if it lies inside T (projected), so nearly parallel segments
// are never extended to a far-away crossing. Not for a segment lying in the plane (handled in 2D).
bool segment_crosses(const Vec3& p, const Vec3& q, int dp, int dq, const Vec3* T) {
  if (dp * dq > 0 || (dp == 0 && dq == 0)) return false;
  if (dp == 0 || dq == 0) {
    const Projection pr(T);
    return inside_2d(pr(dp == 0 ? p : q), pr(T[0]), pr(T[1]), pr(T[2]));
  }
  const int s1 = sign(orient(p, q, T[0], T[1])), s2 = sign(orient(p, q, T[1], T[2])),
            s3 = sign(orient(p, q, T[2], T[0]));
  if (s1 == 0 && s2 == 0 && s3 == 0) return false;
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

// Sides of the points P[0..2] relative to the plane of T, 0 within `tol` (a length).
void sides(const Vec3* T, const Vec3* P, double tol, int* out) {
  const Vec3 n = (T[1] - T[0]).cross(T[2] - T[0]);
  const double len = n.norm();
  for (int i = 0; i < 3; ++i) {
    const double d = n.dot(P[i] - T[0]);
    out[i] = std::abs(d) <= tol * len ? 0 : sign(d);
  }
}

// Triangle-triangle intersection (Moller's separating-plane rejection first): two triangles in general
// position meet iff an edge of one meets the other; coplanar pairs are tested in 2D. Points within a
// rounding tolerance of the other plane count as on it, so that coplanar neighbours written through
// float or decimal files are not reported.
// The rounding tolerance (a length) for points of the largest coordinate `scale` and longest side `edge`.
double tolerance(double scale, double edge) { return 8 * std::numeric_limits<float>::epsilon() * scale + 1e-9 * edge; }

bool meet(const Vec3* A, const Vec3* B) {
  double scale = 0, edge = 0;
  for (int i = 0; i < 3; ++i) {
    scale = std::max({scale, A[i].cwiseAbs().maxCoeff(), B[i].cwiseAbs().maxCoeff()});
    edge = std::max({edge, (A[i] - A[(i + 1) % 3]).norm(), (B[i] - B[(i + 1) % 3]).norm()});
  }
  const double tol = tolerance(scale, edge);
  int da[3], db[3];
  sides(B, A, tol, da);
  if (da[0] == da[1] && da[1] == da[2] && da[0] != 0) return false;
  sides(A, B, tol, db);
  if (db[0] == db[1] && db[1] == db[2] && db[0] != 0) return false;
  const bool a_flat = da[0] == 0 && da[1] == 0 && da[2] == 0, b_flat = db[0] == 0 && db[1] == 0 && db[2] == 0;
  if (a_flat || b_flat) {
    // onto the plane the other lies in (of the larger when both do): a sliver thinner than the tolerance
    // may have a normal lying in the other's plane, and projected along it far triangles would overlap
    const auto area2 = [](const Vec3* T) { return (T[1] - T[0]).cross(T[2] - T[0]).squaredNorm(); };
    const Projection pr(a_flat && b_flat ? (area2(A) >= area2(B) ? A : B) : a_flat ? B : A);
    P2 a[3], b[3];
    for (int i = 0; i < 3; ++i) a[i] = pr(A[i]), b[i] = pr(B[i]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (segments_cross_2d(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3])) return true;
    for (int i = 0; i < 3; ++i)
      if (inside_2d(a[i], b[0], b[1], b[2]) || inside_2d(b[i], a[0], a[1], a[2])) return true;
    return false;
  }
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (segment_crosses(A[i], A[j], da[i], da[j], B) || segment_crosses(B[i], B[j], db[i], db[j], A)) return true;
  }
  return false;
}

}  // namespace

bool segment_meets_triangle(const Vec3& p, const Vec3& q, const std::array<Vec3, 3>& t) {
  double scale = std::max(p.cwiseAbs().maxCoeff(), q.cwiseAbs().maxCoeff()), edge = (q - p).norm();
  for (int i = 0; i < 3; ++i) {
    scale = std::max(scale, t[i].cwiseAbs().maxCoeff());
    edge = std::max(edge, (t[i] - t[(i + 1) % 3]).norm());
  }
  if ((t[1] - t[0]).cross(t[2] - t[0]).squaredNorm() == 0) return false;  // no area, no plane: nothing to meet
  const Vec3 P[3] = {p, q, q};
  int d[3];
  sides(t.data(), P, tolerance(scale, edge), d);
  if (d[0] != 0 || d[1] != 0) return segment_crosses(p, q, d[0], d[1], t.data());
  const Projection pr(t.data());  // in the plane: an end inside, or crossing a side
  const P2 a = pr(p), b = pr(q), T[3] = {pr(t[0]), pr(t[1]), pr(t[2])};
  if (inside_2d(a, T[0], T[1], T[2]) || inside_2d(b, T[0], T[1], T[2])) return true;
  for (int i = 0; i < 3; ++i)
    if (segments_cross_2d(a, b, T[i], T[(i + 1) % 3])) return true;
  return false;
}

bool triangles_intersect(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
  return meet(a.data(), b.data());
}

bool triangles_cross_beyond_corner(const std::array<Vec3, 3>& a, int i, const std::array<Vec3, 3>& b, int j) {
  // first the cheap case, most pairs round a corner of a mesh: a side wholly off the other's plane, by more
  // than twice any rounding tolerance (8 float epsilons of the coordinates, plus 1e-9 of sides shorter than 4
  // times them), cannot meet it
  double scale = 0;
  for (int k = 0; k < 3; ++k) scale = std::max({scale, a[k].cwiseAbs().maxCoeff(), b[k].cwiseAbs().maxCoeff()});
  const double margin = 2e-6 * scale;
  const auto off = [margin](const Vec3& p, const Vec3& q, const std::array<Vec3, 3>& t) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    const double dp = n.dot(p - t[0]), dq = n.dot(q - t[0]), limit = margin * margin * n.squaredNorm();
    return (dp > 0) == (dq > 0) && dp * dp > limit && dq * dq > limit;
  };
  const Vec3 &a1 = a[(i + 1) % 3], &a2 = a[(i + 2) % 3], &b1 = b[(j + 1) % 3], &b2 = b[(j + 2) % 3];
  return (!off(a1, a2, b) && segment_meets_triangle(a1, a2, b)) ||
         (!off(b1, b2, a) && segment_meets_triangle(b1, b2, a));
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) {  // degenerate triangle: the closest of its three edges
    Vec3 best = a;
    for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
      const Vec3 e = v - u;
      const double l2 = e.squaredNorm();
      const double t = l2 > 0 ? std::clamp((p - u).dot(e) / l2, 0.0, 1.0) : 0.0;
      const Vec3 q = u + t * e;
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    }
    return best;
  }
  const double v = vb / denom, w = vc / denom;
  return a + ab * v + ac * w;
}

}  // namespace cellform::core
