// Tests of the plotter's stroke order: the greedy nearest-next order by brute force, and what it saves.
#include "venation/plot_order.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <set>
#include <tuple>

#include "core/random.h"

using namespace cellform;
using venation::PlotStep;
using venation::Vec2;

namespace {

/// The same rule by brute force: every undrawn end, nearest first, then the smaller stroke, then end 0.
std::vector<PlotStep> brute_order(const std::vector<std::array<Vec2, 2>>& ends, Vec2 pen) {
  std::vector<PlotStep> order;
  std::vector<char> drawn(ends.size(), 0);
  for (std::size_t k = 0; k < ends.size(); ++k) {
    std::tuple<double, std::size_t, int> best{std::numeric_limits<double>::infinity(), 0, 0};
    for (std::size_t s = 0; s < ends.size(); ++s)
      for (int w = 0; w < 2; ++w)
        if (!drawn[s])
          best = std::min(best, std::tuple<double, std::size_t, int>{(ends[s][w] - pen).squaredNorm(), s, w});
    const auto [d2, s, w] = best;
    drawn[s] = 1;
    order.push_back({s, w == 1});
    pen = ends[s][1 - w];
  }
  return order;
}

double travel(const std::vector<std::array<Vec2, 2>>& ends, const std::vector<PlotStep>& order, Vec2 pen) {
  double t = 0;
  for (const PlotStep& p : order) {
    t += (ends[p.stroke][p.reversed ? 1 : 0] - pen).norm();
    pen = ends[p.stroke][p.reversed ? 0 : 1];
  }
  return t;
}

}  // namespace

TEST_CASE("plot order is the greedy nearest-next order (brute force), reversals included", "[plot_order]") {
  for (std::uint64_t seed : {1, 2, 3, 4}) {
    core::Rng rng(seed);
    std::vector<std::array<Vec2, 2>> ends;
    const std::size_t n = seed == 4 ? 3000 : 400;
    for (std::size_t i = 0; i < n; ++i) {
      // clustered strokes of random lengths, some on a coarse lattice so that distances tie
      const Vec2 a = seed == 3 ? Vec2(std::floor(rng.uniform(0, 20)), std::floor(rng.uniform(0, 5)))
                               : Vec2(rng.uniform(0, 100) * (i % 3 == 0 ? 0.1 : 1), rng.uniform(0, 60));
      const Vec2 b = a + Vec2(rng.uniform(-3, 3), rng.uniform(-3, 3));
      ends.push_back({a, b});
    }
    const Vec2 start(-10, 70);  // outside the strokes' box, as a plotter's home corner
    const auto fast = venation::plot_order(ends, start);
    const auto slow = brute_order(ends, start);
    REQUIRE(fast.size() == n);
    std::set<std::size_t> seen;
    for (std::size_t k = 0; k < n; ++k) {
      INFO("seed " << seed << " step " << k);
      REQUIRE(fast[k].stroke == slow[k].stroke);
      REQUIRE(fast[k].reversed == slow[k].reversed);
      seen.insert(fast[k].stroke);
    }
    CHECK(seen.size() == n);  // every stroke once
    std::vector<PlotStep> given;
    for (std::size_t s = 0; s < n; ++s) given.push_back({s, false});
    CHECK(travel(ends, fast, start) < 0.25 * travel(ends, given, start));
  }
  CHECK(venation::plot_order({}, Vec2(0, 0)).empty());
  // all ends on one line (a flat box): the same order, and not a grid of 1e-300-wide cells to walk
  std::vector<std::array<Vec2, 2>> line;
  core::Rng rng(9);
  for (int i = 0; i < 2000; ++i) {
    const double a = rng.uniform(0, 1000);
    line.push_back({Vec2(a, 3), Vec2(a + rng.uniform(-2, 2), 3)});
  }
  line.push_back({Vec2(0, 3), Vec2(1, 3)});
  line.push_back({Vec2(100, 3), Vec2(101, 3)});
  for (const Vec2& pen : {Vec2(0, 3), Vec2(-50, 40), Vec2(2000, -1e6)}) {
    const auto fast = venation::plot_order(line, pen), slow = brute_order(line, pen);
    REQUIRE(fast.size() == slow.size());
    for (std::size_t k = 0; k < fast.size(); ++k)
      REQUIRE((fast[k].stroke == slow[k].stroke && fast[k].reversed == slow[k].reversed));
  }
  // an end that is not a number: every stroke still comes once, that one last
  std::vector<std::array<Vec2, 2>> odd{
      {Vec2(0, 0), Vec2(1, 0)}, {Vec2(std::nan(""), 0), Vec2(2, 0)}, {Vec2(3, 0), Vec2(4, 0)}};
  odd[1][1] = Vec2(std::nan(""), std::nan(""));
  const auto o3 = venation::plot_order(odd, Vec2(0, 0));
  REQUIRE(o3.size() == 3);
  CHECK(o3[0].stroke == 0);
  CHECK(o3[1].stroke == 2);
  CHECK(o3[2].stroke == 1);
  // all ends at one point: ties by stroke index
  const std::vector<std::array<Vec2, 2>> same(5, {Vec2(1, 1), Vec2(1, 1)});
  const auto o = venation::plot_order(same, Vec2(0, 0));
  for (std::size_t k = 0; k < 5; ++k) CHECK(o[k].stroke == k);
}
