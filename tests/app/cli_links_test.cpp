// Tests that the cell files link the cells as they lie when written: the k nearest of each, as a brute-force
// search finds them, also right after a step that divided every cell.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <set>
#include <utility>
#include <vector>

#include "tests/app/test_util.h"
#include "tests/export/ply_reader.h"

using namespace cellform::test;
namespace fs = std::filesystem;

namespace {

/// The links (i < j) of the k = 6 nearest cells of each cell within 1.5 rest lengths (the defaults), ties to the
/// smaller index, by brute force over `p`'s positions; and the edges `p` holds.
std::pair<std::set<std::array<int, 2>>, std::set<std::array<int, 2>>> links_and_edges(const Ply& p) {
  const PlyElement& v = p.elements.at(0);
  REQUIRE(v.name == "vertex");
  const auto n = static_cast<int>(v.count);
  auto d2 = [&](int i, int j) {
    double s = 0;
    for (int k = 0; k < 3; ++k) s += (v.rows[i][k] - v.rows[j][k]) * (v.rows[i][k] - v.rows[j][k]);
    return s;
  };
  std::set<std::array<int, 2>> want, have;
  for (int i = 0; i < n; ++i) {
    std::vector<std::pair<double, int>> by;
    for (int j = 0; j < n; ++j)
      if (j != i) by.push_back({d2(i, j), j});
    std::sort(by.begin(), by.end());
    for (std::size_t s = 0; s < std::min<std::size_t>(6, by.size()) && by[s].first <= 1.5 * 1.5; ++s)
      want.insert({std::min(i, by[s].second), std::max(i, by[s].second)});
  }
  for (const PlyElement& e : p.elements)
    if (e.name == "edge")
      for (const auto& row : e.rows) {
        const int a = static_cast<int>(row[0]), b = static_cast<int>(row[1]);
        have.insert({std::min(a, b), std::max(a, b)});
      }
  return {want, have};
}

}  // namespace

TEST_CASE("cells.ply and the frames link the cells as they lie, also after a step that divided them all",
          "[cli][files]") {
  // a review: the files took the links the last step made before it moved and divided the cells, so each
  // daughter held a copy of her mother's row and no row held her; the surface was a patchwork of the two
  TempDir t("cli-fresh-links");
  const auto script = t.write("lockstep.lua",
                              "division { trigger = 'age', age = 5, min_age = 1, probability = 1, max_cells = 1000 }\n"
                              "run { steps = 10 }\noutput { every = 5 }\ndisc { radius = 2.5 }\n");
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet"}).code == 0);
  for (const char* file : {"cells.ply", "frames/cells_000005.ply", "frames/cells_000010.ply"}) {
    INFO(file);
    const Ply p = parse_ply(slurp(out / file));
    const auto [want, have] = links_and_edges(p);
    CHECK(want.size() > 100);
    CHECK(have == want);
  }
  CHECK(slurp(out / "cells.ply") == slurp(out / "frames/cells_000010.ply"));
  // and the run goes on from its checkpoint as an unbroken one does: the steps link the cells again
  REQUIRE(cli({"run", script.string(), "--out", (t.path / "whole").string(), "--quiet", "--steps", "14"}).code == 0);
  REQUIRE(cli({"resume", out.string(), "--steps", "14", "--quiet"}).code == 0);
  CHECK(slurp(out / "cells.ply") == slurp(t.path / "whole" / "cells.ply"));
}
