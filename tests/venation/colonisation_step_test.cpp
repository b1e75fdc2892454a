// Tests of the rules of a space-colonisation step (venation/colonisation.cpp) against hand-worked cases and
// a brute-force oracle: pulls that cancel, the kill distance, the tags of closed sources, Urquhart's neighbours
// (ties across a sector boundary: the mirror-image test in colonisation_test.cpp).
#include "venation/colonisation.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <set>

#include "core/random.h"
#include "tests/venation/eq1_oracle.h"
#include "tests/venation/leaf_fixtures.h"
#include "venation/domain.h"

using namespace cellform;
using core::Index;
using core::Vec3;
namespace v = cellform::venation;
using namespace cellform::test;

namespace {

// a source's position as a map key (sources keep their coordinates exactly)
struct Key {
  double x, y;
  bool operator<(const Key& o) const { return x < o.x || (x == o.x && y < o.y); }
  bool operator==(const Key& o) const { return x == o.x && y == o.y; }
};

}  // namespace

TEST_CASE("pulls that nearly cancel (|sum| < 1e-9) grow towards the nearest source", "[colonisation]") {
  v::Leaf leaf = ellipse_leaf(20, 20);
  leaf.initial_nodes = {{0, 10}};
  // unit pulls sum to (0, 1.7e-12); the nearer source is listed second, so neither the first nor the last wins
  leaf.initial_sources = {{6, 10 + 1e-11}, {-5, 10}};
  for (v::VenationType type : {v::VenationType::open, v::VenationType::closed}) {
    v::ColonisationParams p = params(type, 1);
    p.darts_per_area = 0;
    v::Colonisation c(leaf, p);
    c.step();
    const v::VeinTree t = c.tree();
    REQUIRE(t.size() == 2);
    CHECK(t.positions[1].x() == -1);
    CHECK(t.positions[1].y() == 10);
  }
}

TEST_CASE("an open source exactly d_k from a node is not yet reached (|v - s| < d_k)", "[colonisation]") {
  v::Leaf leaf = ellipse_leaf(20, 20);
  leaf.initial_nodes = {{0, 5}};
  leaf.initial_sources = {{0, 8}};
  v::ColonisationParams p = params(v::VenationType::open, 1);
  p.darts_per_area = 0;
  v::Colonisation c(leaf, p);
  c.step();
  c.step();  // node (0, 7): exactly d_k = 1 from the source
  CHECK(c.sources().size() == 1);
  c.run();
  CHECK(c.tree().size() == 4);
}

