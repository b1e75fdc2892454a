// Tests of core/triangle_intersection.cpp: crossing, touching, apart, and slivers within rounding of a plane;
// closest points.
#include "core/triangle_intersection.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/random.h"

using cellform::core::triangles_intersect;
using cellform::core::Vec3;

TEST_CASE("triangles meet when an edge crosses, touch, or overlap in one plane; not when apart", "[triangle]") {
  const std::array<Vec3, 3> flat{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)};
  // an upright triangle whose lower edge pierces the flat one
  CHECK(triangles_intersect(flat, {Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 1), Vec3(0.5, 3, 0)}));
  // the same, moved beyond the flat one's hypotenuse x + y = 2
  CHECK_FALSE(triangles_intersect(flat, {Vec3(1.5, 1.5, -1), Vec3(1.5, 1.5, 1), Vec3(1.5, 3, 0)}));
  // above it
  CHECK_FALSE(triangles_intersect(flat, {Vec3(0, 0, 0.1), Vec3(1, 0, 0.1), Vec3(0, 1, 0.1)}));
  // touching it with a corner inside it
  CHECK(triangles_intersect(flat, {Vec3(0.5, 0.5, 0), Vec3(0.5, 0.5, 1), Vec3(1, 0.5, 1)}));
  // coplanar: overlapping, then apart
  CHECK(triangles_intersect(flat, {Vec3(1, 1, 0), Vec3(-1, 1, 0), Vec3(1, -1, 0)}));
  CHECK_FALSE(triangles_intersect(flat, {Vec3(3, 3, 0), Vec3(5, 3, 0), Vec3(3, 5, 0)}));
}

TEST_CASE("a triangle lying inside another in its plane meets it, in either argument order", "[triangle]") {
  // no edges cross: only a corner inside the other triangle decides, and it must be looked for both ways round
  const std::array<Vec3, 3> big{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const std::array<Vec3, 3> small{Vec3(0.2, 0.2, 0), Vec3(0.6, 0.2, 0), Vec3(0.2, 0.6, 0)};
  CHECK(triangles_intersect(big, small));
  CHECK(triangles_intersect(small, big));
  // the same, tilted out of the axis planes and moved away from the origin
  const Vec3 o(3, -2, 5), e1 = Vec3(1, 2, 0.5).normalized(), e2 = e1.cross(Vec3(0.3, -1, 2)).normalized();
  auto on_plane = [&](const std::array<Vec3, 3>& t) {
    std::array<Vec3, 3> r;
    for (int i = 0; i < 3; ++i) r[i] = o + t[i].x() * e1 + t[i].y() * e2;
    return r;
  };
  CHECK(triangles_intersect(on_plane(big), on_plane(small)));
  CHECK(triangles_intersect(on_plane(small), on_plane(big)));
  // intersection is symmetric: random pairs in general position and in one plane (overlapping, apart, or one
  // inside the other) get the same answer in both orders; a triangle whose corners are convex combinations of
  // another's with weights bounded away from 0 lies inside it and must meet it
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1), w(0.1, 1);
  std::size_t met = 0, nested = 0, asymmetric = 0, nested_missed = 0;
  for (int k = 0; k < 6000; ++k) {
    const int kind = k % 3;  // 0: general position, 1: coplanar, 2: coplanar, the second inside the first
    auto point = [&]() { return Vec3(u(rng), u(rng), kind == 0 ? u(rng) : 0.0); };
    const std::array<Vec3, 3> a{point(), point(), point()};
    std::array<Vec3, 3> b{point(), point(), point()};
    if (kind == 2) {
      if ((a[1] - a[0]).cross(a[2] - a[0]).norm() < 0.1) continue;  // a clear interior
      for (Vec3& p : b) {
        const double w0 = w(rng), w1 = w(rng), w2 = w(rng);
        p = (w0 * a[0] + w1 * a[1] + w2 * a[2]) / (w0 + w1 + w2);
      }
    }
    const bool ab = triangles_intersect(a, b), ba = triangles_intersect(b, a);
    asymmetric += ab != ba;
    met += ab;
    if (kind == 2) {
      nested_missed += !ab || !ba;
      ++nested;
    }
  }
  CHECK(asymmetric == 0);
  CHECK(nested_missed == 0);
  CHECK(met > 1000);
  CHECK(nested > 1000);
}

