// Tests of the vein-node k-d tree: nearest, relative (Eq. 2), Delaunay and Urquhart neighbourhoods vs oracles.
#include "venation/point_tree.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/random.h"

using namespace cellform;
using core::Index;
using core::Vec3;
using venation::PointTree;

namespace {

std::vector<Vec3> random_points(std::uint64_t seed, int n, bool three_d, double spread = 10) {
  core::Rng rng(seed);
  std::vector<Vec3> p;
  for (int i = 0; i < n; ++i)
    p.emplace_back(rng.uniform(0, spread), rng.uniform(0, spread), three_d ? rng.uniform(0, spread) : 0.0);
  return p;
}

/// Points along a wiggly curve with unit spacing, like a vein (near-collinear runs stress the pruning).
std::vector<Vec3> vein_like(int n) {
  std::vector<Vec3> p;
  for (int i = 0; i < n; ++i) p.emplace_back(0.5 * i, 3 * std::sin(0.05 * i) + (i % 7 == 0 ? 0.3 : 0.0), 0.0);
  return p;
}

PointTree build(const std::vector<Vec3>& pts) {
  PointTree t;
  for (const Vec3& q : pts) t.insert(q);
  return t;
}

/// Brute-force Delaunay neighbourhood of s in the plane: v is one iff the part of the s-v bisector
/// closer to s than to every other point has positive length (a Voronoi edge exists).
std::vector<Index> delaunay_brute_force(const std::vector<Vec3>& pts, const Vec3& s) {
  std::vector<Index> out;
  for (Index v = 0; v < pts.size(); ++v) {
    const Eigen::Vector2d S(s.x(), s.y()), V(pts[v].x(), pts[v].y());
    if ((V - S).norm() == 0) continue;
    const Eigen::Vector2d m = 0.5 * (S + V), d((V - S).y() * -1, (V - S).x());
    double lo = -1e300, hi = 1e300;
    for (Index u = 0; u < pts.size(); ++u) {
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

}  // namespace

TEST_CASE("nearest equals a brute-force scan, ties by index", "[point_tree]") {
  auto pts = random_points(7, 500, false);
  pts.push_back(pts[10]);  // an exact duplicate: the smaller index must win
  const PointTree t = build(pts);
  core::Rng rng(99);
  for (int q = 0; q < 200; ++q) {
    const Vec3 s = q == 0 ? pts[10] : Vec3(rng.uniform(-2, 12), rng.uniform(-2, 12), 0);
    Index best = core::kNoIndex;
    double d2 = 0;
    REQUIRE(t.nearest(s, best, d2));
    Index bb = 0;
    for (Index i = 1; i < pts.size(); ++i)
      if ((pts[i] - s).squaredNorm() < (pts[bb] - s).squaredNorm()) bb = i;
    CHECK(best == bb);
  }
}

TEST_CASE("exact relative neighbourhood equals brute-force Eq. 2", "[point_tree]") {
  for (std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    for (bool three_d : {false, true}) {
      const auto pts = random_points(seed, 300, three_d);
      const PointTree t = build(pts);
      PointTree::Scratch sc;
      std::vector<Index> got;
      core::Rng rng(seed * 31);
      for (int q = 0; q < 60; ++q) {
        // queries inside, on the border and far outside the cloud
        const double lo = q < 40 ? 0 : -30, hi = q < 40 ? 10 : 40;
        const Vec3 s(rng.uniform(lo, hi), rng.uniform(lo, hi), three_d ? rng.uniform(lo, hi) : 0.0);
        t.relative_neighbourhood(s, got, sc);
        INFO("seed " << seed << " 3d " << three_d << " query " << q);
        CHECK(got == venation::relative_neighbourhood_brute_force(pts, s));
        CHECK(!got.empty());
      }
    }
  }
}

TEST_CASE("exact relative neighbourhood on vein-like near-collinear nodes", "[point_tree]") {
  const auto pts = vein_like(400);
  const PointTree t = build(pts);
  PointTree::Scratch sc;
  std::vector<Index> got;
  core::Rng rng(5);
  for (int q = 0; q < 100; ++q) {
    const Vec3 s(rng.uniform(-10, 210), rng.uniform(-20, 20), 0);
    t.relative_neighbourhood(s, got, sc);
    CHECK(got == venation::relative_neighbourhood_brute_force(pts, s));
  }
}

TEST_CASE("Delaunay neighbourhood matches the Voronoi-edge oracle; RN within Urquhart within Delaunay",
          "[point_tree]") {
  for (std::uint64_t seed : {11u, 12u, 13u}) {
    const auto pts = random_points(seed, 200, false);
    const PointTree t = build(pts);
    PointTree::Scratch sc;
    std::vector<Index> dn, ur, rn;
    core::Rng rng(seed);
    for (int q = 0; q < 50; ++q) {
      const Vec3 s(rng.uniform(1, 9), rng.uniform(1, 9), 0);
      t.delaunay_neighbourhood(s, 1e4, dn, sc);
      t.urquhart_neighbourhood(s, 1e4, ur, sc);
      t.relative_neighbourhood(s, rn, sc);
      CHECK(dn == delaunay_brute_force(pts, s));
      CHECK(std::includes(dn.begin(), dn.end(), ur.begin(), ur.end()));
      CHECK(std::includes(ur.begin(), ur.end(), rn.begin(), rn.end()));
    }
  }
}

TEST_CASE("Figure 8: Urquhart keeps v that a non-Delaunay neighbour a excludes", "[point_tree]") {
  // s = origin; v = (1, 0); a lies in the lune of s and v but w1, w2 cut it off from the Voronoi cell of s
  const Vec3 s(0, 0, 0);
  const std::vector<Vec3> pts{{1, 0, 0}, {0.5, 0.8, 0}, {0.1, 0.55, 0}, {0.9, 0.55, 0}};
  const Index v = 0, a = 1, w1 = 2;
  const PointTree t = build(pts);
  PointTree::Scratch sc;
  std::vector<Index> dn, ur, rn;
  t.delaunay_neighbourhood(s, 100, dn, sc);
  t.urquhart_neighbourhood(s, 100, ur, sc);
  t.relative_neighbourhood(s, rn, sc);
  CHECK(dn == delaunay_brute_force(pts, s));
  CHECK(std::find(dn.begin(), dn.end(), a) == dn.end());  // a is not a Delaunay neighbour of s
  CHECK(std::find(ur.begin(), ur.end(), v) != ur.end());  // so Urquhart keeps v ...
  CHECK(std::find(rn.begin(), rn.end(), v) == rn.end());  // ... which Eq. 2 excludes (a is in the lune)
  CHECK(rn == venation::relative_neighbourhood_brute_force(pts, s));
  // where no such point exists they agree: w1 is in both
  CHECK(std::find(ur.begin(), ur.end(), w1) != ur.end());
  CHECK(std::find(rn.begin(), rn.end(), w1) != rn.end());
}

TEST_CASE("lune and radius queries", "[point_tree]") {
  const auto pts = random_points(21, 300, true);
  const PointTree t = build(pts);
  core::Rng rng(3);
  for (int q = 0; q < 100; ++q) {
    const Vec3 s(rng.uniform(0, 10), rng.uniform(0, 10), rng.uniform(0, 10));
    const double r2 = rng.uniform(0, 4);
    bool any = false;
    for (const Vec3& p : pts) any = any || (p - s).squaredNorm() <= r2;
    CHECK(t.any_within(s, r2) == any);
    std::vector<Index> w;
    t.within(s, r2, w);
    CHECK(w.size() == static_cast<std::size_t>(std::count_if(
                          pts.begin(), pts.end(), [&](const Vec3& p) { return (p - s).squaredNorm() <= r2; })));
  }
}
