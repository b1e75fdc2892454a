// Tests of the cell table rule functions read: a misspelt field is an error naming the closest one.
#include <catch2/catch.hpp>

#include "app/script_host.h"
#include "cells/cells.h"
#include "core/errors.h"

using Catch::Matchers::Contains;
using cellform::app::ScriptHost;

namespace {
/// Whether the division rule `body` (a Lua expression of `cell`) holds for the first of two cells.
bool divides(const std::string& body, const cellform::cells::Cells& c) {
  ScriptHost host;
  host.load("disc { radius = 2 }\ndivision { rule = function(cell)\n  return " + body + "\nend }\n", "rule.lua", {});
  return host.rules().divides(c, 0);
}
}  // namespace

TEST_CASE("a rule reading a field the cell table does not have is stopped, with the closest name", "[script]") {
  cellform::cells::Cells c;
  cellform::cells::add_cell(c, {1, 0, 0});
  cellform::cells::add_cell(c, {-1, 0, 0});
  c.age = {3, 3};
  // the comparison with a misspelt field was always true (nil ~= "vein")
  CHECK_THROWS_WITH(divides("cell.typ ~= 'vein'", c),
                    Contains("rule.lua:3: cell.typ: the cell table has no such field; did you mean 'type'?"));
  CHECK_THROWS_WITH(divides("cell.neighbors < 6", c), Contains("did you mean 'neighbours'?"));
  CHECK_THROWS_WITH(divides("cell.flo > 3", c), Contains("cell.flo:") && Contains("did you mean 'flow'?"));
  CHECK_THROWS_WITH(divides("cell.zzzzzzzz == 1", c), Contains("no such field (its fields: id, index,"));
  // every documented field reads, and venation's attributes are nil before canalisation made them
  CHECK(divides("cell.type == 'general' and cell.age == 3 and cell.x == 1 and cell.step >= 0 and cell.fixed == false",
                c));
  CHECK(
      divides("cell.id + cell.index + cell.generation + cell.y + cell.z + cell.vx + cell.vy + cell.vz + "
              "cell.neighbours >= 0",
              c));
  CHECK(divides("cell.flow == nil and cell.vein_radius == nil and cell.vein_order == nil and cell.flow_dx == nil", c));
  cellform::cells::attribute(c, "flow") = {7, 8};
  CHECK(divides("cell.flow == 7", c));
  // keys that are not names are no fields: nil, as for any table
  CHECK(divides("cell[1] == nil and cell[true] == nil", c));
}
