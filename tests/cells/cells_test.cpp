// add_cell, attributes, vein children and reordering.
#include "cells/cells.h"

#include <catch2/catch.hpp>

using namespace cellform::cells;

TEST_CASE("add_cell appends a resting cell with a fresh id and padded links", "[cells]") {
  Cells c;
  attribute(c, "flow", 2.0);
  REQUIRE(add_cell(c, Vec3(1, 2, 3)) == 0);
  REQUIRE(add_cell(c, Vec3(4, 5, 6), CellType::petiole, true) == 1);
  REQUIRE(c.size() == 2);
  REQUIRE(c.id == std::vector<std::uint64_t>{0, 1});
  REQUIRE(c.next_id == 2);
  REQUIRE(c.fixed[1] == 1);
  REQUIRE(c.type[1] == CellType::petiole);
  REQUIRE(c.links.size() == 2 * static_cast<std::size_t>(c.link_stride));
  for (Index l : c.links) REQUIRE(l == kNoIndex);
  REQUIRE(c.attributes["flow"].size() == 2);
  REQUIRE(attribute(c, "age2", 7.0) == std::vector<double>{7.0, 7.0});
  REQUIRE(attribute(c, "age2", 1.0) == std::vector<double>{7.0, 7.0});  // found, not refilled
}

TEST_CASE("vein_children lists children in index order", "[cells]") {
  Cells c;
  for (int i = 0; i < 6; ++i) add_cell(c, Vec3(i, 0, 0), CellType::vein);
  c.vein_parent = {kNoIndex, 0, 0, 1, kNoIndex, 0};
  const VeinChildren vc = vein_children(c);
  REQUIRE(vc.start == std::vector<Index>{0, 3, 4, 4, 4, 4, 4});
  REQUIRE(vc.child == std::vector<Index>{1, 2, 5, 3});
}

TEST_CASE("reorder moves every array and remaps indices", "[cells]") {
  Cells c;
  for (int i = 0; i < 4; ++i) add_cell(c, Vec3(i, 0, 0));
  c.vein_parent = {kNoIndex, 0, 1, 2};
  auto& flow = attribute(c, "flow");
  flow = {10, 11, 12, 13};
  c.links[0] = 1;
  c.links[6] = 0;
  c.links[6 + 1] = 2;
  const std::vector<Index> perm = {3, 1, 0, 2};  // perm[new] = old
  reorder(c, perm);
  REQUIRE(c.id == std::vector<std::uint64_t>{3, 1, 0, 2});
  REQUIRE(c.position[0].x() == 3);
  REQUIRE(c.attributes["flow"] == std::vector<double>{13, 11, 10, 12});
  // old parents: 3->2, 1->0, 0->none, 2->1 ; old->new: 0->2, 1->1, 2->3, 3->0
  REQUIRE(c.vein_parent == std::vector<Index>{3, 2, kNoIndex, 1});
  REQUIRE(c.links[2 * 6] == 1);      // old cell 0 linked old 1
  REQUIRE(c.links[1 * 6] == 2);      // old cell 1 linked old 0 ...
  REQUIRE(c.links[1 * 6 + 1] == 3);  // ... and old 2
  REQUIRE(c.links[1 * 6 + 2] == kNoIndex);
}
