// Tests of auxin canalisation: analytic flows, conservation, forest structure, Murray radii, spacing.
#include "venation/canalisation.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>

#include "cells/simulation.h"
#include "core/errors.h"
#include "core/random.h"
#include "tests/fixtures.h"
#include "tests/venation/canalisation_fixtures.h"
#include "tests/venation/canalisation_oracle.h"

using namespace cellform;
using namespace cellform::test;  // chain, attr, grow, leaf
using Catch::Matchers::Contains;
using cells::CellType;
using core::Index;
using core::kNoIndex;

TEST_CASE("on a straight chain the flow at each cell is the number of cells upstream", "[venation]") {
  cells::Cells c = chain(12);
  venation::Params p;
  p.threshold = 1e9;  // no promotion: pure flow
  const auto r = grow(c, p, 1);
  const auto& flow = attr(c, venation::kFlow);
  for (int i = 0; i < 12; ++i) CHECK(flow[i] == 12 - i);  // itself and everything beyond it
  CHECK(r.petiole_inflow == 12);
  CHECK(r.total_source == 12);
  CHECK(r.promoted == 0);
}

TEST_CASE("a chain turns into a vein from the petiole outward, one cell per step", "[venation]") {
  cells::Cells c = chain(10);
  venation::Params p;
  p.threshold = 4.5;  // a cell with five or more cells upstream becomes a vein
  venation::Workspace ws;
  for (int step = 1; step <= 8; ++step) {
    const auto r = venation::canalise(c, p, {}, ws);
    // cells 1..5 carry flows 9..5 and pass 4.5, one more per step as the vein reaches them; cell 6 carries 4
    CHECK(r.vein_cells == std::min<std::size_t>(static_cast<std::size_t>(step), 5));
  }
  for (int i = 1; i <= 5; ++i) {
    CHECK(c.type[i] == CellType::vein);
    CHECK(c.vein_parent[i] == static_cast<Index>(i - 1));
  }
  CHECK(c.type[6] == CellType::general);
}

TEST_CASE("a cell drains into the neighbour of the previous layer with the largest flow", "[venation]") {
  // petiole 0 links to 2 then 1, so the search reaches 2 first and then, from 2, cells 3 and 5 (layer 2,
  // in that order). Cell 3 drains into 2 (its only option), so when cell 5, which touches both 1 and 2,
  // chooses, 2 already carries more than 1 and wins despite its larger index. Cell 4 hangs on 3.
  cells::Cells c;
  c.link_stride = 2;
  for (int i = 0; i < 6; ++i) cells::add_cell(c, core::Vec3(i, 0, 0));
  c.type[0] = CellType::petiole;
  auto link = [&](Index a, std::initializer_list<Index> b) {
    int k = 0;
    for (Index x : b) c.links[a * 2 + k++] = x;
  };
  link(0, {2, 1});
  link(3, {2});
  link(4, {3});
  link(5, {1, 2});
  venation::Params p;
  p.threshold = 1e9;
  grow(c, p, 1);
  const auto& flow = attr(c, venation::kFlow);
  CHECK(flow[3] == 2);  // 3 + 4
  CHECK(flow[2] == 4);  // 2 + 3 + 4 + 5
  CHECK(flow[1] == 1);
  CHECK(flow[0] == 6);
  // the flow direction of cell 5 points at cell 2
  CHECK(attr(c, venation::kFlowX)[5] == -1.0);
}

