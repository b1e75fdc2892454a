// Tests of marginal growth's sources (Runions et al. 2005, Section 3.3): the precomputed set, its entry
// steps, and a colonisation that only ever reveals them inside the grown blade.
#include "venation/marginal_sources.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "core/errors.h"
#include "tests/venation/leaf_fixtures.h"
#include "venation/colonisation.h"

using namespace cellform;
using Catch::Matchers::Contains;
using core::Vec3;
namespace v = cellform::venation;

namespace {

v::Outline ellipse(double length, double width) {
  v::ShapeParams sp;
  sp.length = length;
  sp.width = width;
  return v::make_outline(sp);
}

/// A C open to the left, the petiole at (0, 0) on its bottom edge: the ray straight up leaves the blade at
/// y = 1 and enters it again at y = 3, so a point above the petiole enters the growing blade, leaves it
/// and enters again (not star-shaped about the petiole).
v::Outline c_shape() { return {{{-3, 0}, {3, 0}, {3, 4}, {-3, 4}, {-3, 3}, {2, 3}, {2, 1}, {-3, 1}}}; }

/// A fan of radius 10 between 30 and 150 degrees with its tip at the petiole (a vertex) and a V notch
/// down to radius 6 at the top centre (a deeper notch than examples/colonisation/ginkgo_fan.txt's).
v::Outline notched_fan() {
  v::Outline o;
  o.points.push_back({0, 0});
  for (int k = 0; k <= 40; ++k) {
    const double deg = 30 + 3 * k;
    if (deg > 84 && deg < 96) continue;
    const double a = deg * M_PI / 180;
    o.points.push_back({10 * std::cos(a), 10 * std::sin(a)});
    if (deg == 84) o.points.push_back({0, 6});
  }
  return o;
}

/// Brute force: the first step whose blade contains q, as the colonisation tests it; -1 if none.
long first_step_inside(const v::OutlineIndex& unit, const v::Vec2& petiole, const std::vector<double>& scales,
                       const v::Vec2& q) {
  for (std::size_t k = 0; k < scales.size(); ++k)
    if (unit.contains(petiole + (q - petiole) / scales[k])) return static_cast<long>(k);
  return -1;
}

}  // namespace

TEST_CASE("marginal_scales are the simulation's growth scales, step by step", "[marginal]") {
  const std::vector<double> s = v::marginal_scales(0.3, 1, 0.07);
  REQUIRE(s.size() == 11);  // 10 steps of 0.07 reach 1 (the last clipped to 1)
  CHECK(s.front() == 0.3);
  CHECK(s.back() == 1);
  for (std::size_t k = 1; k < s.size(); ++k) CHECK(s[k] > s[k - 1]);
  CHECK(v::marginal_scales(0.5, 0.5, 0.1) == std::vector<double>{0.5});
  CHECK_THROWS_WITH(v::marginal_scales(1, 1e9, 1), Contains("colonisation.scale_step"));
  // a step below the rounding of the scale would never arrive (it used to grow the list until memory ran out)
  CHECK_THROWS_WITH(v::marginal_scales(1, 1 + 1e-10, 2e-17), Contains("colonisation.scale_step"));
  v::MarginalSourceParams dense;  // 1.1 x 10^8 darts (allowed) where b_s = 0.1 lets nearly all of them stay
  dense.darts_per_area = 1e-1;
  dense.birth_distance = 0.1;
  CHECK_THROWS_WITH(v::precompute_marginal_sources(ellipse(1e4, 1e4), {0, 0}, s, dense),
                    Contains("colonisation.birth_distance") && Contains("5 x 10^7"));
  v::MarginalSourceParams huge;
  huge.darts_per_area = 1;  // 11 steps x 10^8 area units
  CHECK_THROWS_WITH(v::precompute_marginal_sources(ellipse(1e4, 1e4), {0, 0}, s, huge),
                    Contains("colonisation.darts") && Contains("10^9"));

  v::Leaf leaf;
  leaf.outline = ellipse(30, 20);
  v::ColonisationParams p;
  p.type = v::VenationType::open;
  p.source_birth_distance = p.vein_birth_distance = 2;
  p.growth = v::GrowthMode::marginal;
  p.initial_scale = 0.3;
  p.final_scale = 1;
  p.scale_step = 0.07;
  p.darts_per_area = 0.01;
  v::Colonisation sim(leaf, p);
  for (std::size_t k = 1; k < s.size() + 3; ++k) {
    sim.step();
    CHECK(sim.report().scale == s[std::min(k, s.size() - 1)]);  // bitwise
  }
}

