// Tests of venation/colonisation_sources.cpp: the darts' birth tests (b_s against sources, b_v against
// nodes) and the max_sources ceiling.
#include "venation/colonisation.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/random.h"
#include "tests/venation/leaf_fixtures.h"
#include "venation/leaf_shape.h"

using namespace cellform;
using core::Vec3;
namespace v = cellform::venation;
using namespace cellform::test;

TEST_CASE("darts test b_s against sources and b_v against nodes, when they differ", "[colonisation]") {
  const v::Leaf leaf = ellipse_leaf(80, 60);
  const v::OutlineIndex blade(leaf.outline);
  for (auto [bs, bv] : {std::pair{5.0, 3.0}, std::pair{3.0, 5.0}}) {
    v::ColonisationParams p = params(v::VenationType::open, 1);
    p.source_birth_distance = bs;
    p.vein_birth_distance = bv;
    p.darts_per_area = 0.5;
    v::Colonisation sim(leaf, p);
    core::Rng rng(p.seed);
    std::vector<Vec3> expect;
    for (int step = 0; step < 2; ++step) {
      const std::vector<Vec3> nodes = sim.tree().positions;
      const double expected = p.darts_per_area * blade.area();
      auto count = static_cast<std::size_t>(std::floor(expected));
      if (rng.uniform() < expected - std::floor(expected)) ++count;
      for (std::size_t d = 0; d < count; ++d) {
        Vec3 q;
        do q = Vec3(rng.uniform(blade.lo().x(), blade.hi().x()), rng.uniform(blade.lo().y(), blade.hi().y()), 0.0);
        while (!blade.contains(v::Vec2(q.x(), q.y())));
        bool ok = true;
        for (const Vec3& s : expect) ok = ok && (s - q).norm() > bs;
        for (const Vec3& n : nodes) ok = ok && (n - q).norm() > bv;
        if (ok) expect.push_back(q);
      }
      sim.step();
      INFO("b_s " << bs << " b_v " << bv << " step " << step + 1);
      REQUIRE(sim.sources() == expect);
    }
  }
}

TEST_CASE("max_sources is a ceiling: a step that would leave one more waiting is not taken", "[colonisation]") {
  v::ColonisationParams p = params(v::VenationType::closed, 1, 2);
  p.darts_per_area = 0.2;
  const v::Leaf leaf = ellipse_leaf(60, 40, v::ShapeKind::ovate);
  v::Colonisation whole(leaf, p);
  const std::size_t first_step = whole.step().sources;
  REQUIRE(first_step > 40);
  for (std::size_t limit : {first_step - 1, first_step}) {
    v::ColonisationParams cut = p;
    cut.max_sources = limit;
    v::Colonisation c(leaf, cut);
    const v::ColonisationReport& r = c.step();
    INFO("limit " << limit << " of " << first_step);
    CHECK(r.hit_max_sources);
    CHECK(c.sources().size() <= limit);
    CHECK(r.steps == (limit == first_step ? 1u : 0u));
  }
}

namespace {

/// Share of `probes` random points of the blade farther than `bv` from every vein node (brute force): the
/// room a source could still be born in, once no source waits.
double free_share(const v::Leaf& leaf, const v::VeinTree& t, double bv, int probes) {
  const v::OutlineIndex blade(leaf.outline);
  core::Rng rng(7);
  const v::Vec2 lo = blade.lo(), hi = blade.hi();
  int inside = 0, free = 0;
  while (inside < probes) {
    const v::Vec2 q(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()));
    if (!blade.contains(q)) continue;
    ++inside;
    bool near = false;
    for (const Vec3& n : t.positions) near = near || (Vec3(q.x(), q.y(), 0) - n).squaredNorm() <= bv * bv;
    free += near ? 0 : 1;
  }
  return static_cast<double>(free) / probes;
}

}  // namespace

TEST_CASE("a run settles after five quiet steps and as many vain darts as its blade holds b_v discs, up to 1,000",
          "[colonisation]") {
  // the rule watched from outside: a change is a vein node or a source more or less
  for (auto [length, width] : {std::pair{60.0, 40.0}, std::pair{500.0, 400.0}}) {
    const v::Leaf leaf = ellipse_leaf(length, width);
    v::ColonisationParams p = params(v::VenationType::open, 1, 6);
    p.darts_per_area = 5 / v::OutlineIndex(leaf.outline).area();  // about 5 darts a step
    p.max_steps = 100000;
    const double discs = v::OutlineIndex(leaf.outline).area() / (std::numbers::pi * 36);
    v::Colonisation sim(leaf, p);
    std::size_t quiet_steps = 0, quiet_darts = 0, last_darts = 0;
    while (!sim.done()) {
      const v::ColonisationReport before = sim.report();
      sim.step();
      const v::ColonisationReport& r = sim.report();
      last_darts = r.darts - before.darts;
      const bool changed = r.nodes != before.nodes || r.sources != before.sources;
      quiet_steps = changed ? 0 : quiet_steps + 1;
      quiet_darts = changed ? 0 : quiet_darts + last_darts;
    }
    const double needed = std::min(discs, 1000.0);
    INFO(length << " x " << width << ": " << discs << " discs, " << sim.report().steps << " steps, quiet for "
                << quiet_steps << " steps and " << quiet_darts << " darts");
    REQUIRE(sim.report().finished);
    CHECK(quiet_steps >= 5);
    CHECK(static_cast<double>(quiet_darts) >= needed);
    // and not a step later than both held
    CHECK((quiet_steps == 5 || static_cast<double>(quiet_darts - last_darts) < needed));
  }
}

TEST_CASE("a run ends only once its darts find no room, however few a step throws", "[colonisation]") {
  // 0.05 and 2 darts a step over a 60 x 40 ellipse (about 1,900 units of area, 67 b_v discs): a run once ended
  // after five steps without a change, which left a sparse blade empty (no source at 0.05 darts a step)
  const v::Leaf leaf = ellipse_leaf(60, 40);
  std::vector<std::size_t> born;
  for (double rho : {2.5e-5, 1e-3}) {
    v::ColonisationParams p = params(v::VenationType::open, 1, 3);
    p.darts_per_area = rho;
    p.max_steps = 100000;
    const auto [t, rep] = v::colonise(leaf, p);
    INFO("rho " << rho << ": " << rep.steps << " steps, " << rep.sources_born << " sources, " << rep.darts << " darts");
    REQUIRE(rep.finished);
    const double share = free_share(leaf, t, 3, 20000);
    INFO("free share " << share);
    CHECK(share < 0.08);  // settled once as many darts as the blade holds b_v discs fell in vain: a few discs' room
    born.push_back(rep.sources_born);
  }
  // about as many sources, at one dart in 20 steps as at two a step
  CHECK(static_cast<double>(born[0]) > 0.8 * static_cast<double>(born[1]));
}
