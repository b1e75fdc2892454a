// Tests of where a space-colonisation node may grow and how a pattern ends: pulls that cancel or leave the
// blade, sources born already reached, the stalled flag.
#include <catch2/catch.hpp>

#include "tests/venation/leaf_fixtures.h"
#include "venation/colonisation.h"
#include "venation/domain.h"
#include "venation/leaf_shape.h"

using namespace cellform;
using core::Index;
using core::Vec3;
namespace v = cellform::venation;
using namespace cellform::test;

namespace {
/// A pattern in `where` (a leaf or a 3-D domain) with its initial sources alone (no darts), after one step.
template <class Where>
v::Colonisation after_one_step(const Where& where, v::VenationType type) {
  v::ColonisationParams p = params(type, 1);
  p.darts_per_area = 0;
  v::Colonisation c(where, p);
  c.step();
  return c;
}
}  // namespace

TEST_CASE("veins stay in a lobed blade: sources across a sinus do not pull a node out of it", "[colonisation]") {
  // Deep lobes: a node between the sources of two lobes was pulled across the sinus between them, out of
  // the outline (a laser cut the vein through it), in every growth mode but marginal (which had a check).
  for (const v::GrowthMode g : {v::GrowthMode::none, v::GrowthMode::uniform})
    for (const v::VenationType type : {v::VenationType::open, v::VenationType::closed}) {
      v::ShapeParams sp;
      sp.kind = v::ShapeKind::lobed;
      sp.length = 100;
      sp.width = 60;
      sp.lobes = 4;
      sp.lobe_depth = 0.6;
      v::Leaf leaf;
      leaf.outline = v::make_outline(sp);
      v::ColonisationParams p = params(type, 1, 3);
      p.growth = g;
      if (g == v::GrowthMode::uniform) {
        p.initial_scale = 0.5;
        p.final_scale = 1;
        p.scale_step = 0.01;
      }
      p.darts_per_area = 0.01;
      v::Colonisation sim(leaf, p);
      sim.run();
      INFO("growth " << static_cast<int>(g) << ", type " << static_cast<int>(type) << ", steps " << sim.report().steps
                     << ", sources left " << sim.report().sources);
      const v::VeinTree t = sim.tree();
      CHECK(t.size() > 500);
      const v::OutlineIndex blade(sim.outline());
      std::size_t outside = 0, across = 0;
      for (std::size_t i = 1; i < t.size(); ++i) {  // (the seed is the petiole, on the outline)
        outside += !blade.contains({t.positions[i].x(), t.positions[i].y()});
        if (t.parent[i] == core::kNoIndex) continue;
        const Vec3& a = t.positions[t.parent[i]];
        across += !blade.segment_inside({a.x(), a.y()}, {t.positions[i].x(), t.positions[i].y()});
      }
      CHECK(outside == 0);
      CHECK(across == 0);  // nor a segment across a sinus from a node beside it
      // the nodes go round the sinus instead; in open patterns a source whose nearest node is across a sinus
      // (from which every step leaves the blade) is left
      if (type == v::VenationType::closed)
        CHECK(sim.report().finished);
      else
        CHECK(sim.report().sources * 20 <= sim.report().sources_born);
    }
}

TEST_CASE("no vein segment cuts between the teeth of a toothed blade", "[colonisation]") {
  // 200 teeth 0.05 leaf widths deep, 80 segments long: 92 of 1,314 segments cut across a notch between two
  // teeth with both their ends inside, up to 0.34 segments out of the blade (veins.svg crossed the cut line)
  v::ShapeParams sp;
  sp.kind = v::ShapeKind::ovate;
  sp.length = 80;
  sp.width = 48;
  sp.teeth = {{4, 200}};  // 0.05 leaf lengths deep
  v::Leaf leaf;
  leaf.outline = v::make_outline(sp);
  for (const v::VenationType type : {v::VenationType::open, v::VenationType::closed}) {
    v::ColonisationParams p = params(type, 1, 1.5);
    p.darts_per_area = 0.005;
    v::Colonisation sim(leaf, p);
    sim.run();
    const v::VeinTree t = sim.tree();
    const v::OutlineIndex blade(sim.outline());
    std::size_t across = 0, margin = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (t.parent[i] == core::kNoIndex) continue;
      const Vec3& a = t.positions[t.parent[i]];
      across += !blade.segment_inside({a.x(), a.y()}, {t.positions[i].x(), t.positions[i].y()});
      margin += v::distance_to_boundary(sim.outline(), {t.positions[i].x(), t.positions[i].y()}) < 1;
    }
    INFO((type == v::VenationType::open ? "open" : "closed")
         << ": " << t.size() << " nodes, " << margin << " within a segment of the margin");
    CHECK(margin > 50);  // the veins do reach into the teeth
    CHECK(across == 0);
  }
}

