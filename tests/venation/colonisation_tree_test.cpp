// Tests of venation/colonisation_tree.cpp: stems from anchors to the roots of a vein tree.
#include <catch2/catch.hpp>
#include <cmath>

#include "venation/colonisation.h"

using namespace cellform;
using Catch::Matchers::Contains;
using core::Index;
using core::kNoIndex;
using core::Vec3;
namespace v = cellform::venation;

TEST_CASE("with_stems joins each root to its anchor where they differ, keeping parents before children",
          "[colonisation]") {
  // two roots (0 and 1), a branch 0 -> 2 -> 3, 1 -> 4, and an anastomosis 3 - 4
  v::VeinTree t;
  t.positions = {Vec3(0, 0, 0), Vec3(5, 0, 0), Vec3(0, 1, 0), Vec3(0, 2, 0), Vec3(5, 1, 0)};
  t.parent = {kNoIndex, kNoIndex, 0, 2, 1};
  t.birth_step = {0, 0, 1, 2, 1};
  t.anastomoses = {{3, 4}};
  // root 0 stands on its anchor; root 1's anchor is 1.5 below it
  const v::VeinTree s = v::with_stems(t, {Vec3(0, 0, 0), Vec3(5, 0, -1.5)}, 1e-9);
  REQUIRE(s.size() == 6);
  CHECK(s.positions[0] == Vec3(5, 0, -1.5));  // the stem's node first
  CHECK(s.parent[0] == kNoIndex);
  for (Index i = 0; i < t.size(); ++i) CHECK(s.positions[i + 1] == t.positions[i]);
  CHECK(s.parent[1] == kNoIndex);  // root 0 had no stem
  CHECK(s.parent[2] == 0);         // root 1 hangs from its stem
  CHECK(s.parent[3] == 1);
  CHECK(s.parent[4] == 3);
  CHECK(s.parent[5] == 2);
  for (Index i = 0; i < s.size(); ++i)
    if (s.parent[i] != kNoIndex) CHECK(s.parent[i] < i);  // compute_widths' one reverse pass holds
  CHECK(s.anastomoses == std::vector<std::pair<Index, Index>>{{4, 5}});
  CHECK(s.birth_step == std::vector<std::uint32_t>{0, 0, 0, 1, 2, 1});
  // widths then run through the stem: it carries root 1's whole flow
  v::VeinTree w = s;
  v::compute_widths(w, {});
  CHECK(w.flow[0] == Approx(w.flow[2]));
  // anchors within min_length add nothing; the anchors must be one per root
  CHECK(v::with_stems(t, {Vec3(0, 0, 0), Vec3(5, 0, 1e-12)}, 1e-9).size() == t.size());
  // "more than min_length apart": an anchor exactly min_length away adds nothing
  CHECK(v::with_stems(t, {Vec3(0, 0, 0), Vec3(5, 0, -1.5)}, 1.5).size() == t.size());
  CHECK(v::with_stems(t, {Vec3(0, 0, 0), Vec3(5, 0, -1.5)}, 1.25).size() == t.size() + 1);
  CHECK_THROWS_WITH(v::with_stems(t, {Vec3(0, 0, 0)}, 1e-9), Contains("1 anchors for 2 roots"));
}

TEST_CASE("independent cycles: a loop counts, a join of two seeds' trees does not", "[colonisation]") {
  // two seeds 0 and 1, each with a chain of two nodes: 0 <- 2 <- 4 and 1 <- 3 <- 5
  v::VeinTree t;
  for (int i = 0; i < 6; ++i) t.positions.emplace_back(i, 0, 0);
  t.parent = {cellform::core::kNoIndex, cellform::core::kNoIndex, 0, 1, 2, 3};
  CHECK(v::independent_cycles(t) == 0);
  t.anastomoses.push_back({4, 5});  // joins the two trees: no cycle yet (a review found run.json's loops said 1)
  CHECK(v::independent_cycles(t) == 0);
  t.anastomoses.push_back({2, 3});  // now 2-4-5-3-2 is a cycle
  CHECK(v::independent_cycles(t) == 1);
  t.anastomoses.push_back({0, 4});  // and 0-2-4-0
  CHECK(v::independent_cycles(t) == 2);
  // E - V + C: 4 parent edges and 3 anastomoses, 6 nodes, 1 component
  CHECK(v::independent_cycles(t) == 4 + t.anastomoses.size() - 6 + 1);
}

TEST_CASE("compute_widths: the child of the largest flow continues its parent's order, the others start the next",
          "[colonisation]") {
  //   0 -> 1 -> 3 -> 5, 6, 7     0 -> 2     1 -> 4     (2, 4, 5, 6 and 7 are tips)
  v::VeinTree t;
  t.parent = {kNoIndex, 0, 0, 1, 1, 3, 3, 3};
  t.positions.assign(t.parent.size(), Vec3::Zero());
  t.birth_step.assign(t.parent.size(), 0);
  v::WidthParams w;
  w.tip_radius = 0.5;
  w.exponent = 2;
  w.per_node_flow = 0;
  v::compute_widths(t, w);
  // flows count the tips drained: 0: 5, 1: 4, 2: 1, 3: 3, 4: 1, tips 1
  CHECK(t.flow == std::vector<double>{5, 4, 1, 3, 1, 1, 1, 1});
  for (std::size_t i = 0; i < t.size(); ++i) CHECK(t.radius[i] == Approx(0.5 * std::sqrt(t.flow[i])));
  // 0 primary; its larger child 1 goes on as primary, 2 is secondary; at 1, 3 (flow 3) goes on, 4 is secondary;
  // at 3 the three tips tie: the first (5) goes on, 6 and 7 are secondary
  CHECK(t.order == std::vector<std::uint32_t>{1, 1, 2, 1, 2, 1, 2, 2});
}

TEST_CASE("a negative per-node flow is refused", "[colonisation]") {
  v::VeinTree t;
  t.positions = {Vec3::Zero(), Vec3(1, 0, 0)};
  t.parent = {kNoIndex, 0};
  t.birth_step = {0, 1};
  v::WidthParams w;
  w.per_node_flow = -1;
  CHECK_THROWS_WITH(v::compute_widths(t, w), Contains("per_node_flow"));
}
