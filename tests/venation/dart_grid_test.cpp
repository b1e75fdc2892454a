// Tests of the witness grid of the dart b_v test: it only ever proves "a node within r", never wrongly,
// and with cells of at most r / sqrt 2 it proves it for every dart whose cell holds a node.
#include "venation/dart_grid.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "core/random.h"

using namespace cellform;
using core::Index;
using core::Vec3;
using venation::WitnessGrid;

namespace {

bool brute_within(const std::vector<Vec3>& pts, const Vec3& q, double r2) {
  for (const Vec3& p : pts)
    if ((p - q).squaredNorm() <= r2) return true;
  return false;
}

}  // namespace

TEST_CASE("witness grid: a witness is always a real node within r (vs brute force)") {
  core::Rng rng(7);
  std::vector<Vec3> pts;
  for (int i = 0; i < 400; ++i) pts.emplace_back(rng.uniform(0, 50), rng.uniform(0, 40), 0.0);
  for (double r : {0.5, 2.0, 6.0}) {
    for (double cell_factor : {0.3, 0.7, 2.5}) {  // fine, covering and coarse cells: all exact
      WitnessGrid g;
      g.reset(Vec3(-1, -1, 0), Vec3(51, 41, 0), cell_factor * r, 1 << 20);
      for (Index i = 0; i < pts.size(); ++i) g.insert(i, pts[i]);
      int proved = 0;
      for (int k = 0; k < 3000; ++k) {
        const Vec3 q(rng.uniform(-5, 55), rng.uniform(-5, 45), 0.0);
        const bool w = g.witness(q, r * r, pts), b = brute_within(pts, q, r * r);
        if (w) REQUIRE(b);  // never a false "too near"
        proved += w;
      }
      CHECK(proved > 0);
    }
  }
}

TEST_CASE("witness grid: with cells of at most r / sqrt 2 a node in the dart's own cell settles it") {
  core::Rng rng(3);
  const double r = 1.0;
  WitnessGrid g;
  g.reset(Vec3(0, 0, 0), Vec3(20, 20, 0), 0.7 * r, 1 << 20);
  std::vector<Vec3> pts;
  for (int i = 0; i < 50; ++i) {
    pts.emplace_back(rng.uniform(0, 20), rng.uniform(0, 20), 0.0);
    g.insert(static_cast<Index>(i), pts.back());
  }
  const double c = g.cell();
  REQUIRE(c <= r / std::sqrt(2.0));
  for (const Vec3& p : pts) {  // darts in the cell of each node
    const double x0 = std::floor(p.x() / c) * c, y0 = std::floor(p.y() / c) * c;
    for (int k = 0; k < 20; ++k) {
      const Vec3 q(x0 + rng.uniform(0, 0.999) * c, y0 + rng.uniform(0, 0.999) * c, 0.0);
      CHECK(g.witness(q, r * r, pts));
    }
  }
}