TEST_CASE("a cell next to the veins drains into the neighbouring vein cell of the largest flow", "[venation]") {
  // (a paper-fidelity audit: only layer 2 was tested directly.) Vein cells 1 and 2 hang on petiole 0; cell 3
  // touches both, cells 4, 5 and 6 only 2. The first pass knows no vein flow yet (all 0): the smaller index,
  // 1, wins. The choice reads the vein flows of the pass before (this pass's are known only after phase 2),
  // so in the second pass vein 2, which carried 4 against 2, wins.
  cells::Cells c;
  c.link_stride = 2;
  for (const core::Vec3& q : {core::Vec3(0, -1, 0), core::Vec3(-1, 0, 0), core::Vec3(1, 0, 0), core::Vec3(0, 1, 0),
                              core::Vec3(2, 1, 0), core::Vec3(3, 0, 0), core::Vec3(2, -1, 0)})
    cells::add_cell(c, q);
  c.type[0] = CellType::petiole;
  for (Index v : {1u, 2u}) {
    c.type[v] = CellType::vein;
    c.vein_parent[v] = 0;
    c.links[2 * v] = 0;
  }
  c.links[2 * 3] = 1, c.links[2 * 3 + 1] = 2;
  for (Index x : {4u, 5u, 6u}) c.links[2 * x] = 2;
  const venation::Params p{.threshold = 1e9};
  venation::Workspace ws;
  venation::canalise(c, p, {}, ws);
  const auto& flow = attr(c, venation::kFlow);
  CHECK((flow[1] == 2 && flow[2] == 4));    // 1 + 3, and 2 + 4 + 5 + 6
  CHECK(attr(c, venation::kFlowX)[3] < 0);  // towards cell 1
  venation::canalise(c, p, {}, ws);
  CHECK((flow[1] == 1 && flow[2] == 5 && flow[0] == 7));
  CHECK(attr(c, venation::kFlowX)[3] > 0);  // towards cell 2
}

TEST_CASE("flow is conserved into several petioles and the veins form a forest", "[venation]") {
  cells::Cells c = leaf(24, 24);
  c.type[c.size() - 12] = CellType::petiole;  // a second petiole at the top
  venation::Params p;
  p.threshold = 12;
  venation::Workspace ws;
  for (int s = 0; s < 60; ++s) {
    const auto r = venation::canalise(c, p, {}, ws);
    CHECK(r.total_source == static_cast<double>(c.size()));
    CHECK(r.petiole_inflow == r.total_source);  // integers: exact
    CHECK(r.unconnected == 0);
  }
  const auto& flow = attr(c, venation::kFlow);
  std::size_t veins = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c.type[i] != CellType::vein) continue;
    ++veins;
    // walking up the parents reaches a petiole without repeating a cell: a forest, no cycle
    std::set<Index> seen;
    Index v = static_cast<Index>(i);
    while (c.type[v] == CellType::vein) {
      REQUIRE(seen.insert(v).second);
      const Index par = c.vein_parent[v];
      REQUIRE(par != kNoIndex);
      CHECK(flow[par] >= flow[v] + p.source);  // parent flow is at least each child's and its own auxin
      v = par;
    }
    CHECK(c.type[v] == CellType::petiole);
  }
  CHECK(veins > 10);
  // both petioles collect veins
  std::set<Index> roots;
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c.type[i] == CellType::vein) {
      Index v = static_cast<Index>(i);
      while (c.type[v] == CellType::vein) v = c.vein_parent[v];
      roots.insert(v);
    }
  CHECK(roots.size() == 2);
  // each petiole takes in exactly the auxin of its own basin: the cells whose path (downstream, then vein
  // parents) ends there, counted by walking every cell's path
  std::map<Index, double> basin;
  for (std::size_t i = 0; i < c.size(); ++i) {
    Index v = static_cast<Index>(i);
    for (std::size_t hops = 0; c.type[v] != CellType::petiole; ++hops) {
      REQUIRE(hops < c.size());
      v = c.type[v] == CellType::vein ? c.vein_parent[v] : ws.downstream[v];
      REQUIRE(v < c.size());
    }
    basin[v] += p.source;
  }
  REQUIRE(basin.size() == 2);
  for (const auto& [petiole, auxin] : basin) {
    INFO("petiole cell " << petiole);
    CHECK(flow[petiole] == auxin);
    CHECK(auxin > 0.2 * static_cast<double>(c.size()));  // both drain a real share of the sheet
  }
}

TEST_CASE("negative vein flows in a state still give every cell its downstream choice", "[venation]") {
  // a run writes flows >= 0, but a forged checkpoint may hold any finite value; the first layer's choice
  // reads the vein nodes' last flows and must still pick one of them (it once picked none: a wild index)
  cells::Cells c = leaf(12, 12);
  venation::Params p;
  p.threshold = 8;
  grow(c, p, 10);
  auto& flow = c.attributes.at(venation::kFlow);
  std::size_t veins = 0;
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c.type[i] != CellType::general) {
      flow[i] = -5.0 - static_cast<double>(i);
      ++veins;
    }
  REQUIRE(veins > 3);
  venation::Workspace ws;
  const auto r = venation::canalise(c, p, {}, ws);
  CHECK(r.total_source == static_cast<double>(c.size()));
  CHECK(r.petiole_inflow == r.total_source);
}

