// Tests that recompute each step of space colonisation from outside, by brute force: the nodes Eq. 1 adds
// for open (nearest node), closed exact (Eq. 2) and Urquhart neighbourhoods, and where closed loops close.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <set>

#include "core/random.h"
#include "tests/venation/eq1_oracle.h"
#include "tests/venation/leaf_fixtures.h"
#include "venation/colonisation.h"

using namespace cellform;
using core::Index;
using core::Vec3;
namespace v = cellform::venation;
using namespace cellform::test;

namespace {

/// `n` sources of `rng` in 0.9 of the ellipse of half-axes a (x) and b (y) centred at (0, b), y from y0 to y1.
void scatter_sources(v::Leaf& leaf, std::size_t n, core::Rng rng, double a, double b, double y0, double y1) {
  while (leaf.initial_sources.size() < n) {
    const double x = rng.uniform(-a, a), y = rng.uniform(y0, y1);
    if ((x / a) * (x / a) + ((y - b) / b) * ((y - b) / b) < 0.9) leaf.initial_sources.push_back({x, y});
  }
}

/// A blade of 120 x 80 with one seed node at its base and 150 fixed sources scattered over it (no darts):
/// the sources wait far from the veins at first, so in closed exact runs most are in lazy mode.
v::Leaf scattered_sources_leaf() {
  v::Leaf leaf = ellipse_leaf(120, 80);
  leaf.initial_nodes = {{0, 2}};
  scatter_sources(leaf, 150, core::Rng(23), 40, 60, 5, 115);
  return leaf;
}

struct OracleCounts {
  std::size_t steps = 0, checked = 0, lazy_source_steps = 0;
};

/// Runs `p` on `leaf` step by step and requires every step's new nodes to be those of Eq. 1 with the
/// sources each node is pulled by (`pulled`, brute force): one node D along the mean direction; towards
/// the nearest pulling source alone where the pulls cancel or the mean retraces a segment; none where
/// that retraces a segment too.
OracleCounts require_brute_force_steps(v::Colonisation& c, const v::ColonisationParams& p, v::testing::Pulled pulled) {
  OracleCounts n;
  while (!c.done() && n.steps < 400) {
    const v::VeinTree before = c.tree();
    const std::vector<Vec3> sources = c.sources();
    const v::testing::Eq1Pulls e = v::testing::eq1_pulls(before.positions, sources, p.kill_distance, pulled);
    n.lazy_source_steps += c.lazy_sources();
    c.step();
    const v::VeinTree after = c.tree();
    std::map<Index, Vec3> grown = v::testing::grown_by_parent(before, after);
    REQUIRE(grown.size() == after.size() - before.size());  // one new node per parent, each from an old node
    for (Index i = static_cast<Index>(before.size()); i < after.size(); ++i) REQUIRE(after.parent[i] < before.size());
    for (Index u = 0; u < before.size(); ++u) {
      INFO("step " << n.steps << ", node " << u);
      if (!e.pulled[u]) {
        REQUIRE(grown.count(u) == 0);
        continue;
      }
      const bool cancel = e.sum[u].norm() <= 1e-9;
      Vec3 q = cancel ? before.positions[u] : Vec3(before.positions[u] + e.sum[u].normalized());
      if (cancel || v::testing::retraces(before, u, q)) {  // towards the nearest source alone
        const Vec3 dir = sources[e.nearest_source[u]] - before.positions[u];
        q = before.positions[u] + dir / dir.norm();
      }
      const bool repeat = v::testing::retraces(before, u, q);  // that retraces a segment too: no new node
      REQUIRE(grown.count(u) == (repeat ? 0u : 1u));
      if (!repeat) {
        REQUIRE((grown[u] - q).norm() < 1e-9);
        ++n.checked;
      }
    }
    ++n.steps;
  }
  CHECK((c.report().finished || c.report().stalled));
  return n;
}
OracleCounts require_brute_force_steps(const v::Leaf& leaf, const v::ColonisationParams& p, v::testing::Pulled pulled) {
  v::Colonisation c(leaf, p);
  return require_brute_force_steps(c, p, pulled);
}

}  // namespace

