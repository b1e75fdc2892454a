// Whole steps: growth, determinism across thread counts, hooks and reports.
#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "cells/simulation.h"
#include "core/random.h"
#include "tests/fixtures.h"

using namespace cellform::cells;

namespace {

// A jittered hex sheet with a few vein chains, so every force term and branch runs.
Simulation make_sim(int side, std::uint64_t seed, int threads) {
  Params p;
  p.weights[0].cohesion = 0.05;
  p.weights[0].separation = 0.05;
  p.weights[2].cohesion = 0.1;
  p.weights[2].separation = 0.1;
  p.division.trigger = DivisionTrigger::age;
  p.division.division_age = 20;
  p.division.probability = 0.5;
  p.division.max_cells = 200000;
  Simulation sim(p, seed);
  sim.set_threads(threads);
  Cells& c = sim.cells();
  c = cellform::testing::hex_sheet(side, side);
  cellform::core::Rng rng(seed);
  for (std::size_t i = 0; i < c.size(); ++i) {
    c.position[i] += 0.05 * rng.unit_vector();
    c.age[i] = static_cast<std::uint32_t>(rng.next() % 20);
  }
  // vein chains along the first rows
  for (Index i = 0; i + 1 < static_cast<Index>(side); ++i) {
    c.type[i + 1] = CellType::vein;
    c.vein_parent[i + 1] = i;
  }
  c.type[0] = CellType::petiole;
  c.fixed[0] = 1;
  return sim;
}

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(a[i].data(), b[i].data(), sizeof(double) * 3) != 0) return false;
  return true;
}

}  // namespace

TEST_CASE("same seed gives bit-identical cells with 1 and 2 threads", "[simulation][slow]") {
  Simulation one = make_sim(80, 17, 1);  // 6400 cells: above the parallel grain
  Simulation two = make_sim(80, 17, 2);
  std::size_t divisions = 0;
  for (int s = 0; s < 60; ++s) {
    const StepReport a = one.step();
    const StepReport b = two.step();
    REQUIRE(a.cells == b.cells);
    REQUIRE(a.divisions == b.divisions);
    REQUIRE(a.max_speed == b.max_speed);
    divisions += a.divisions;
  }
  REQUIRE(divisions > 1000);
  REQUIRE(one.cells().id == two.cells().id);
  REQUIRE(same_bits(one.cells().position, two.cells().position));
  REQUIRE(same_bits(one.cells().velocity, two.cells().velocity));
  REQUIRE(one.cells().links == two.cells().links);
  REQUIRE(one.cells().vein_parent == two.cells().vein_parent);
  for (const Vec3& x : one.cells().position) REQUIRE(x.allFinite());
}