TEST_CASE("a petiole hung on a vein passes its auxin on: the inflow is counted once, at the root", "[venation]") {
  cells::Cells c = chain(8);  // 0 a root petiole; veins 1 <- 2 hang on it; petiole 3 hangs on vein 2
  c.type[1] = c.type[2] = CellType::vein;
  c.type[3] = CellType::petiole;
  c.vein_parent[1] = 0, c.vein_parent[2] = 1, c.vein_parent[3] = 2;
  venation::Params p;
  p.threshold = 1e9;  // no promotion
  const auto r = grow(c, p, 1);
  CHECK(r.total_source == 8);
  CHECK(attr(c, venation::kFlow)[3] == 5);  // cells 3 to 7 drain into petiole 3, which passes them down the vein
  CHECK(attr(c, venation::kFlow)[0] == 8);  // all of it reaches the root petiole
  CHECK(r.petiole_inflow == r.total_source);
}

TEST_CASE("Murray radii satisfy r_parent^n = sum of r_child^n over every inflow", "[venation]") {
  for (double n : {2.0, 3.0}) {
    cells::Cells c = leaf(20, 20);
    venation::Params p;
    p.threshold = 8;
    p.murray_exponent = n;
    p.min_radius = 0;  // the law holds exactly only without the printable minimum
    p.radius_scale = 0.1;
    grow(c, p, 50);
    venation::Params q = p;
    q.threshold = 1e12;  // one more step without promotion so radii and flows belong to one state
    venation::Workspace ws;
    venation::canalise(c, q, {}, ws);
    const auto& flow = attr(c, venation::kFlow);
    const auto& radius = attr(c, venation::kRadius);
    const cells::VeinChildren ch = cells::vein_children(c);
    // the inflow of each cell measured apart from the flows' own sums: the general cells that chose it as
    // their downstream cell (the veinlets draining straight in), and for a vein node its vein children
    std::vector<double> drained(c.size(), 0.0);
    for (std::size_t x = 0; x < c.size(); ++x)
      if (c.type[x] == CellType::general) {
        REQUIRE(ws.downstream[x] < c.size());  // every cell of this connected sheet drains somewhere
        drained[ws.downstream[x]] += flow[x];
      }
    int checked = 0;
    for (std::size_t v = 0; v < c.size(); ++v) {
      if (c.type[v] == CellType::general) {
        CHECK(flow[v] == p.source + drained[v]);  // integers: exact
        continue;
      }
      double children = 0, child_flow = 0;
      for (Index s = ch.start[v]; s < ch.start[v + 1]; ++s) {
        children += std::pow(radius[ch.child[s]], n);
        child_flow += flow[ch.child[s]];
      }
      CHECK(flow[v] == p.source + drained[v] + child_flow);
      // Murray over every inflow: vein children, and the veinlets with the node's own auxin
      const double local = std::pow(p.radius_scale, n) * (p.source + drained[v]);
      CHECK(std::pow(radius[v], n) == Approx(children + local).epsilon(1e-12));
      checked += ch.start[v + 1] > ch.start[v] && drained[v] > 0;
    }
    CHECK(checked > 5);
  }
}

TEST_CASE("a higher threshold gives fewer vein cells on a fixed sheet", "[venation]") {
  std::size_t previous = ~std::size_t{0};
  for (double t : {4.0, 8.0, 16.0, 32.0, 64.0, 128.0}) {
    cells::Cells c = leaf(30, 30);
    venation::Params p;
    p.threshold = t;
    const auto r = grow(c, p, 120);
    INFO("threshold " << t << ": " << r.vein_cells << " vein cells");
    CHECK(r.vein_cells <= previous);
    previous = r.vein_cells;
  }
  CHECK(previous < 40);
}

TEST_CASE("vein orders: the main path is primary, branches are of higher order", "[venation]") {
  cells::Cells c = leaf(30, 30);
  venation::Params p;
  p.threshold = 10;
  grow(c, p, 150);
  const auto g = venation::vein_graph(c);
  int max_order = 0, primary = 0;
  for (int o : g.order) {
    max_order = std::max(max_order, o);
    primary += o == 1;
  }
  CHECK(primary > 0);
  CHECK(max_order >= 2);
  // along every edge the order never decreases from parent to child
  for (const auto& e : g.edges) CHECK(g.order[e[0]] >= g.order[e[1]]);
  CHECK(g.edges.size() + 1 == g.cell.size());  // one petiole: a tree
}

