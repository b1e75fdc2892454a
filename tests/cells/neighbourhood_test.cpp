// update_links against a brute-force k-nearest oracle.
#include <algorithm>
#include <catch2/catch.hpp>
#include <utility>

#include "cells/simulation.h"
#include "core/random.h"
#include "tests/fixtures.h"

using namespace cellform::cells;

namespace {

void check_links(const Cells& c, int k) {
  REQUIRE(c.link_stride == k);
  REQUIRE(c.links.size() == c.size() * static_cast<std::size_t>(k));
  for (std::size_t i = 0; i < c.size(); ++i) {
    std::vector<std::pair<double, Index>> all;
    for (std::size_t j = 0; j < c.size(); ++j)
      if (j != i) all.push_back({(c.position[j] - c.position[i]).squaredNorm(), static_cast<Index>(j)});
    const auto keep = std::min<std::size_t>(static_cast<std::size_t>(k), all.size());
    std::partial_sort(all.begin(), all.begin() + static_cast<long>(keep), all.end());
    for (int s = 0; s < k; ++s) {
      const Index expected = s < static_cast<int>(all.size()) ? all[static_cast<std::size_t>(s)].second : kNoIndex;
      INFO("cell " << i << " slot " << s);
      REQUIRE(c.links[i * static_cast<std::size_t>(k) + static_cast<std::size_t>(s)] == expected);
    }
  }
}

}  // namespace

TEST_CASE("update_links equals the brute-force oracle (random cloud)", "[neighbourhood]") {
  cellform::core::Rng rng(42);
  Cells c;
  for (int i = 0; i < 3000; ++i) add_cell(c, Vec3(rng.uniform(0, 20), rng.uniform(0, 20), rng.uniform(-0.3, 0.3)));
  Params p;
  p.link_range = 0;  // pure k nearest, as the oracle
  cellform::core::PointGrid grid;
  for (int threads : {1, 2}) {
    update_links(c, p, grid, threads);
    check_links(c, 6);
  }
  p.neighbours = 9;
  update_links(c, p, grid, 2);
  check_links(c, 9);
}

TEST_CASE("update_links on a lattice breaks ties by index; pads when cells are few", "[neighbourhood]") {
  Cells c = cellform::testing::hex_sheet(12, 12);
  Params p;
  p.link_range = 0;  // pure k nearest, as the oracle
  cellform::core::PointGrid grid;
  update_links(c, p, grid, 1);
  check_links(c, 6);

  Cells few;
  add_cell(few, Vec3(0, 0, 0));
  add_cell(few, Vec3(1, 0, 0));
  add_cell(few, Vec3(0, 5, 0));
  update_links(few, p, grid, 1);
  check_links(few, 6);
  REQUIRE(few.links[0] == 1);
  REQUIRE(few.links[2] == kNoIndex);
}

TEST_CASE("links follow cells that come closer", "[neighbourhood]") {
  Cells c = cellform::testing::hex_sheet(6, 6);
  Params p;
  p.link_range = 0;  // pure k nearest, as the oracle
  cellform::core::PointGrid grid;
  update_links(c, p, grid, 1);
  const Index far = 35, centre = 14;
  REQUIRE(std::find(c.links.begin() + centre * 6, c.links.begin() + centre * 6 + 6, far) ==
          c.links.begin() + centre * 6 + 6);
  c.position[far] = c.position[centre] + Vec3(0, 0, 0.3);
  update_links(c, p, grid, 1);
  REQUIRE(c.links[centre * 6] == far);
  check_links(c, 6);
}

TEST_CASE("link_range keeps only the k nearest within range, over several steps", "[neighbourhood]") {
  // a hex sheet: interior cells have six neighbours at 1; rim cells' sixth-nearest lie at sqrt(3) or 2
  Cells c = cellform::testing::hex_sheet(9, 9);
  Params p;
  p.link_range = 1.5;
  cellform::core::PointGrid grid;
  for (int step = 0; step < 3; ++step) {  // later steps use the truncated links as hints
    update_links(c, p, grid, 1);
    for (std::size_t i = 0; i < c.size(); ++i) {
      std::vector<std::pair<double, Index>> all;
      for (std::size_t j = 0; j < c.size(); ++j)
        if (j != i) all.push_back({(c.position[j] - c.position[i]).squaredNorm(), static_cast<Index>(j)});
      std::sort(all.begin(), all.end());
      for (int s = 0; s < 6; ++s) {
        const bool in_range = all[static_cast<std::size_t>(s)].first <= 1.5 * 1.5;
        INFO("cell " << i << " slot " << s);
        CHECK(c.links[i * 6 + static_cast<std::size_t>(s)] ==
              (in_range ? all[static_cast<std::size_t>(s)].second : kNoIndex));
      }
    }
  }
  // a corner cell of the lattice has 2 or 3 neighbours within range, never more
  int fewest = 6;
  for (std::size_t i = 0; i < c.size(); ++i) {
    int n = 0;
    for (int s = 0; s < 6; ++s) n += c.links[i * 6 + static_cast<std::size_t>(s)] != kNoIndex;
    fewest = std::min(fewest, n);
  }
  CHECK(fewest <= 3);
  p.link_range = 0.5;
  CHECK_THROWS_WITH(validate(p), Catch::Matchers::Contains("cells.link_range"));
}

TEST_CASE("link_range is in rest lengths, and a cell with no neighbour in range keeps no link", "[neighbourhood]") {
  // a sparse random cloud at a rest length of 2 (range 3 model units): some cells have a few neighbours in
  // range, some none at all (their nearest one too is dropped); brute force over every pair
  cellform::core::Rng rng(7);
  Cells c;
  for (int i = 0; i < 400; ++i) add_cell(c, Vec3(rng.uniform(0, 60), rng.uniform(0, 60), rng.uniform(-1, 1)));
  add_cell(c, Vec3(200, 200, 0));  // alone
  Params p;
  p.rest_length = 2;
  p.link_range = 1.5;
  cellform::core::PointGrid grid;
  int without = 0, partial = 0;
  for (int threads : {1, 2}) {
    update_links(c, p, grid, threads);
    for (std::size_t i = 0; i < c.size(); ++i) {
      std::vector<std::pair<double, Index>> all;
      for (std::size_t j = 0; j < c.size(); ++j)
        if (j != i) all.push_back({(c.position[j] - c.position[i]).squaredNorm(), static_cast<Index>(j)});
      std::sort(all.begin(), all.end());
      int kept = 0;
      for (int s = 0; s < 6; ++s) {
        const bool in_range = all[static_cast<std::size_t>(s)].first <= 3.0 * 3.0;
        kept += in_range;
        INFO("cell " << i << " slot " << s);
        REQUIRE(c.links[i * 6 + static_cast<std::size_t>(s)] ==
                (in_range ? all[static_cast<std::size_t>(s)].second : kNoIndex));
      }
      without += kept == 0;
      partial += kept > 0 && kept < 6;
    }
  }
  CHECK(without >= 2);  // the lone cell, at least, in each pass
  CHECK(partial > 100);
}
