// Tests of auxin canalisation: analytic flows, conservation, forest structure, Murray radii, spacing.
#include "venation/canalisation.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <set>

#include "core/errors.h"
#include "tests/fixtures.h"

using namespace cellform;
using Catch::Matchers::Contains;
using cells::CellType;
using core::Index;
using core::kNoIndex;

namespace {

/// A chain of n cells along x, each linked to its predecessor and successor, petiole at index 0.
cells::Cells chain(int n) {
  cells::Cells c;
  c.link_stride = 2;
  for (int i = 0; i < n; ++i) cells::add_cell(c, core::Vec3(i, 0, 0));
  for (int i = 0; i < n; ++i) {
    c.links[2 * i] = i > 0 ? static_cast<Index>(i - 1) : kNoIndex;
    c.links[2 * i + 1] = i + 1 < n ? static_cast<Index>(i + 1) : kNoIndex;
  }
  c.type[0] = CellType::petiole;
  return c;
}

const std::vector<double>& attr(const cells::Cells& c, const char* name) { return c.attributes.at(name); }

/// Runs canalisation `steps` times on a fixed sheet.
venation::Report grow(cells::Cells& c, const venation::Params& p, int steps) {
  venation::Workspace ws;
  venation::Report r;
  for (int s = 0; s < steps; ++s) r = venation::canalise(c, p, {}, ws);
  return r;
}

/// The hex sheet with a petiole in the middle of its bottom row.
cells::Cells leaf(int rows, int cols) {
  cells::Cells c = testing::hex_sheet(rows, cols);
  testing::link_lattice(c);
  c.type[static_cast<std::size_t>(cols / 2)] = CellType::petiole;
  return c;
}

}  // namespace

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
      CHECK(flow[par] >= flow[v]);  // parent flow is at least each child's
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
    grow(c, q, 1);
    const auto& flow = attr(c, venation::kFlow);
    const auto& radius = attr(c, venation::kRadius);
    const cells::VeinChildren ch = cells::vein_children(c);
    int checked = 0;
    for (std::size_t v = 0; v < c.size(); ++v) {
      if (c.type[v] == CellType::general) continue;
      double children = 0, child_flow = 0;
      for (Index s = ch.start[v]; s < ch.start[v + 1]; ++s) {
        children += std::pow(radius[ch.child[s]], n);
        child_flow += flow[ch.child[s]];
      }
      // the cells draining straight into v are veinlets of flow (flow[v] - child_flow)
      const double local = std::pow(p.radius_scale, n) * (flow[v] - child_flow);
      CHECK(std::pow(radius[v], n) == Approx(children + local).epsilon(1e-12));
      checked += ch.start[v + 1] > ch.start[v];
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

TEST_CASE("bad input is refused with a clear message", "[venation]") {
  venation::Params p;
  p.threshold = 0;
  CHECK_THROWS_WITH(venation::validate(p), Contains("venation.threshold"));
  p = {};
  p.murray_exponent = 0;
  CHECK_THROWS_WITH(venation::validate(p), Contains("venation.murray_exponent"));
  cells::Cells c = chain(5);
  c.type[0] = CellType::general;
  venation::Workspace ws;
  CHECK_THROWS_WITH(venation::canalise(c, {}, {}, ws), Contains("needs at least one petiole"));
  c.type[0] = CellType::petiole;
  const venation::SourceRule bad = [](const cells::Cells& cc, Index i) { return cc.id[i] == 3 ? -1.0 : 1.0; };
  CHECK_THROWS_WITH(venation::canalise(c, {}, bad, ws), Contains("cell 3"));
}