TEST_CASE("a vein graph before any canalisation pass says of a petiole what a pass would", "[venation]") {
  cells::Cells c = leaf(10, 10);
  venation::Params p;
  p.threshold = 1e9;  // no vein: the petiole stays a root without children
  p.min_radius = 0.1;
  const auto before = venation::vein_graph(c, &p);  // no pass yet: no flow, radius or order attributes
  REQUIRE(before.cell.size() == 1);
  venation::Workspace w;
  venation::canalise(c, p, {}, w, 1);
  const auto after = venation::vein_graph(c, &p);
  REQUIRE(after.cell.size() == 1);
  CHECK(before.order[0] == after.order[0]);
  CHECK(before.order[0] == 1);
  CHECK(before.radius[0] == venation::murray_radius(0.0, p));
  CHECK(before.radius[0] == 0.1);
  CHECK(after.radius[0] >= 0.1);  // the flow it collected since
}

TEST_CASE("vein orders hold at every fork after every step, the cells just promoted too", "[venation]") {
  // a cell promoted took its parent's order, though a child of larger flow had it already: two primaries
  // at one fork in the files of the last step (audit, December 2026)
  cells::Cells c = leaf(30, 30);
  venation::Params p;
  p.threshold = 10;
  venation::Workspace ws;
  std::size_t forks = 0, promoted = 0;
  for (int step = 0; step < 150; ++step) {
    promoted += venation::canalise(c, p, {}, ws, 2).promoted;
    const auto g = venation::vein_graph(c);
    std::vector<std::vector<std::uint32_t>> children(g.cell.size());
    std::vector<bool> has_parent(g.cell.size(), false);
    for (const auto& e : g.edges) {
      children[e[1]].push_back(e[0]);
      has_parent[e[0]] = true;
    }
    for (std::uint32_t v = 0; v < g.cell.size(); ++v) {
      if (children[v].empty()) continue;
      forks += children[v].size() > 1;
      std::uint32_t main = children[v][0];
      for (const std::uint32_t ch : children[v])  // the largest flow, ties to the smaller cell index
        if (g.flow[ch] > g.flow[main] || (g.flow[ch] == g.flow[main] && g.cell[ch] < g.cell[main])) main = ch;
      for (const std::uint32_t ch : children[v]) {
        const int want = !has_parent[v] ? 1 : ch == main ? g.order[v] : g.order[v] + 1;
        if (g.order[ch] != want)
          FAIL("step " << step << ": cell " << g.cell[ch] << " of order " << g.order[ch] << " under cell " << g.cell[v]
                       << " of order " << g.order[v] << ", want " << want);
      }
    }
  }
  CHECK(promoted > 20);
  CHECK(forks > 5);
}