TEST_CASE("pulls that cancel: the node grows towards its nearest influencing source, and the pattern completes",
          "[colonisation]") {
  // Eq. 1 has no direction for two sources exactly opposite. The node grew nothing, and open leaves stalled
  // with such pairs left (4 to 16 of 95 sources in a 36 x 60 rectangle; none on the same rectangle as a
  // surface, where this was already done).
  for (const v::VenationType type : {v::VenationType::open, v::VenationType::closed}) {
    INFO((type == v::VenationType::open ? "open" : "closed"));
    v::Leaf leaf = ellipse_leaf(20, 20);
    leaf.initial_nodes = {{0, 10}};
    leaf.initial_sources = {{-5, 10}, {5, 10}};
    v::Colonisation c = after_one_step(leaf, type);
    v::VeinTree t = c.tree();
    REQUIRE(t.size() == 2);
    CHECK(t.positions[1].x() == -1);  // towards the first of the two, equally near
    CHECK(t.positions[1].y() == 10);
    while (!c.done()) c.step();
    CHECK(c.report().finished);
    CHECK(c.sources().empty());
    t = c.tree();
    double left = 0, right = 0;
    for (const Vec3& q : t.positions) {
      left = std::min(left, q.x());
      right = std::max(right, q.x());
    }
    CHECK(left <= -4);  // within the kill distance of each source
    CHECK(right >= 4);
  }
}