TEST_CASE("lengths scale: twice the rest length, positions and radii give twice the positions, bit for bit",
          "[simulation]") {
  // Every length-valued parameter doubled (rest length, division radius, unary acceleration; the cohesion and
  // separation weights, in units^2 / time^2, times 4) and the cells placed twice as far apart: each force is
  // then exactly twice as large (powers of two scale without rounding), and so is every position at every
  // step. A length taken in the wrong units (rest_length where its square is meant, or a constant left
  // unscaled) breaks it; the tests' usual rest length of 1 hides such a slip.
  for (const DivisionTrigger trigger : {DivisionTrigger::age, DivisionTrigger::neighbours}) {
    auto run = [&](double k) {
      Simulation sim = make_sim(12, 5, 1);
      Params p = sim.params();
      p.rest_length *= k;
      for (auto& w : p.weights) {
        w.cohesion *= k * k;
        w.separation *= k * k;
      }
      p.unary = Vec3(0.01, -0.02, 0.03) * k;
      p.division.trigger = trigger;
      p.division.radius *= k;
      p.division.min_neighbours = 5;
      Simulation scaled(p, 5);
      scaled.set_threads(1);
      scaled.cells() = sim.cells();
      for (Vec3& x : scaled.cells().position) x *= k;
      std::size_t divisions = 0;
      for (int s = 0; s < 40; ++s) divisions += scaled.step().divisions;
      CHECK(divisions > 20);
      // by id: the spatial reorder may number them differently
      std::vector<std::pair<std::uint64_t, std::pair<Vec3, Vec3>>> by_id;
      const Cells& c = scaled.cells();
      for (std::size_t i = 0; i < c.size(); ++i) by_id.push_back({c.id[i], {c.position[i], c.velocity[i]}});
      std::sort(by_id.begin(), by_id.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      return by_id;
    };
    const auto one = run(1), two = run(2);
    INFO((trigger == DivisionTrigger::age ? "age" : "neighbours"));
    REQUIRE(one.size() == two.size());
    std::size_t same = 0;
    for (std::size_t i = 0; i < one.size(); ++i) {
      REQUIRE(one[i].first == two[i].first);
      same += (2 * one[i].second.first == two[i].second.first && 2 * one[i].second.second == two[i].second.second);
    }
    CHECK(same == one.size());
  }
}

TEST_CASE("the neighbours trigger counts the cells where the step moved them (brute force)", "[simulation]") {
  // cells thrown about fast between the links' update and the division: a count over the grid of their
  // places before the move would miss some and count others
  // also over a radius of 3 rest lengths, which the trigger counts in a grid of its own, half the radius wide
  const auto [radius, min_neighbours] = GENERATE(std::make_pair(kDivisionRadius, 6), std::make_pair(3.0, 24));
  Params p;
  p.division.trigger = DivisionTrigger::neighbours;
  p.division.min_age = 0;
  p.division.probability = 1;
  p.division.max_cells = 100000;
  p.division.radius = radius;
  p.division.min_neighbours = min_neighbours;
  Simulation sim(p, 9);
  sim.set_threads(1);
  sim.cells() = cellform::testing::hex_sheet(14, 14);
  cellform::core::Rng rng(9);
  for (Vec3& v : sim.cells().velocity) v = 6.0 * rng.unit_vector();
  INFO("radius " << radius);
  for (int step = 0; step < 3; ++step) {
    std::size_t expected = 0;
    const StepReport r = sim.step({}, [&](Cells& c) {
      expected = 0;
      for (std::size_t i = 0; i < c.size(); ++i) {
        int near = 0;
        for (std::size_t j = 0; j < c.size(); ++j)
          near += j != i && (c.position[j] - c.position[i]).norm() <= p.division.radius;
        expected += near < p.division.min_neighbours;
      }
    });
    INFO("step " << step);
    CHECK(r.divisions == expected);
    CHECK(expected > 20);
  }
}

TEST_CASE("step report, hooks and the spatial reorder", "[simulation]") {
  Simulation sim = make_sim(12, 3, 1);
  const std::size_t n0 = sim.cells().size();
  int forces_called = 0, constrain_called = 0;
  StepReport r;
  for (int s = 0; s < 40; ++s) {
    r = sim.step([&](Cells&) { ++forces_called; },
                 [&](Cells& c) {
                   ++constrain_called;
                   for (Vec3& x : c.position) x.z() = std::max(x.z(), -0.01);  // a floor
                 });
  }
  REQUIRE(forces_called == 40);
  REQUIRE(constrain_called == 40);
  REQUIRE(r.step == 40);
  REQUIRE(sim.step_count() == 40);
  REQUIRE(r.cells == sim.cells().size());
  REQUIRE(sim.cells().size() > n0);
  REQUIRE(r.max_speed > 0);
  // the vein chain survives the reorder at step 32 by id
  const Cells& c = sim.cells();
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c.vein_parent[i] == kNoIndex) continue;
    REQUIRE(c.id[c.vein_parent[i]] + 1 == c.id[i]);
  }
}

TEST_CASE("a forces hook's acceleration is integrated, and the constrain hook sees the moved cells", "[simulation]") {
  // one cell alone feels no force of its own: semi-implicit Euler gives v = drag (v0 + a dt), x = x0 + v dt
  Params p;
  p.division.trigger = DivisionTrigger::none;
  p.drag = Vec3(0.9, 0.8, 0.7);
  p.time_step = 0.25;
  Simulation sim(p, 1);
  add_cell(sim.cells(), Vec3(1, 2, 3));
  sim.cells().velocity[0] = Vec3(0.5, -1, 0.25);
  const Vec3 a(2, 4, -8), x0(1, 2, 3), v0(0.5, -1, 0.25);
  const Vec3 v = p.drag.cwiseProduct(v0 + a * p.time_step);
  Vec3 seen = Vec3::Zero();
  const StepReport r = sim.step([&](Cells& c) { c.acceleration[0] += a; },
                                [&](Cells& c) {
                                  seen = c.position[0];
                                  c.position[0].z() = 0;  // a floor the hook puts the cell on
                                });
  CHECK((seen - (x0 + v * p.time_step)).norm() < 1e-12);
  CHECK((sim.cells().velocity[0] - v).norm() < 1e-12);
  CHECK(sim.cells().position[0].z() == 0);  // what the constrain hook did stays
  CHECK(r.max_speed == Approx(v.norm()).epsilon(1e-12));
}