namespace {

namespace oracle = venation::testing::oracle;

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

/// Runs the oracle on a copy of `c` and canalise (with `threads`) on `c`, and requires identical bits
/// in every output: attributes, types, vein parents, downstream choices and the report.
void check_against_oracle(cells::Cells& c, const venation::Params& p, const venation::SourceRule& rule,
                          venation::Workspace& ws, int threads) {
  cells::Cells ref = c;
  const oracle::Result want = oracle::canalise(ref, p, rule);
  const venation::Report got = venation::canalise(c, p, rule, ws, threads);
  REQUIRE(got.promoted == want.report.promoted);
  REQUIRE(got.vein_cells == want.report.vein_cells);
  REQUIRE(got.unconnected == want.report.unconnected);
  REQUIRE(std::memcmp(&got.total_source, &want.report.total_source, sizeof(double)) == 0);
  REQUIRE(std::memcmp(&got.petiole_inflow, &want.report.petiole_inflow, sizeof(double)) == 0);
  REQUIRE(c.type == ref.type);
  REQUIRE(c.vein_parent == ref.vein_parent);
  REQUIRE(ws.downstream == want.downstream);
  for (const char* name :
       {venation::kFlow, venation::kRadius, venation::kOrder, venation::kFlowX, venation::kFlowY, venation::kFlowZ}) {
    INFO(name);
    REQUIRE(same_bits(c.attributes.at(name), ref.attributes.at(name)));
  }
}

/// Steps both implementations side by side for `steps` steps, checking every step.
void run_against_oracle(cells::Cells& c, const venation::Params& p, int steps, int threads,
                        const venation::SourceRule& rule = {}) {
  venation::Workspace ws;
  for (int s = 0; s < steps; ++s) {
    INFO("step " << s);
    check_against_oracle(c, p, rule, ws, threads);
  }
}

/// A sheet grown by the cell system (irregular k-nearest links, many not mutual, spatially reordered),
/// with `petioles` petiole cells spread over it.
cells::Cells grown_sheet(int steps, int petioles, std::uint64_t seed) {
  cells::Params cp;
  cp.division.trigger = cells::DivisionTrigger::age;
  cp.division.division_age = 12;
  cp.division.probability = 0.6;
  cp.division.direction = cells::SplitDirection::tangent;
  cp.division.max_cells = 6000;
  cells::Simulation sim(cp, seed);
  sim.set_threads(1);
  sim.cells() = testing::hex_sheet(8, 8);
  for (int s = 0; s < steps; ++s) sim.step();
  cells::Cells c = sim.cells();
  for (int k = 0; k < petioles; ++k)
    c.type[(c.size() * static_cast<std::size_t>(2 * k + 1)) / (2 * petioles)] = CellType::petiole;
  return c;
}

}  // namespace

TEST_CASE("canalise matches the reference algorithm bit for bit on a hex leaf", "[venation][oracle]") {
  cells::Cells c = leaf(30, 30);
  c.type[c.size() - 7] = CellType::petiole;
  venation::Params p;
  p.threshold = 10;
  run_against_oracle(c, p, 120, 1);
}

TEST_CASE("canalise matches the reference algorithm on grown sheets with several petioles", "[venation][oracle]") {
  for (const int petioles : {1, 3}) {
    cells::Cells c = grown_sheet(90, petioles, 7 + static_cast<std::uint64_t>(petioles));
    INFO(c.size() << " cells, " << petioles << " petioles");
    REQUIRE(c.size() > 1000);
    venation::Params p;
    p.threshold = 25;
    run_against_oracle(c, p, 60, 2);
  }
}

TEST_CASE("canalise matches the reference algorithm with non-integer sources", "[venation][oracle]") {
  cells::Cells c = grown_sheet(70, 2, 3);
  venation::Params p;
  p.threshold = 9.5;
  const venation::SourceRule rule = [](const cells::Cells& cc, Index i) {
    return 0.1 + 0.37 * static_cast<double>(cc.id[i] % 7) + 1e-3 * cc.position[i].x() * cc.position[i].x();
  };
  run_against_oracle(c, p, 50, 2, rule);
  CHECK(std::count(c.type.begin(), c.type.end(), CellType::vein) > 20);  // the promotions were compared too
  // one strength for all, not a whole number: sums of 0.1 round, so a flow is the running sum the reference
  // adds up, not 0.1 times the count (the product is taken only where every partial sum is exact)
  cells::Cells u = grown_sheet(70, 2, 3);
  venation::Params q;
  q.source = 0.1;
  q.threshold = 0.95;
  run_against_oracle(u, q, 50, 2, {});
  CHECK(std::count(u.type.begin(), u.type.end(), CellType::vein) > 20);
}

TEST_CASE("a higher threshold gives fewer vein cells on grown sheets, for each seed", "[venation]") {
  // irregular links and spacing, where ties between neighbours are rare (the hex lattice test has many)
  for (std::uint64_t seed : {3u, 4u, 5u}) {
    const cells::Cells sheet = grown_sheet(70, 1, seed);
    std::size_t previous = ~std::size_t{0};
    for (double t : {5.0, 10.0, 20.0, 40.0, 80.0}) {
      cells::Cells c = sheet;
      venation::Params p;
      p.threshold = t;
      const auto r = grow(c, p, 150);
      INFO("seed " << seed << ", threshold " << t << ": " << r.vein_cells << " vein cells of " << c.size());
      CHECK(r.vein_cells < previous);
      previous = r.vein_cells;
    }
  }
}