TEST_CASE("a pull along a closed surface's normal: the node grows towards its nearest source", "[colonisation]") {
  // a 10-unit cube; the seed at the centre of its floor, sources round it on the floor (they cancel) and on
  // the walls and ceiling (they pull it inwards, along the normal): the step projected back onto the floor
  // was shorter than a tenth of a segment, so the node never grew and the run stalled with its seed alone
  v::Domain d;
  d.kind = v::DomainKind::surface;
  d.mesh.vertices = {Vec3(0, 0, 0),  Vec3(10, 0, 0),  Vec3(10, 10, 0),  Vec3(0, 10, 0),
                     Vec3(0, 0, 10), Vec3(10, 0, 10), Vec3(10, 10, 10), Vec3(0, 10, 10)};
  d.mesh.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                      {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  d.initial_nodes = {Vec3(5, 5, 0)};
  d.initial_sources = {Vec3(2, 5, 0), Vec3(8, 5, 0),  Vec3(5, 2, 0), Vec3(5, 8, 0), Vec3(5, 5, 10),
                       Vec3(0, 5, 5), Vec3(10, 5, 5), Vec3(5, 0, 5), Vec3(5, 10, 5)};
  for (const v::VenationType type : {v::VenationType::open, v::VenationType::closed}) {
    INFO((type == v::VenationType::open ? "open" : "closed"));
    v::Colonisation c = after_one_step(d, type);
    v::VeinTree t = c.tree();
    REQUIRE(t.size() == 2);
    CHECK((t.positions[1] - Vec3(4, 5, 0)).norm() < 1e-9);  // towards the first of the four nearest
    while (!c.done()) c.step();
    CHECK(c.report().finished);
    CHECK(!c.report().stalled);
    CHECK(c.sources().empty());
  }
}

TEST_CASE("sources born within the kill distance go at once: the pattern ends instead of running to max_steps",
          "[colonisation]") {
  // closed, kill distance beyond the vein birth distance: every dart that lands is already reached, and a
  // reached vein is not pulled. Such steps used to count as progress (a source born, one removed), so the
  // run went on to max_steps (100,000 in the audit, with every source ever made kept: 700 MB). (An open
  // source pulls its nearest node once, as in the paper's loop, and goes when the new node is within d_k.)
  {
    v::ColonisationParams p = params(v::VenationType::closed, 1000, 3);
    p.darts_per_area = 0.05;
    p.max_steps = 1000;
    v::Colonisation c(ellipse_leaf(40, 30), p);
    while (!c.done()) c.step();
    INFO("steps " << c.report().steps << ", sources born " << c.report().sources_born);
    CHECK(c.report().finished);
    CHECK(c.report().steps == p.settle_steps);
    CHECK(c.report().sources_born > 0);
    CHECK(c.tree().size() == 1);
  }
}

TEST_CASE("a pattern that cannot grow ends with the stalled flag", "[colonisation]") {
  // two parallel sheets 5 apart; the seed is on the lower, a source right above it on the upper. The
  // node's step towards it projects back onto the lower sheet at the node itself: it cannot advance.
  v::Domain d;
  d.kind = v::DomainKind::surface;
  for (const double z : {0.0, 5.0}) {
    const auto base = static_cast<Index>(d.mesh.vertices.size());
    d.mesh.vertices.insert(d.mesh.vertices.end(),
                           {Vec3(-10, -10, z), Vec3(10, -10, z), Vec3(10, 10, z), Vec3(-10, 10, z)});
    d.mesh.triangles.push_back({base, base + 1, base + 2});
    d.mesh.triangles.push_back({base, base + 2, base + 3});
  }
  d.initial_nodes = {Vec3(0, 0, 0)};
  d.initial_sources = {Vec3(0, 0, 5)};
  v::ColonisationParams p = params(v::VenationType::open, 1);
  p.darts_per_area = 0;
  v::Colonisation c(d, p);
  while (!c.done()) c.step();
  CHECK(c.report().stalled);
  CHECK(!c.report().finished);
  CHECK(c.report().steps == p.settle_steps);
  CHECK(c.tree().size() == 1);
  p.max_steps = 2;
  p.settle_steps = 10;
  v::Colonisation limited(d, p);
  while (!limited.done()) limited.step();
  CHECK(limited.report().hit_max_steps);
}

TEST_CASE("a growth table is read between its points along straight lines, and held beyond its ends",
          "[colonisation]") {
  const v::GrowthFunction f{{0, 2, 10}, {1.10, 1.02, 1.0}};
  CHECK(f(-5) == 1.10);  // held below the first point
  CHECK(f(0) == 1.10);
  CHECK(f(1) == Approx(1.06));  // halfway from 1.10 to 1.02
  CHECK(f(2) == Approx(1.02));
  CHECK(f(4) == Approx(1.015));  // a quarter of the way from 1.02 to 1.0
  CHECK(f(10) == 1.0);
  CHECK(f(50) == 1.0);  // held above the last
}

TEST_CASE("nonuniform growth moves the blade as Appendix A's Eq. 4 says", "[colonisation]") {
  // (a paper-fidelity audit: the growth test held for swapped rates or t + 1 steps.) After t steps a point
  // of the initial blade at (x0, y0), relative to the petiole, lies at x0 REG_x(y0)^t and
  // y_t = integral from 0 to y0 of REG_y(y)^t dy (Runions 2005, Eq. 4), here by Simpson's rule.
  v::ColonisationParams p = params(v::VenationType::open, 0.5, 1);
  p.growth = v::GrowthMode::nonuniform;
  p.growth_x = {{0, 10}, {1.03, 1.03}};
  p.growth_y = {{0, 10}, {1.05, 1.01}};  // the base lengthens faster than the tip
  p.growth_steps = 20;
  const v::Leaf leaf = ellipse_leaf(10, 5);
  v::Colonisation sim(leaf, p);
  const v::Outline initial = sim.outline();
  auto y_at = [&](double y0, int t) {
    const int n = 2000;  // intervals (even)
    const double h = y0 / n;
    double sum = 0;
    for (int i = 0; i <= n; ++i) sum += (i == 0 || i == n ? 1 : i % 2 ? 4 : 2) * std::pow(p.growth_y(i * h), t);
    return sum * h / 3;
  };
  for (int t = 1; t <= 12; ++t) {
    sim.step();
    if (t % 4 != 0) continue;
    const v::Outline now = sim.outline();
    REQUIRE(now.points.size() == initial.points.size());
    for (std::size_t k = 0; k < now.points.size(); k += 7) {
      const v::Vec2 q0 = initial.points[k] - leaf.petiole;
      INFO("step " << t << ", outline point " << k << " from (" << q0.x() << ", " << q0.y() << ")");
      CHECK(now.points[k].x() - leaf.petiole.x() == Approx(q0.x() * std::pow(1.03, t)).margin(1e-6));
      CHECK(now.points[k].y() - leaf.petiole.y() == Approx(y_at(q0.y(), t)).margin(1e-5));
    }
  }
}

TEST_CASE("closed: a source waits for a vein still on its way, and the late vein closes the loop", "[colonisation]") {
  // (a paper-fidelity audit: no test had a late vein.) Runions 2005: a source "must remain active until it is
  // reached by all veins that are growing towards it". One source, a vein 5 below it and one `far` above it
  // (both relative neighbours of the source): the near vein reaches it first, the far one keeps growing to it.
  for (const double far : {10.0, 20.0}) {
    v::ShapeParams sp;
    sp.kind = v::ShapeKind::ellipse;
    sp.length = sp.width = 200;
    v::Leaf leaf;
    leaf.outline = v::make_outline(sp);
    leaf.initial_nodes = {{0, 55}, {0, 60 + far}};
    leaf.initial_sources = {{0.3, 60.4}};
    v::ColonisationParams p = params(v::VenationType::closed, 1);
    p.darts_per_area = 0;
    p.max_steps = 200;
    v::Colonisation c(leaf, p);
    std::size_t alive_after_near = 0;
    for (int step = 0; step < 200 && !c.done(); ++step) {
      c.step();
      if (step == 6) alive_after_near = c.sources().size();  // the near vein has reached it by now
    }
    const v::VeinTree t = c.tree();
    std::size_t from_far = 0;  // nodes grown from the far seed (node 1)
    for (std::size_t i = 2; i < t.size(); ++i) {
      Index r = static_cast<Index>(i);
      while (t.parent[r] != core::kNoIndex) r = t.parent[r];
      from_far += r == 1;
    }
    INFO("far vein at " << far << ": " << t.size() << " nodes, " << from_far << " from the far seed");
    CHECK(alive_after_near == 1);
    CHECK(c.report().finished);
    CHECK(from_far >= static_cast<std::size_t>(far) - 2);  // it grew all the way
    REQUIRE(t.anastomoses.size() == 1);                    // and the graph has the closing edge
  }
}