TEST_CASE("closed sources go when every tagged vein reached them or left their neighbourhood", "[colonisation]") {
  // brute-force oracle of the tags (Section 3.2): a source reached first tags the veins of V(s) (or their
  // new node) that did not reach it; a tag passes to the node a tagged vein grows while s still pulls it,
  // and goes when s no longer does; s goes when no tag is left.
  v::Leaf leaf = ellipse_leaf(120, 80);
  leaf.initial_nodes = {{0, 2}};
  core::Rng rng(23);
  while (leaf.initial_sources.size() < 150) {
    const double x = rng.uniform(-40, 40), y = rng.uniform(5, 115);
    if ((x / 40) * (x / 40) + ((y - 60) / 60) * ((y - 60) / 60) < 0.9) leaf.initial_sources.push_back({x, y});
  }
  for (double dk : {1.0, 2.0}) {
    v::ColonisationParams p = params(v::VenationType::closed, dk);
    p.darts_per_area = 0;
    v::Colonisation c(leaf, p);
    std::map<Key, std::vector<Index>> tags;  // tagged sources
    std::size_t steps = 0, passed = 0;
    while (!c.done() && steps < 600) {
      const v::VeinTree before = c.tree();
      const std::vector<Vec3> src = c.sources();
      std::vector<std::vector<Index>> infl(src.size());
      for (std::size_t k = 0; k < src.size(); ++k)
        for (Index u : v::testing::relative_neighbourhood_brute_force(before.positions, src[k]))
          if ((before.positions[u] - src[k]).squaredNorm() >= dk * dk) infl[k].push_back(u);
      c.step();
      const v::VeinTree after = c.tree();
      std::map<Index, Index> child;
      for (Index i = static_cast<Index>(before.size()); i < after.size(); ++i) child[after.parent[i]] = i;
      auto reached = [&](Index t, const Vec3& s) { return (after.positions[t] - s).squaredNorm() < dk * dk; };
      std::set<Key> expect_alive;
      for (std::size_t k = 0; k < src.size(); ++k) {
        const Vec3& s = src[k];
        const Key key{s.x(), s.y()};
        bool gone = false;
        if (auto it = tags.find(key); it != tags.end()) {
          std::vector<Index> next;
          for (Index t : it->second) {
            if (reached(t, s)) continue;
            const bool pulls = std::find(infl[k].begin(), infl[k].end(), t) != infl[k].end();
            if (pulls && child.count(t)) {
              ++passed;
              if (!reached(child[t], s)) next.push_back(child[t]);
            }
          }
          it->second = next;
          gone = next.empty();
        } else {
          double nd2 = 1e300;
          for (const Vec3& q : after.positions) nd2 = std::min(nd2, (q - s).squaredNorm());
          if (nd2 < dk * dk) {
            std::vector<Index> T;
            for (Index u : infl[k]) {
              const Index t = child.count(u) ? child[u] : u;
              if (!reached(t, s)) T.push_back(t);
            }
            gone = T.empty();
            tags[key] = T;
          }
        }
        if (!gone) expect_alive.insert(key);
      }
      std::set<Key> alive;
      for (const Vec3& s : c.sources()) alive.insert({s.x(), s.y()});
      INFO("d_k " << dk << " step " << steps + 1);
      REQUIRE(alive == expect_alive);
      ++steps;
    }
    INFO("tags passed " << passed);
    CHECK(passed > 20);
    CHECK((c.report().finished || c.report().stalled));
  }
}

TEST_CASE("a source between a near and a far vein pulls both (Urquhart and exact)", "[colonisation]") {
  v::Leaf leaf = ellipse_leaf(100, 100);
  leaf.initial_nodes = {{-1, 50}, {3, 50}};  // B at 3 is a Delaunay, Urquhart and relative neighbour of s
  leaf.initial_sources = {{0, 50}};
  for (v::Neighbourhood nb : {v::Neighbourhood::exact, v::Neighbourhood::urquhart}) {
    v::ColonisationParams p = params(v::VenationType::closed, 0.5);
    p.darts_per_area = 0;
    p.neighbourhood = nb;
    v::Colonisation c(leaf, p);
    c.step();
    const v::VeinTree t = c.tree();
    INFO("neighbourhood " << static_cast<int>(nb));
    REQUIRE(t.size() == 4);
    CHECK(t.positions[3] == Vec3(2, 50, 0));
  }
}

TEST_CASE("3-D pulls that cancel grow towards the nearest source that pulls the node", "[colonisation]") {
  v::Domain d;
  d.kind = v::DomainKind::box;
  d.box_min = Vec3::Zero();
  d.box_max = Vec3::Constant(20);
  d.initial_nodes = {{10, 10, 10}, {10, 10, 14}};
  // the first two pull v = (10, 10, 10) apart exactly, the nearer listed second; the third is nearer v but pulls w
  d.initial_sources = {{16, 10, 10}, {5, 10, 10}, {10, 10, 12.6}};
  v::ColonisationParams p = params(v::VenationType::open, 1);
  p.darts_per_area = 0;
  v::Colonisation c(d, p);
  c.step();
  const v::VeinTree t = c.tree();
  REQUIRE(t.size() == 4);
  for (Index i = 2; i < 4; ++i)
    if (t.parent[i] == 0) CHECK(t.positions[i] == Vec3(9, 10, 10));
}