TEST_CASE("a sliver within rounding of another triangle's plane is tested in that plane", "[triangle]") {
  // A stands across B's plane by 1e-6 (within the tolerance), and A's normal lies in B's plane: projected
  // along it, B is a segment that A's edge crosses; in B's plane they are 0.047 apart
  const std::array<Vec3, 3> b{Vec3(0, -1, 0), Vec3(2, -1, 0), Vec3(2, -0.9, 0)};
  const std::array<Vec3, 3> a{Vec3(0.05, -0.95, -1e-6), Vec3(0.05, -0.9, 0), Vec3(0.05, -0.95, 1e-6)};
  CHECK_FALSE(triangles_intersect(a, b));
  CHECK_FALSE(triangles_intersect(b, a));
  // moved onto B (x = 1.9, where B spans y from -1 to -0.905), it meets it
  std::array<Vec3, 3> on = a;
  for (Vec3& p : on) p.x() = 1.9;
  CHECK(triangles_intersect(on, b));
  CHECK(triangles_intersect(b, on));
}

TEST_CASE("a segment meets a triangle it crosses, touches or lies across in its plane", "[triangle]") {
  using cellform::core::segment_meets_triangle;
  const std::array<Vec3, 3> flat{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)};
  CHECK(segment_meets_triangle(Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 1), flat));         // through it
  CHECK_FALSE(segment_meets_triangle(Vec3(1.5, 1.5, -1), Vec3(1.5, 1.5, 1), flat));   // beside it
  CHECK_FALSE(segment_meets_triangle(Vec3(0.5, 0.5, 0.1), Vec3(0.5, 0.5, 1), flat));  // short of it
  CHECK(segment_meets_triangle(Vec3(0.5, 0.5, 0), Vec3(0.5, 0.5, 1), flat));          // ending on it
  CHECK(segment_meets_triangle(Vec3(-1, 0.5, 0), Vec3(3, 0.5, 0), flat));             // across, in its plane
  CHECK_FALSE(segment_meets_triangle(Vec3(-1, 3, 0), Vec3(3, 3, 0), flat));           // in its plane, past it
  // two triangles sharing corner (0, 0, 0): an upright one through the flat one crosses it beyond the corner
  // exactly when its side opposite the corner meets the flat one
  CHECK(segment_meets_triangle(Vec3(1, 0.5, -1), Vec3(1, 0.5, 1), flat));
  CHECK_FALSE(segment_meets_triangle(Vec3(1, 1.5, -1), Vec3(1, 1.5, 1), flat));
  // a triangle of no area (in a line, or two corners the same) has no plane and meets nothing, however the
  // segment lies
  for (const std::array<Vec3, 3>& line : {std::array<Vec3, 3>{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)},
                                          std::array<Vec3, 3>{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0)}}) {
    CHECK_FALSE(segment_meets_triangle(Vec3(0.5, 5, 5), Vec3(0.5, 5, 6), line));
    CHECK_FALSE(segment_meets_triangle(Vec3(0.5, -1, 0), Vec3(0.5, 1, 0), line));
  }
}