TEST_CASE("witness grid: the map of covered cells settles a dart alone only for radii of at least its own") {
  core::Rng rng(11);
  std::vector<Vec3> pts;
  for (int i = 0; i < 300; ++i) pts.emplace_back(rng.uniform(0, 30), rng.uniform(0, 30), 0.0);
  const double cover = 2.0;
  WitnessGrid g;
  g.reset(Vec3(-1, -1, 0), Vec3(31, 31, 0), 0.7 * cover, 1 << 20, cover);
  for (Index i = 0; i < pts.size(); ++i) g.insert(i, pts[i]);
  CHECK(g.covers_radius(cover * cover));
  CHECK(g.covers_radius(std::pow(std::sqrt(cover * cover * (1 - 1e-15)), 2)));  // a radius rounded on the way
  CHECK_FALSE(g.covers_radius(cover * cover * (1 - 1e-6)));
  // darts everywhere, and at the corners of every cell (the points of a cell farthest from a node)
  std::vector<Vec3> darts;
  for (int k = 0; k < 20000; ++k) darts.emplace_back(rng.uniform(-2, 32), rng.uniform(-2, 32), 0.0);
  const double c = g.cell();
  for (int y = 0; y < 23; ++y)
    for (int x = 0; x < 23; ++x)
      for (const double e : {1e-9, 1 - 1e-9}) darts.emplace_back(-1 + (x + e) * c, -1 + (y + e) * c, 0.0);
  for (const double r : {0.5 * cover, 0.999999 * cover, cover, 1.3 * cover}) {
    INFO("r = " << r);
    int proved = 0, within = 0;
    for (const Vec3& q : darts) {
      const bool w = g.witness(q, r * r, pts), b = brute_within(pts, q, r * r);
      if (w) REQUIRE(b);  // never a false "too near"
      proved += w;
      within += b;
    }
    CHECK(proved > 0.9 * within);  // most darts near a node are settled by the grid
  }
  // a dart 1.9 from its only node, in a cell the node's disc of radius 2 covers: the map settles it for r = 2,
  // and for r = 1.95 the node's own distance does; off the plane, the node alone decides
  const std::vector<Vec3> one{Vec3(0.05, 0.05, 0)};
  WitnessGrid h;
  h.reset(Vec3(0, 0, 0), Vec3(10, 10, 0), 0.7 * cover, 1 << 20, cover);
  h.insert(0, one[0]);
  const Vec3 q(0.05 + 1.9 / std::sqrt(2.0), 0.05 + 1.9 / std::sqrt(2.0), 0);
  CHECK(h.witness(q, 4.0, one));
  // only the map knows it once the node is read elsewhere: the grid's answer comes from the bit alone
  const std::vector<Vec3> moved{Vec3(1e3, 1e3, 0)};
  CHECK(h.witness(q, 4.0, moved));
  CHECK_FALSE(h.witness(q, 1.95 * 1.95, moved));  // below the map's radius: the (moved) node decides
  CHECK(h.witness(q, 1.95 * 1.95, one));
  CHECK_FALSE(h.witness(q, 1.85 * 1.85, one));
  CHECK_FALSE(h.witness(q + Vec3(0, 0, 1), 4.0, one));
  // a grid whose cells are too fine for its coordinates keeps no map
  WitnessGrid off;
  off.reset(Vec3(1e9, 0, 0), Vec3(1e9 + 10, 10, 0), 1.0, 1 << 20, 2.0);
  CHECK_FALSE(off.covers_radius(100.0));
}

TEST_CASE("witness grid: outside the box, off the plane, cleared or over budget it only defers to the tree") {
  std::vector<Vec3> pts{Vec3(1, 1, 0), Vec3(30, 30, 0), Vec3(2, 2, 1)};
  WitnessGrid g;
  g.reset(Vec3(0, 0, 0), Vec3(10, 10, 0), 1.0, 1 << 20);
  for (Index i = 0; i < pts.size(); ++i) g.insert(i, pts[i]);
  CHECK(g.witness(Vec3(1.2, 1.2, 0), 1.0, pts));
  CHECK_FALSE(g.witness(Vec3(30, 30, 0), 1.0, pts));  // node outside the box was not kept
  CHECK_FALSE(g.witness(Vec3(2, 2, 1), 0.01, pts));   // node off the plane was not kept
  CHECK(g.covers(Vec3(1, 1, 0), Vec3(9, 9, 0)));
  CHECK_FALSE(g.covers(Vec3(1, 1, 0), Vec3(11, 9, 0)));
  // a budget of 4 cells coarsens the cells instead of allocating 100
  WitnessGrid small;
  small.reset(Vec3(0, 0, 0), Vec3(10, 10, 0), 1.0, 4);
  CHECK(small.cell() >= 5.0);
  small.insert(0, pts[0]);
  CHECK(small.witness(Vec3(1.5, 1.5, 0), 1.0, pts));
  g.clear();
  CHECK(g.empty());
  CHECK_FALSE(g.witness(Vec3(1.2, 1.2, 0), 1.0, pts));
  CHECK_FALSE(g.covers(Vec3(1, 1, 0), Vec3(9, 9, 0)));
}

TEST_CASE("witness grid: absurd cell sizes coarsen or give no grid, never overflow") {
  std::vector<Vec3> pts{Vec3(1, 1, 0)};
  WitnessGrid g;
  g.reset(Vec3(0, 0, 0), Vec3(30, 5, 0), 1e-18, 1 << 20);  // 3e19 cells wide: more than a long counts
  REQUIRE_FALSE(g.empty());
  CHECK(g.cell() > 1e-3);  // coarsened to the budget of 2^20 cells
  g.insert(0, pts[0]);
  CHECK(g.witness(Vec3(1.001, 1, 0), 1.0, pts));
  for (double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    WitnessGrid h;
    h.reset(Vec3(0, 0, 0), Vec3(30, 5, 0), bad, 1 << 20);
    CHECK(h.empty());
    h.insert(0, pts[0]);
    CHECK_FALSE(h.witness(Vec3(1, 1, 0), 1.0, pts));  // defers to the tree
  }
  WitnessGrid inf_box;
  inf_box.reset(Vec3(0, 0, 0), Vec3(std::numeric_limits<double>::infinity(), 5, 0), 1.0, 1 << 20);
  CHECK(inf_box.empty());
}