TEST_CASE("every step follows Eq. 1 by brute force: open, closed exact (lazy sectors) and Urquhart", "[colonisation]") {
  // no darts: the sources are known, so each step's growth can be recomputed from outside
  const v::Leaf leaf = scattered_sources_leaf();
  SECTION("open: each source pulls its nearest node (ties: the smaller index)") {
    v::ColonisationParams p = params(v::VenationType::open, 1);
    p.darts_per_area = 0;
    const OracleCounts n = require_brute_force_steps(leaf, p, v::testing::Pulled::nearest);
    CHECK(n.checked > 300);
  }
  SECTION("closed, exact: Eq. 2, with sources far from the veins in lazy mode until their margins run out") {
    v::ColonisationParams p = params(v::VenationType::closed, 1);
    p.darts_per_area = 0;
    p.threads = 2;
    const OracleCounts n = require_brute_force_steps(leaf, p, v::testing::Pulled::relative);
    INFO("steps " << n.steps << ", source-steps in lazy mode " << n.lazy_source_steps);
    CHECK(n.checked > 500);
    CHECK(n.lazy_source_steps > 1000);
  }
  SECTION("closed, Urquhart: the Delaunay neighbours that no other Delaunay neighbour excludes") {
    v::ColonisationParams p = params(v::VenationType::closed, 1);
    p.darts_per_area = 0;
    p.neighbourhood = v::Neighbourhood::urquhart;
    const OracleCounts n = require_brute_force_steps(leaf, p, v::testing::Pulled::urquhart);
    CHECK(n.checked > 500);
  }
}

TEST_CASE("Urquhart's window grows with a blade grown nonuniformly", "[colonisation]") {
  // (review of venation/: the window around each source was sized by the initial blade under nonuniform
  // growth, so sources left far from the veins by a blade grown 28 times pulled nothing.) A 10 x 5 blade
  // with 40 fixed sources grows 1.25 times a step for 15 steps, with the veins still at its base; from then
  // on every step must follow Eq. 1 with the Urquhart neighbours by brute force.
  v::Leaf leaf = ellipse_leaf(10, 5);
  leaf.initial_nodes = {{0, 0.2}};
  scatter_sources(leaf, 40, core::Rng(5), 2.5, 5, 1, 10);
  v::ColonisationParams p = params(v::VenationType::closed, 1);
  p.darts_per_area = 0;
  p.neighbourhood = v::Neighbourhood::urquhart;
  p.growth = v::GrowthMode::nonuniform;
  p.growth_x = p.growth_y = {{0, 10}, {1.25, 1.25}};
  p.growth_steps = 15;
  v::Colonisation c(leaf, p);
  for (int t = 0; t < 15; ++t) c.step();
  const v::Outline grown = c.outline();
  double top = 0;
  for (const v::Vec2& q : grown.points) top = std::max(top, q.y());
  REQUIRE(top > 250);  // grown some 28 times
  const OracleCounts n = require_brute_force_steps(c, p, v::testing::Pulled::urquhart);
  CHECK(n.checked > 300);
}

TEST_CASE("closed loops close at a source that veins from two sides reached", "[colonisation]") {
  // fixed sources, stepped by hand: every closing edge a step adds joins two nodes within d_k of a source
  // that step removed (the veins met at the source they shared), and not two tips that merely came close
  for (v::Neighbourhood nb : {v::Neighbourhood::exact, v::Neighbourhood::urquhart}) {
    INFO("neighbourhood " << static_cast<int>(nb));
    v::ColonisationParams p = params(v::VenationType::closed, 2);
    p.darts_per_area = 0;
    p.neighbourhood = nb;
    v::Colonisation c(scattered_sources_leaf(), p);
    std::size_t loops = 0;
    while (!c.done()) {
      const std::vector<Vec3> before = c.sources();
      const std::size_t closed = c.tree().anastomoses.size();
      c.step();
      const std::vector<Vec3> after_sources = c.sources();
      const std::set<std::array<double, 2>> alive = [&] {
        std::set<std::array<double, 2>> a;
        for (const Vec3& q : after_sources) a.insert({q.x(), q.y()});
        return a;
      }();
      std::vector<Vec3> removed;
      for (const Vec3& q : before)
        if (!alive.count({q.x(), q.y()})) removed.push_back(q);
      const v::VeinTree t = c.tree();
      for (std::size_t k = closed; k < t.anastomoses.size(); ++k) {
        const auto [a, b] = t.anastomoses[k];
        bool shared = false;
        for (const Vec3& s : removed)
          shared |= (t.positions[a] - s).norm() < p.kill_distance && (t.positions[b] - s).norm() < p.kill_distance;
        INFO("step " << c.report().steps << ", loop " << k << " joins " << a << " and " << b);
        CHECK(shared);
        CHECK(t.parent[a] != b);
        CHECK(t.parent[b] != a);
      }
      loops = t.anastomoses.size();
    }
    CHECK(loops >= 5);
  }
}