TEST_CASE("three cells relax to an equilateral triangle of rest-length sides", "[simulation]") {
  Params p;
  p.rest_length = 1.3;
  p.link_range = 0;  // the far cell starts beyond the default range
  p.division.trigger = DivisionTrigger::none;
  Simulation sim(p, 1);
  add_cell(sim.cells(), Vec3(0, 0, 0));
  add_cell(sim.cells(), Vec3(0.5, 0, 0));
  add_cell(sim.cells(), Vec3(0.2, 2.0, 0));
  for (int s = 0; s < 400; ++s) sim.step();
  const Cells& c = sim.cells();
  for (int a = 0; a < 3; ++a) REQUIRE((c.position[a] - c.position[(a + 1) % 3]).norm() == Approx(1.3).epsilon(1e-6));
}

TEST_CASE("a flat sheet stays flat, in any orientation", "[simulation]") {
  Params p;
  p.division.trigger = DivisionTrigger::none;
  p.weights[0].cohesion = 0.05;
  p.weights[0].separation = 0.05;
  Simulation sim(p, 1);
  sim.cells() = cellform::testing::hex_sheet(15, 15, 0.8);
  cellform::core::Rng rng(4);           // jittered in the plane, so that no two links tie (a tie broken by index
  for (Vec3& x : sim.cells().position)  // may break the other way once rotated)
    x += Vec3(rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), 0);
  const std::vector<Vec3> start = sim.cells().position;
  for (int s = 0; s < 100; ++s) sim.step();
  for (const Vec3& x : sim.cells().position) REQUIRE(x.z() == 0.0);
  // tilted: every force lies in the plane only if each term is computed as the formulas say (a term that
  // pushed along some fixed axis, or planarisation towards a wrong plane, would lift cells off it)
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(0.4, Vec3::UnitX())).toRotationMatrix();
  Simulation tilted(p, 1);
  tilted.cells() = cellform::testing::hex_sheet(15, 15, 0.8);
  for (std::size_t i = 0; i < start.size(); ++i) tilted.cells().position[i] = turn * start[i] + Vec3(3, -2, 5);
  const Vec3 normal = turn * Vec3::UnitZ(), origin(3, -2, 5);
  for (int s = 0; s < 100; ++s) tilted.step();
  double moved = 0, off = 0;
  const Cells &flat = sim.cells(), &t = tilted.cells();
  for (std::size_t i = 0; i < t.size(); ++i) {
    off = std::max(off, std::abs((t.position[i] - origin).dot(normal)));
    const auto same = static_cast<std::size_t>(std::find(flat.id.begin(), flat.id.end(), t.id[i]) - flat.id.begin());
    REQUIRE(same < flat.size());  // (the arrays are re-sorted in space: cells are matched by id)
    moved = std::max(moved, (t.position[i] - (turn * flat.position[same] + origin)).norm());
  }
  CHECK(off < 1e-9);
  CHECK(moved < 1e-9);  // and moves as the untilted sheet did (the sheet relaxes outwards from 0.8)
}

