// Tests of venation/colonisation_impl.h's pure pieces: the lazy-mode margin bound against brute force.
#include "venation/colonisation_impl.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "core/random.h"

using namespace cellform;
using core::Vec3;
namespace v = cellform::venation;

TEST_CASE("the lazy-mode margin bound holds after any step the model allows, and is nearly attained",
          "[colonisation]") {
  // Brute force: a source s, its nearest node a, other nodes all nearer a than s by their margin; a step
  // places a node D from some of them (random directions, and the ones that cut the margin most);
  // the new nearest a' and the true new margin must stay above lazy_slack_after's bound.
  core::Rng rng(11);
  const double D = 1;
  const Vec3 s = Vec3::Zero();
  auto unit = [](const Vec3& x) { return Vec3(x / x.norm()); };
  double closest = std::numeric_limits<double>::infinity();  // least (true margin - bound) seen
  int trials = 0;
  while (trials < 200000) {
    const double r = rng.uniform(2, 42), th = rng.uniform(0, 2 * M_PI);
    const Vec3 a(r * std::cos(th), r * std::sin(th), 0);
    std::vector<Vec3> nodes{a};
    double slack = std::numeric_limits<double>::infinity();  // the true margin: the tightest valid bound
    for (int i = 0, k = 1 + static_cast<int>(rng.next() % 10); i < k; ++i) {
      const double rr = rng.uniform() * std::min(r, 6.0) * (rng.uniform() < 0.5 ? 1 : 3), ph = rng.uniform(0, 2 * M_PI);
      const Vec3 v = a + Vec3(rr * std::cos(ph), rr * std::sin(ph), 0);
      const double m = (v - s).norm() - (v - a).norm();
      if (!(m > 0)) continue;  // lazy mode holds only while every other node is on a's side
      nodes.push_back(v);
      slack = std::min(slack, m);
    }
    if (nodes.size() < 2) continue;
    ++trials;
    const std::size_t old = nodes.size();
    for (std::size_t i = 0; i < old; ++i) {
      if (rng.uniform() < 0.3) continue;  // not every node grows
      const Vec3 v = nodes[i];
      Vec3 dir;
      switch (rng.next() % 4) {
        case 0:
          dir = unit(Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 0));
          break;
        case 1:
          dir = unit(s - v);
          break;  // straight at the source
        case 2:
          dir = i ? unit(unit(s - v) - unit(a - v)) : unit(s - v);
          break;  // down the margin's slope
        default:
          dir = i ? unit(unit(v - a) + Vec3(rng.uniform(-.5, .5), rng.uniform(-.5, .5), 0)) : unit(s - v);
      }
      if (dir.allFinite()) nodes.push_back(v + D * dir);
    }
    std::size_t n = 0;  // the new nearest a'
    for (std::size_t i = 1; i < nodes.size(); ++i)
      if ((nodes[i] - s).norm() < (nodes[n] - s).norm()) n = i;
    double margin = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (i != n) margin = std::min(margin, (nodes[i] - s).norm() - (nodes[i] - nodes[n]).norm());
    const double bound = v::detail::lazy_slack_after(slack, (nodes[n] - s).norm(), D, (nodes[n] - a).norm(), 0);
    REQUIRE(margin >= bound - 1e-9);
    closest = std::min(closest, margin - bound);
  }
  // the trials come within a segment of the bound: a bound looser by a whole D (2 D -> D, or the
  // anchor's move left out) fails them
  CHECK(closest < 0.9 * D);
}

TEST_CASE("the source grid answers exactly for any cell size, 1e-300 and 1e300 included", "[colonisation]") {
  // cells so small that floor(x / cell) leaves the range of a long (it overflowed: undefined behaviour)
  // or so large that every source shares one cell: any_within must still equal brute force
  core::Rng rng(5);
  for (const double cell : {1e-300, 1e-12, 0.7, 1e300}) {
    v::detail::SourceGrid grid;
    grid.reset(cell);
    std::vector<Vec3> pos;
    for (int i = 0; i < 200; ++i) {
      pos.emplace_back(rng.uniform(-20, 20), rng.uniform(-20, 20), i % 2 ? 0.0 : rng.uniform(-1e6, 1e6));
      grid.insert(static_cast<core::Index>(i), pos.back());
    }
    for (int i = 0; i < 100; i += 3) grid.erase(static_cast<core::Index>(i), pos[static_cast<std::size_t>(i)]);
    for (int q = 0; q < 500; ++q) {
      const Vec3 p(rng.uniform(-20, 20), rng.uniform(-20, 20), q % 2 ? 0.0 : rng.uniform(-1e6, 1e6));
      const double r = std::min(cell, rng.uniform(0, 3));
      bool brute = false;
      for (std::size_t i = 0; i < pos.size(); ++i)
        brute |= (i >= 100 || i % 3 != 0) && (pos[i] - p).squaredNorm() <= r * r;
      CHECK(grid.any_within(p, r * r, pos) == brute);
    }
  }
}

TEST_CASE("the nodes that reached a source are joined wherever they lie within reach, once", "[colonisation]") {
  using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;
  const double reach = 3;
  // all near the first: a star from it, as before
  CHECK(v::detail::closing_pairs({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}, reach) == Pairs{{0, 1}, {0, 2}});
  // the first far from two that lie near each other (d_k = 2: the audit's case, left apart before)
  CHECK(v::detail::closing_pairs({{-2, 0, 0}, {1.5, 1.3, 0}, {1.5, -1.3, 0}}, reach) == Pairs{{1, 2}});
  // a chain: joined along it, and a triangle within reach gets no third edge
  CHECK(v::detail::closing_pairs({{0, 0, 0}, {2.5, 0, 0}, {5, 0, 0}}, reach) == Pairs{{0, 1}, {1, 2}});
  CHECK(v::detail::closing_pairs({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {9, 9, 0}}, reach) == Pairs{{0, 1}, {0, 2}});
  // the result is a forest: never more pairs than nodes - 1, on random sets
  cellform::core::Rng rng(3);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<Vec3> at(2 + rng.next() % 6);
    for (Vec3& p : at) p = Vec3(rng.uniform(-4, 4), rng.uniform(-4, 4), 0);
    const Pairs pairs = v::detail::closing_pairs(at, reach);
    CHECK(pairs.size() < at.size());
    for (const auto& [j, i] : pairs) CHECK((at[i] - at[j]).norm() <= reach);
    // and every pair within reach ends up joined: a component search over the pairs
    std::vector<std::size_t> comp(at.size());
    for (std::size_t k = 0; k < at.size(); ++k) comp[k] = k;
    for (bool again = true; again;) {
      again = false;
      for (const auto& [j, i] : pairs)
        if (comp[i] != comp[j]) comp[i] = comp[j] = std::min(comp[i], comp[j]), again = true;
    }
    for (std::size_t i = 0; i < at.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if ((at[i] - at[j]).norm() <= reach) CHECK(comp[i] == comp[j]);
  }
}