TEST_CASE("precomputed sources: b_s apart, each at the first step whose blade contains it", "[marginal]") {
  struct Case {
    const char* name;
    v::Outline outline;
    double initial, final, step, bs, rho;
  };
  const std::vector<Case> cases = {
      {"ellipse", ellipse(120, 80), 0.2, 1, 0.01, 1.5, 0.004},
      {"C shape", c_shape(), 0.25, 5, 0.05, 0.6, 0.05},
      {"notched fan, petiole at a vertex", notched_fan(), 0.05, 1, 0.01, 0.15, 0.1},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    const std::vector<double> scales = v::marginal_scales(c.initial, c.final, c.step);
    v::MarginalSourceParams mp;
    mp.birth_distance = c.bs;
    mp.darts_per_area = c.rho;
    mp.seed = 7;
    const v::MarginalSources ms = v::precompute_marginal_sources(c.outline, {0, 0}, scales, mp);
    const v::OutlineIndex unit(c.outline);
    const double box = (c.final * (unit.hi() - unit.lo())).prod();
    // rho darts per unit area for each step, over the final blade's box
    CHECK(std::abs(static_cast<double>(ms.darts) - c.rho * static_cast<double>(scales.size()) * box) <= 1);
    REQUIRE(ms.start.size() == scales.size() + 1);
    REQUIRE(ms.start.back() == ms.points.size());
    CHECK(ms.points.size() <= ms.accepted);
    CHECK(ms.accepted <= ms.darts);
    REQUIRE(ms.points.size() > 500);
    std::size_t later_entries = 0;  // entries after the first step: the margin reached them
    for (std::size_t k = 0; k < scales.size(); ++k)
      for (std::size_t i = ms.start[k]; i < ms.start[k + 1]; ++i) {
        const long brute = first_step_inside(unit, {0, 0}, scales, ms.points[i]);
        INFO("point " << i << " (" << ms.points[i].x() << ", " << ms.points[i].y() << ")");
        REQUIRE(brute == static_cast<long>(k));
        later_entries += k > 0 ? 1 : 0;
      }
    CHECK(later_entries > ms.points.size() / 2);
    for (std::size_t i = 0; i < ms.points.size(); ++i)
      for (std::size_t j = i + 1; j < ms.points.size(); ++j) REQUIRE((ms.points[i] - ms.points[j]).norm() > c.bs);
    // deterministic, and the same for any thread count
    mp.threads = 2;
    const v::MarginalSources again = v::precompute_marginal_sources(c.outline, {0, 0}, scales, mp);
    CHECK(again.points == ms.points);
    CHECK(again.start == ms.start);
    mp.seed = 8;
    CHECK(v::precompute_marginal_sources(c.outline, {0, 0}, scales, mp).points != ms.points);
  }
  // the C shape: a point straight above the petiole at y = 3.5 x final enters inside the top bar at
  // scale 7/8 (y 4 of the outline), before the bar and the gap pass over it; brute force agreed above
}