TEST_CASE("triangles round a shared corner cross iff a far side meets the other, its quick rejection aside",
          "[triangle]") {
  using cellform::core::segment_meets_triangle;
  using cellform::core::triangles_cross_beyond_corner;
  // random pairs round a corner far from the origin, many nearly in one plane (within and just beyond the
  // rounding tolerance, where the quick rejection must never decide differently from the full test)
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec3 corner(300, -200, 150);
  std::size_t crossing = 0, near_plane = 0;
  for (int k = 0; k < 20000; ++k) {
    const double flat = std::pow(10.0, -8 + 8 * (u(rng) + 1) / 2);  // out-of-plane size, 1e-8 to 1e0
    auto point = [&]() -> Vec3 { return corner + Vec3(u(rng), u(rng), flat * u(rng)); };
    const std::array<Vec3, 3> a{corner, point(), point()}, b{point(), corner, point()};
    const bool full =
        segment_meets_triangle(a[1], a[2], b) || segment_meets_triangle(b[2], b[0], a);  // sides opposite it
    CHECK(triangles_cross_beyond_corner(a, 0, b, 1) == full);
    crossing += full;
    near_plane += flat < 1e-4;
  }
  CHECK(crossing > 1000);
  CHECK(near_plane > 5000);
  // an independent oracle in general position: copies with the shared corner moved a little towards their
  // centroids lie inside the triangles and away from that corner, so they meet iff the triangles cross beyond
  // it (unless the crossing ends within about that move of the corner: those, where two moves disagree, skipped);
  // at the origin, where the rounding tolerance (1e-6 of the coordinates) is far below the moves
  auto shrunk = [](std::array<Vec3, 3> t, int at, double by) {
    t[at] += by * ((t[0] + t[1] + t[2]) / 3 - t[at]);
    return t;
  };
  std::size_t agreed = 0, crossed = 0, borderline = 0;
  for (int k = 0; k < 5000; ++k) {
    auto point = [&]() -> Vec3 { return Vec3(u(rng), u(rng), u(rng)); };
    const std::array<Vec3, 3> a{Vec3::Zero(), point(), point()}, b{point(), point(), Vec3::Zero()};
    const bool coarse = triangles_intersect(shrunk(a, 0, 1e-2), shrunk(b, 2, 1e-2)),
               fine = triangles_intersect(shrunk(a, 0, 1e-4), shrunk(b, 2, 1e-4));
    CHECK(triangles_intersect(shrunk(b, 2, 1e-2), shrunk(a, 0, 1e-2)) == coarse);  // either order
    CHECK(triangles_intersect(shrunk(b, 2, 1e-4), shrunk(a, 0, 1e-4)) == fine);
    if (coarse != fine) {
      ++borderline;
      continue;
    }
    CHECK(triangles_cross_beyond_corner(a, 0, b, 2) == fine);
    agreed += triangles_cross_beyond_corner(a, 0, b, 2) == fine;
    crossed += fine;
  }
  CHECK(borderline < 50);
  CHECK(crossed > 200);
  CHECK(agreed + borderline == 5000);
}

TEST_CASE("the closest point of a triangle is no farther than any sampled point of it, and lies on it", "[core]") {
  cellform::core::Rng rng(9);
  const Vec3 a(0, 0, 0), b(2, 0, 0.5), c(0.3, 1.5, -0.2);
  for (int i = 0; i < 300; ++i) {
    const Vec3 q(rng.uniform(-2, 3), rng.uniform(-2, 3), rng.uniform(-2, 2));
    const Vec3 p = cellform::core::closest_point_on_triangle(q, a, b, c);
    const Vec3 n = (b - a).cross(c - a).normalized();
    REQUIRE(std::abs((p - a).dot(n)) < 1e-12);
    for (int u = 0; u <= 20; ++u)
      for (int w = 0; u + w <= 20; ++w) {
        const Vec3 s = a + (b - a) * (u / 20.0) + (c - a) * (w / 20.0);
        REQUIRE((p - q).norm() <= (s - q).norm() + 1e-12);
      }
  }
  // a degenerate triangle (three points on a line): the closest point of its sides
  const Vec3 d = cellform::core::closest_point_on_triangle(Vec3(1, 1, 0), Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(4, 0, 0));
  CHECK((d - Vec3(1, 0, 0)).norm() < 1e-12);
}