TEST_CASE("planarisation brings a lifted cell back into its flat sheet", "[simulation]") {
  // a flat sheet stays flat whatever the forces (all in plane); a cell lifted out of it must come back,
  // every step a little nearer at first, and faster than the springs alone bring it (the lift stretches
  // its links). The sheet may rise a little as a whole (planarisation pulls the lifted cell's neighbours
  // up too), so heights are measured from the sheet's mean height.
  struct Heights {
    double lifted, spread;  // the lifted cell above the mean; highest minus lowest cell
  };
  auto after = [](double planar, int steps) {
    Params p;
    p.division.trigger = DivisionTrigger::none;
    for (ForceWeights& w : p.weights) w.planar = planar;
    Simulation sim(p, 1);
    sim.cells() = cellform::testing::hex_sheet(15, 15, 1.0);
    const std::size_t lifted = 7 * 15 + 7;  // in the middle
    sim.cells().position[lifted].z() = 0.3;
    REQUIRE(sim.cells().id[lifted] == lifted);
    Heights h{0.3, 0.3};
    for (int s = 0; s < steps; ++s) {
      sim.step();
      const Cells& c = sim.cells();  // cells are reordered in space now and then: found by id
      const auto at = static_cast<std::size_t>(std::find(c.id.begin(), c.id.end(), lifted) - c.id.begin());
      REQUIRE(at < c.size());
      double mean = 0, lo = 1e9, hi = -1e9;
      for (const Vec3& x : c.position) {
        mean += x.z() / static_cast<double>(c.size());
        lo = std::min(lo, x.z());
        hi = std::max(hi, x.z());
      }
      const double z = std::abs(c.position[at].z() - mean);
      INFO("planar " << planar << ", step " << s << ": lifted " << z << " above the mean");
      if (s < 20) REQUIRE(z < h.lifted);
      h = {z, hi - lo};
    }
    return h;
  };
  const Heights with = after(0.5, 5), springs_only = after(0, 5);
  INFO("after 5 steps: " << with.lifted << " with planarisation, " << springs_only.lifted << " with the springs alone");
  CHECK(0.3 - with.lifted > 4 * (0.3 - springs_only.lifted));  // about 7 times as far in December 2026
  // within 40 steps it is back to a tenth of the lift. (Left longer, a slow bend grows again on this regular
  // lattice, where each cell has six equally close neighbours and ties choose Eq. 3's three: not asserted.)
  const Heights back = after(0.5, 40);
  CHECK(back.lifted < 0.03);
  CHECK(back.spread < 0.08);
}