TEST_CASE("precomputed darts are uniform in the box when b_s does not bind", "[marginal]") {
  // b_s far below the dart spacing: every dart is accepted, and the share the final blade reaches is its
  // share of the box (binomial, 5 standard deviations)
  const v::Outline o = ellipse(100, 60);
  const std::vector<double> scales = v::marginal_scales(0.1, 1, 0.01);
  v::MarginalSourceParams mp;
  mp.birth_distance = 1e-6;
  mp.darts_per_area = 0.0005;
  const v::MarginalSources ms = v::precompute_marginal_sources(o, {0, 0}, scales, mp);
  CHECK(ms.accepted == ms.darts);
  const v::OutlineIndex unit(o);
  const double share = unit.area() / (unit.hi() - unit.lo()).prod();
  const double n = static_cast<double>(ms.darts), mean = n * share;
  CHECK(std::abs(static_cast<double>(ms.points.size()) - mean) < 5 * std::sqrt(n * share * (1 - share)));
}

TEST_CASE("marginal growth reveals precomputed sources inside the current outline only", "[marginal][colonisation]") {
  struct Case {
    const char* name;
    v::Outline outline;
    v::VenationType type;
    double kill, birth, initial, step;
  };
  const std::vector<Case> cases = {
      {"open ellipse, d_k > b_s = b_v", ellipse(60, 40), v::VenationType::open, 8, 1, 0.15, 0.01},
      {"closed C shape", c_shape(), v::VenationType::closed, 1, 0.5, 1, 0.05},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    v::Leaf leaf;
    leaf.outline = c.outline;
    v::ColonisationParams p;
    p.type = c.type;
    p.kill_distance = c.kill;
    p.source_birth_distance = p.vein_birth_distance = c.birth;
    p.darts_per_area = 0.003;
    p.growth = v::GrowthMode::marginal;
    p.initial_scale = c.initial;
    p.final_scale = c.initial + 80 * c.step;
    p.scale_step = c.step;
    p.seed = 5;
    const std::vector<double> scales = v::marginal_scales(p.initial_scale, p.final_scale, p.scale_step);
    v::MarginalSourceParams mp;
    mp.birth_distance = p.source_birth_distance;
    mp.darts_per_area = p.darts_per_area;
    mp.seed = p.seed;
    const v::MarginalSources ms = v::precompute_marginal_sources(leaf.outline, leaf.petiole, scales, mp);
    std::set<std::pair<double, double>> precomputed;
    for (const v::Vec2& q : ms.points) precomputed.insert({q.x(), q.y()});

    v::Colonisation sim(leaf, p);
    std::set<std::pair<double, double>> ever;  // every source revealed so far
    std::size_t revealed = 0;
    while (!sim.done()) {
      const std::size_t k = sim.report().steps;
      const v::OutlineIndex blade(sim.outline());  // the blade this step reveals in
      const double tol = 1e-9 * (blade.hi() - blade.lo()).norm();
      const std::vector<Vec3> before = sim.sources(), nodes = sim.tree().positions;
      const std::size_t born = sim.report().sources_born;
      // oracle: the points entering at step k that pass the dart tests against the state before the step
      std::vector<Vec3> expect;
      for (const v::Vec2& q2 : ms.entering(k)) {
        const Vec3 q(q2.x(), q2.y(), 0);
        bool ok = true;
        for (const Vec3& s : before) ok = ok && (s - q).norm() > p.source_birth_distance;
        for (const Vec3& n : nodes) ok = ok && (n - q).norm() > p.vein_birth_distance;
        if (ok) expect.push_back(q);
      }
      sim.step();
      REQUIRE(sim.report().sources_born - born == expect.size());
      const std::vector<Vec3> after = sim.sources();
      std::set<std::pair<double, double>> old;
      for (const Vec3& s : before) old.insert({s.x(), s.y()});
      for (const Vec3& s : after) {
        if (old.count({s.x(), s.y()})) continue;
        INFO("step " << k << " new source (" << s.x() << ", " << s.y() << ")");
        CHECK(std::find(expect.begin(), expect.end(), s) != expect.end());
        CHECK(precomputed.count({s.x(), s.y()}) == 1);  // a subset of the precomputed set
        CHECK(ever.insert({s.x(), s.y()}).second);      // never revealed twice
        CHECK((blade.contains({s.x(), s.y()}) || v::distance_to_boundary(sim.outline(), {s.x(), s.y()}) < tol));
        for (const Vec3& o : after)
          if (o != s) CHECK((o - s).norm() >= p.source_birth_distance);
      }
      revealed += expect.size();
    }
    INFO("steps " << sim.report().steps << " nodes " << sim.report().nodes << " revealed " << revealed << " left "
                  << sim.report().sources);
    // the C's slot lies between the petiole and its upper arm: the young blade's slot was below the grown
    // one's, and veins once crossed the grown slot to the sources beyond. No vein is added there now, so
    // sources that pull straight across it stay, and the run ends stalled
    CHECK((sim.report().finished || sim.report().stalled));
    const v::OutlineIndex grown(sim.outline());
    for (const Vec3& q : sim.tree().positions)
      CHECK((grown.contains({q.x(), q.y()}) || v::distance_to_boundary(sim.outline(), {q.x(), q.y()}) < 1e-9));
    CHECK(revealed > 100);
    CHECK(revealed == sim.report().sources_born);
    std::size_t entering = 0;
    for (std::size_t k = 0; k < sim.report().steps; ++k) entering += ms.entering(k).size();
    CHECK(sim.report().darts == entering);
    CHECK(entering == ms.points.size());  // growth ended, so every precomputed source had its chance
  }
}

