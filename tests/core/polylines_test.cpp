// core::polylines: every edge once, inner vertices of degree two, branches of a tree as polylines.
#include "core/polylines.h"

#include <catch2/catch.hpp>
#include <map>
#include <set>

#include "core/random.h"

using cellform::core::Index;
using cellform::core::polylines;
using Edges = std::vector<std::array<Index, 2>>;
using Lines = std::vector<std::vector<Index>>;

TEST_CASE("polylines of a path, a tree and a cycle", "[core][polylines]") {
  CHECK(polylines(4, Edges{{0, 1}, {1, 2}, {2, 3}}) == Lines{{0, 1, 2, 3}});
  // a vein tree, edges child -> parent: the branches between tips, forks and the root, each towards the root
  CHECK(polylines(5, Edges{{1, 0}, {2, 1}, {3, 1}, {4, 3}}) == Lines{{1, 0}, {2, 1}, {4, 3, 1}});
  CHECK(polylines(4, Edges{{0, 1}, {1, 2}, {2, 0}}) == Lines{{0, 1, 2, 0}});  // vertex 3 has no edge
  // a root with two children ends both branches; so does a node with two parents
  CHECK(polylines(5, Edges{{1, 0}, {2, 0}, {3, 1}, {4, 2}}) == Lines{{3, 1, 0}, {4, 2, 0}});
  CHECK(polylines(3, Edges{{1, 0}, {1, 2}}) == Lines{{1, 0}, {1, 2}});
  CHECK(polylines(3, Edges{{0, 1}, {1, 0}}) == Lines{{0, 1, 0}});  // two edges between the same two
  CHECK(polylines(2, Edges{{1, 1}}).empty());                      // a loop at one vertex is no line
}

TEST_CASE("polylines of random graphs: every edge once, and only degree-two vertices inside", "[core][polylines]") {
  cellform::core::Rng rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = 2 + static_cast<std::size_t>(rng.uniform(0, 60));
    Edges e;
    for (Index v = 1; v < n; ++v)  // a forest (child -> parent), then some extra edges making loops
      if (rng.uniform() < 0.9) e.push_back({v, static_cast<Index>(rng.uniform(0, v))});
    for (int k = 0; k < static_cast<int>(rng.uniform(0, 6)); ++k) {
      const auto a = static_cast<Index>(rng.uniform(0, static_cast<double>(n))),
                 b = static_cast<Index>(rng.uniform(0, static_cast<double>(n)));
      if (a != b && a < n && b < n) e.push_back({a, b});
    }
    std::map<std::pair<Index, Index>, int> want;  // undirected edge -> copies
    std::vector<int> in(n, 0), out(n, 0);
    for (const auto& [a, b] : e) {
      ++want[{std::min(a, b), std::max(a, b)}];
      ++out[a];
      ++in[b];
    }
    auto passes = [&](Index v) { return in[v] == 1 && out[v] == 1; };  // a polyline runs through v
    std::map<std::pair<Index, Index>, int> got, directed_want, directed_got;
    for (const auto& [a, b] : e) ++directed_want[{a, b}];
    for (const auto& line : polylines(n, e)) {
      REQUIRE(line.size() >= 2);
      for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        ++got[{std::min(line[i], line[i + 1]), std::max(line[i], line[i + 1])}];
        ++directed_got[{line[i], line[i + 1]}];  // along the edges' direction throughout
      }
      for (std::size_t i = 1; i + 1 < line.size(); ++i) CHECK(passes(line[i]));
      if (line.front() != line.back()) {  // maximal
        CHECK_FALSE(passes(line.front()));
        CHECK_FALSE(passes(line.back()));
      }
    }
    CHECK(got == want);
    CHECK(directed_got == directed_want);
  }
}