TEST_CASE("a disc dividing along one axis keeps its centre, reaching as far to either side along it", "[simulation]") {
  // split direction = axis: were the daughter always on the axis's + side, the form would drift along it.
  // Not a test of elongation: under the age trigger the disc grows about as wide as long (SplitDirection::axis)
  Params p;
  p.drag = cellform::core::Vec3(0.85, 0.85, 0.2);
  p.division.trigger = DivisionTrigger::age;
  p.division.division_age = 30;
  p.division.min_age = 1;
  p.division.direction = SplitDirection::axis;
  p.division.axis = cellform::core::Vec3(1, 0, 0);
  Simulation sim(p, 1);
  Cells& c = sim.cells();
  c = cellform::testing::hex_sheet(5, 5);
  cellform::core::Vec3 centre = cellform::core::Vec3::Zero();
  for (const auto& q : c.position) centre += q;
  centre /= static_cast<double>(c.size());
  for (int i = 0; i < 150; ++i) sim.step();
  REQUIRE(c.size() > 100);
  cellform::core::Vec3 mean = cellform::core::Vec3::Zero(), lo = c.position[0], hi = c.position[0];
  for (const auto& q : c.position) {
    mean += q;
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  mean /= static_cast<double>(c.size());
  // one-sided daughters moved the centre 1.5 rest lengths along x in a form 11 across (measured)
  CHECK(std::abs(mean.x() - centre.x()) < 0.1 * (hi.x() - lo.x()));
  CHECK(std::abs(centre.x() - lo.x()) == Approx(std::abs(hi.x() - centre.x())).epsilon(0.25));
}

TEST_CASE("vein cells straighten without collapsing onto their vein parents", "[simulation]") {
  // The script defaults: vein cells with cohesion and separation 0.05, four times that along the vein.
  // Eq. 4 as printed pulls a tip onto its parent harder the closer it gets (1 / distance), beyond what the
  // bounded spring can hold: the pair collapsed and was thrown off (examples/leaf.lua at seed 4 tore
  // off 635 cells). Below a rest length the pull now weakens with the distance.
  Params p;
  p.weights[2].cohesion = 0.05;
  p.weights[2].separation = 0.05;
  p.division.trigger = DivisionTrigger::none;
  Simulation sim(p, 3);
  Cells& c = sim.cells();
  c = cellform::testing::hex_sheet(12, 12);
  // vein chains of 2 to 6 cells along rows, each rooted at a fixed petiole
  for (int row = 2; row < 11; row += 2) {
    const Index first = static_cast<Index>(row * 12 + 1);
    c.type[first] = CellType::petiole;
    c.fixed[first] = 1;
    for (Index k = 1; k <= static_cast<Index>(row / 2 + 1); ++k) {
      c.type[first + k] = CellType::vein;
      c.vein_parent[first + k] = first + k - 1;
    }
  }
  double shortest = 1e9;
  for (int s = 0; s < 600; ++s) {
    sim.step();
    for (std::size_t i = 0; i < c.size(); ++i)
      if (c.vein_parent[i] != kNoIndex)
        shortest = std::min(shortest, (c.position[i] - c.position[c.vein_parent[i]]).norm());
  }
  INFO("shortest vein segment over the run " << shortest);
  CHECK(shortest > 0.5 * p.rest_length);
  CHECK(shortest < 1.0 * p.rest_length);  // the pull still draws the chain together
}

namespace {

/// Mean turning angle (degrees) at the joints of a vein chain given root first.
double mean_turn(const Cells& c, const std::vector<Index>& chain) {
  double sum = 0;
  for (std::size_t k = 1; k + 1 < chain.size(); ++k) {
    const Vec3 a = c.position[chain[k]] - c.position[chain[k - 1]], b = c.position[chain[k + 1]] - c.position[chain[k]];
    sum += std::acos(std::clamp(a.dot(b) / (a.norm() * b.norm()), -1.0, 1.0)) * 180 / M_PI;
  }
  return sum / static_cast<double>(chain.size() - 2);
}

/// A vein zig-zagging between two rows of a hex sheet packed at `spacing` (every joint turns 120 degrees),
/// rooted at a fixed petiole, after `steps` cell steps with the given straightening factors.
double zigzag_turn(double spacing, double vein_cohesion, double vein_separation, int steps, double* initial = nullptr,
                   bool straight = false) {
  Params p;  // the script defaults of the general and vein cells
  p.weights[0].separation = 0.05;
  p.weights[2].cohesion = 0.05;
  p.weights[2].separation = 0.05;
  p.vein_cohesion_factor = vein_cohesion;
  p.vein_separation_factor = vein_separation;
  p.division.trigger = DivisionTrigger::none;
  Simulation sim(p, 5);
  Cells& c = sim.cells();
  const int side = 24;
  c = cellform::testing::hex_sheet(side, side, spacing);
  std::vector<Index> chain;
  for (int k = 0; k < 16; ++k) {  // rows 11 and 12 alternately, each cell a lattice neighbour of the last
    const int row = straight ? 11 : 11 + k % 2,
              col = straight ? 4 + k : 4 + (k + 1) / 2;  // odd rows are shifted by half a cell
    chain.push_back(static_cast<Index>(row * side + col));
  }
  c.type[chain[0]] = CellType::petiole;
  c.fixed[chain[0]] = 1;
  for (std::size_t k = 1; k < chain.size(); ++k) {
    c.type[chain[k]] = CellType::vein;
    c.vein_parent[chain[k]] = chain[k - 1];
  }
  if (initial) *initial = mean_turn(c, chain);
  std::vector<std::uint64_t> ids;
  for (const Index i : chain) ids.push_back(c.id[i]);
  for (int s = 0; s < steps; ++s) sim.step();
  for (std::size_t k = 0; k < ids.size(); ++k)  // the cell arrays are re-sorted in space: find the chain by id
    chain[k] = static_cast<Index>(std::find(c.id.begin(), c.id.end(), ids[k]) - c.id.begin());
  for (std::size_t k = 1; k < chain.size(); ++k) REQUIRE(c.vein_parent[chain[k]] == chain[k - 1]);
  return mean_turn(c, chain);
}

}  // namespace

TEST_CASE("vein straightening: both terms straighten a crumpled vein; far more separation buckles a straight one",
          "[simulation]") {
  // Found by an audit: in grown leaves more vein_separation measured more bent veins. The terms do what the
  // paper says on a vein that zig-zags (it lengthens and straightens), but a vein already straight and held
  // by the sheet around it can only lengthen by buckling.
  for (const double spacing : {1.0, 0.85}) {  // at rest, and packed as grown sheets are
    INFO("sheet spacing " << spacing);
    double initial = 0;
    const double none = zigzag_turn(spacing, 0, 0, 1500, &initial);
    const double cohesion = zigzag_turn(spacing, 4, 0, 1500);
    const double both = zigzag_turn(spacing, 4, 4, 1500);  // the defaults
    INFO("mean turn " << initial << " -> none " << none << ", cohesion " << cohesion << ", both " << both);
    CHECK(initial == Approx(120));
    CHECK(std::abs(none - initial) < 5);  // the sheet alone keeps the vein's shape
    CHECK(cohesion < none - 20);
    CHECK(both < cohesion - 20);
  }
  double initial = 1;
  CHECK(zigzag_turn(0.85, 4, 4, 1500, &initial, true) < 1);
  CHECK(initial == Approx(0).margin(1e-9));
  CHECK(zigzag_turn(0.85, 4, 8, 1500, &initial, true) > 5);
}