TEST_CASE("marginal growth is deterministic and the same for 1 and 2 threads", "[marginal][colonisation]") {
  v::Leaf leaf;
  leaf.outline = ellipse(80, 50);
  v::ColonisationParams p;
  p.type = v::VenationType::closed;
  p.kill_distance = 1;
  p.source_birth_distance = p.vein_birth_distance = 2;
  p.darts_per_area = 0.002;
  p.growth = v::GrowthMode::marginal;
  p.initial_scale = 0.2;
  p.final_scale = 1;
  p.scale_step = 0.01;
  p.seed = 3;
  const auto a = v::colonise(leaf, p);
  const auto b = v::colonise(leaf, p);
  p.threads = 2;
  const auto c = v::colonise(leaf, p);
  INFO("steps " << a.second.steps << " nodes " << a.second.nodes << " sources " << a.second.sources << " born "
                << a.second.sources_born << " stalled " << a.second.stalled);
  REQUIRE(a.first.size() > 200);
  CHECK((a.second.finished || a.second.stalled));
  for (const auto* o : {&b, &c}) {
    CHECK(o->first.positions == a.first.positions);
    CHECK(o->first.parent == a.first.parent);
    CHECK(o->first.anastomoses == a.first.anastomoses);
    CHECK(o->second.darts == a.second.darts);
    CHECK(o->second.sources_born == a.second.sources_born);
  }
}

TEST_CASE("marginal growth of an outline with barbs adds no vein outside the grown blade", "[colonisation]") {
  // barbs that point back towards the petiole: the blade scaled up from the petiole leaves the space the
  // young blade covered under each barb outside, and veins once grew there (7 mm out of a 120 mm leaf)
  v::Leaf leaf;
  leaf.outline.points = {{0, 0}, {45, 15}, {12, 35}, {35, 70}, {0, 100}, {-35, 70}, {-12, 35}, {-45, 15}};
  v::ColonisationParams p = cellform::test::params(v::VenationType::open, 3, 1.5);
  p.growth = v::GrowthMode::marginal;
  p.initial_scale = 0.2;
  p.final_scale = 1;
  p.scale_step = 0.002;
  p.darts_per_area = 0.004;
  v::Colonisation sim(leaf, p);
  sim.run();
  const v::VeinTree t = sim.tree();
  const v::OutlineIndex grown(leaf.outline);
  std::size_t outside = 0;
  for (const Vec3& q : t.positions)  // the seed at the petiole lies on the outline
    outside += !grown.contains({q.x(), q.y()}) && v::distance_to_boundary(leaf.outline, {q.x(), q.y()}) > 1e-9;
  INFO("nodes " << t.size() << " steps " << sim.report().steps << " sources left " << sim.report().sources);
  CHECK(t.size() > 1000);
  CHECK(outside == 0);
}
