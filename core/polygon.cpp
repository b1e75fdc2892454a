// Ear clipping of polygon faces in the coordinate plane most nearly their own.
#include "core/polygon.h"

#include <algorithm>
#include <cmath>

namespace cellform::core {

namespace {

using P2 = std::array<double, 2>;

double cross(const P2& a, const P2& b, const P2& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Whether p lies in the closed triangle abc (counter-clockwise).
bool in_triangle(const P2& p, const P2& a, const P2& b, const P2& c) {
  return cross(a, b, p) >= 0 && cross(b, c, p) >= 0 && cross(c, a, p) >= 0;
}

}  // namespace

std::vector<std::array<std::uint32_t, 3>> triangulate_polygon(std::span<const Vec3> corners, bool* concave_too_large) {
  if (concave_too_large) *concave_too_large = false;
  std::vector<std::array<std::uint32_t, 3>> out;
  const std::size_t n = corners.size();
  if (n < 3) return out;
  auto fan = [&](const std::vector<std::uint32_t>& ring) {
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) out.push_back({ring[0], ring[k], ring[k + 1]});
  };
  std::vector<std::uint32_t> ring(n);
  for (std::size_t i = 0; i < n; ++i) ring[i] = static_cast<std::uint32_t>(i);
  if (n == 3) {
    fan(ring);
    return out;
  }
  // the plane: drop the axis along which the Newell normal is largest; the 2-D corners then run
  // counter-clockwise when the normal's component there is positive, else they are mirrored
  Vec3 normal = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 &a = corners[i], &b = corners[(i + 1) % n];
    normal +=
        Vec3((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()), (a.x() - b.x()) * (a.y() + b.y()));
  }
  int axis = 0;
  normal.cwiseAbs().maxCoeff(&axis);
  if (!(normal[axis] != 0)) {  // no area (or not finite): nothing to cut by
    fan(ring);
    return out;
  }
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const bool mirror = normal[axis] < 0;
  std::vector<P2> q(n);
  for (std::size_t i = 0; i < n; ++i) q[i] = {corners[i][u], mirror ? -corners[i][v] : corners[i][v]};
  // convex: no corner turns right or back, at least three turn left, and once round in all (a pentagram
  // turns left at every corner, twice round; a corner repeated at a right turn
  // hides that turn, so the rest add up to more than once round). Corners in line turn by 0: a fan from
  // corner 0 gives a triangle of no area when corner 1 or n - 1 is one (a vertex a modeller put on an
  // edge), so such a polygon is cut by ear clipping, which never cuts at them.
  bool convex = true;
  int left = 0;
  double turning = 0;
  for (std::size_t i = 0; i < n && convex; ++i) {
    const P2 &a = q[(i + n - 1) % n], &b = q[i], &c = q[(i + 1) % n];
    const double turn = cross(a, b, c), ahead = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]);
    convex = turn > 0 || (turn == 0 && ahead >= 0);  // (a spike doubling back: turn 0, going back)
    left += turn > 0;
    turning += std::atan2(turn, ahead);
  }
  const bool convex_once = convex && left >= 3 && std::abs(turning - 2 * M_PI) < 1e-6;
  if (convex_once && left == static_cast<int>(n)) {
    fan(ring);
    return out;
  }
  if (n > (convex_once ? 16 * kMaxConcaveCorners : kMaxConcaveCorners)) {
    if (convex_once) {  // (its corners in line give triangles of no area, as a fan did before)
      fan(ring);
      return out;
    }
    if (concave_too_large) *concave_too_large = true;
    return out;
  }
  // ear clipping: a convex corner whose triangle holds no other corner of the rest is cut off; the scan
  // goes on from the corner after it. (A convex polygon needs the search too: where corners in line lie on
  // the chord, a cut there would leave a triangle of no area.) Its time grows as the square of the corners:
  // a convex polygon with corners in line is cut up to 16 times as many as a concave one. The rest of the
  // ring is a linked list (a cut is O(1)).
  std::vector<std::uint32_t> next(n), prev(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    next[i] = static_cast<std::uint32_t>((i + 1) % n);
    prev[i] = static_cast<std::uint32_t>((i + n - 1) % n);
  }
  std::uint32_t at = 0;
  std::size_t m = n, misses = 0;
  while (m > 3) {
    const std::uint32_t ip = prev[at], in = next[at];
    const P2 &a = q[ip], &b = q[at], &c = q[in];
    bool ear = cross(a, b, c) > 0;
    for (std::uint32_t k = next[in]; ear && k != ip; k = next[k]) {
      const P2& p = q[k];
      if (p == a || p == b || p == c) continue;  // a corner repeated at the same place
      ear = !in_triangle(p, a, b, c);
    }
    if (ear) {
      out.push_back({ip, at, in});
      next[ip] = in;
      prev[in] = ip;
      at = in;
      --m;
      misses = 0;
    } else if (++misses == m) {  // no ear anywhere: it crosses itself, or is flat along a line
      std::vector<std::uint32_t> rest;
      for (std::uint32_t k = at; rest.size() < m; k = next[k]) rest.push_back(k);
      fan(rest);
      return out;
    } else {
      at = in;
    }
  }
  std::array<std::uint32_t, 3> last{prev[at], at, next[at]};  // from its first corner in the polygon's order
  std::rotate(last.begin(), std::min_element(last.begin(), last.end()), last.end());
  out.push_back(last);
  return out;
}

}  // namespace cellform::core