TEST_CASE("a higher threshold spaces the veins farther apart on grown sheets", "[venation]") {
  // the paper: the threshold "controls the distance between adjacent veins". The mean distance from a cell
  // to the nearest vein or petiole cell (brute force) grows with it, for each seed.
  for (std::uint64_t seed : {3u, 4u}) {
    const cells::Cells sheet = grown_sheet(70, 1, seed);
    double previous = 0;
    for (double t : {5.0, 20.0, 80.0}) {
      cells::Cells c = sheet;
      venation::Params p;
      p.threshold = t;
      grow(c, p, 150);
      double sum = 0;
      for (std::size_t i = 0; i < c.size(); ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t j = 0; j < c.size(); ++j)
          if (c.type[j] != CellType::general) best = std::min(best, (c.position[j] - c.position[i]).norm());
        sum += best;
      }
      const double mean = sum / static_cast<double>(c.size());
      INFO("seed " << seed << ", threshold " << t << ": mean distance to a vein " << mean);
      CHECK(mean > previous * 1.15);
      previous = mean;
    }
  }
}

TEST_CASE("canalise matches the reference algorithm with unconnected islands and odd links", "[venation][oracle]") {
  // two sheets side by side without links between them; the petiole is on the first only. Then some
  // links are made one-way, duplicated, pointed at the cell itself or out of range.
  cells::Cells a = leaf(16, 16);
  cells::Cells b = testing::hex_sheet(10, 12);
  testing::link_lattice(b);
  const Index offset = static_cast<Index>(a.size());
  for (std::size_t i = 0; i < b.size(); ++i) {
    cells::add_cell(a, b.position[i] + core::Vec3(100, 0, 0));
    for (int k = 0; k < 6; ++k) {
      const Index l = b.links[i * 6 + static_cast<std::size_t>(k)];
      a.links[(offset + i) * 6 + static_cast<std::size_t>(k)] = l == kNoIndex ? kNoIndex : l + offset;
    }
  }
  core::Rng rng(5);
  const std::size_t n = a.size();
  for (int t = 0; t < 300; ++t) {
    const std::size_t i = rng.next() % offset;  // edits on the connected sheet only
    const std::size_t k = rng.next() % 6;
    switch (rng.next() % 4) {
      case 0:
        a.links[i * 6 + k] = static_cast<Index>(rng.next() % offset);
        break;  // one-way, maybe far
      case 1:
        a.links[i * 6 + k] = a.links[i * 6 + (k + 1) % 6];
        break;  // duplicate
      case 2:
        a.links[i * 6 + k] = static_cast<Index>(i);
        break;  // self
      default:
        a.links[i * 6 + k] = static_cast<Index>(n + rng.next() % 5);
        break;  // out of range
    }
  }
  // a vein fragment far from the petiole whose root hangs on a general cell: a sink of its own
  const Index tip = offset - 3, mid = offset - 4, root = offset - 5;
  a.type[tip] = a.type[mid] = a.type[root] = CellType::vein;
  a.vein_parent[tip] = mid;
  a.vein_parent[mid] = root;
  a.vein_parent[root] = offset - 40;
  venation::Params p;
  p.threshold = 6;
  run_against_oracle(a, p, 80, 1);
  venation::Workspace ws;
  CHECK(venation::canalise(a, p, {}, ws, 1).unconnected >= b.size());
}

TEST_CASE("canalise gives the same bits for 1 and 2 threads on a large sheet", "[venation][oracle]") {
  cells::Cells one = grown_sheet(140, 2, 11);
  REQUIRE(one.size() > 5000);  // above the parallel chunk size
  cells::Cells two = one;
  venation::Params p;
  p.threshold = 30;
  venation::Workspace w1, w2;
  for (int s = 0; s < 40; ++s) {
    const venation::Report r1 = venation::canalise(one, p, {}, w1, 1);
    const venation::Report r2 = venation::canalise(two, p, {}, w2, 2);
    REQUIRE(r1.promoted == r2.promoted);
    REQUIRE(std::memcmp(&r1.total_source, &r2.total_source, sizeof(double)) == 0);
    REQUIRE(one.type == two.type);
    REQUIRE(one.vein_parent == two.vein_parent);
    for (const auto& [name, values] : one.attributes) REQUIRE(same_bits(values, two.attributes.at(name)));
  }
  venation::Workspace w3;
  check_against_oracle(one, p, {}, w3, 2);  // and both still agree with the oracle
}
