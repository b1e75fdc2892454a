// Tests of the tables a script reads: the cell table of rule functions (a misspelt field is an error naming
// the closest one) and the knobs of params{} (read-only, printable).
#include <catch2/catch.hpp>

#include "app/script_host.h"
#include "cells/cells.h"
#include "core/errors.h"
#include "tests/app/script_test_util.h"

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

TEST_CASE("params{} knobs are read-only, iterate with pairs, next and rawget, and print as values", "[script]") {
  using cellform::test::load;
  using cellform::test::load_error;
  // changing one changed the run but not run.json's record of the knob: refused at the params{} line
  CHECK_THAT(load_error("local P = params { size = 500 }\ndisc { radius = 2 }\nP.size = 900\n"),
             Contains("test/leaf.lua:1: params: the script changed the knob size from 500 to 900") &&
                 Contains("--set size=VALUE"));
  CHECK_THAT(load_error("local P = params { n = 3 }\nrawset(P, 'n', 9)\n"), Contains("knob n from 3 to 9"));
  CHECK_THAT(load_error("local P = params { n = 3 }\nP.n = nil\n"), Contains("knob n from 3 to \"nil\""));
  CHECK_THAT(load_error("local P = params { size = 500 }\nsetmetatable(P, nil)\n"), Contains("protected metatable"));
  // a value set back, a field of the script's own and a NaN knob are no change
  CHECK_NOTHROW(load("local P = params { n = 3 }\nP.n = 4\nP.n = 3\n"));
  CHECK_NOTHROW(load("local P = params { size = 500 }\nP.other = P.size + 1\nP.other = P.other + 1\n"));
  CHECK_NOTHROW(load("local P = params { bad = 0/0 }\n"));
  // a misspelt knob is still named
  CHECK_THAT(load_error("local P = params { size = 500 }\ndisc { radius = P.sise }\n"),
             Contains(":2: params has no knob 'sise'; did you mean 'size'?"));
  // reads, pairs, next, rawget and --set as before
  cellform::app::Overrides o{{"radius", "3"}};
  const auto cfg = load(
      "local P = params { radius = 2, name = 'x' }\n"
      "local n = 0\nfor k, v in pairs(P) do n = n + 1 assert(P[k] == v) end\nassert(n == 2)\n"
      "local m = 0\nfor k, v in next, P do m = m + 1 end\nassert(m == 2)\n"
      "assert(rawget(P, 'radius') == 3)\n"
      "disc { radius = rawget(P, 'radius') or 5 }\n",
      o);
  CHECK(cfg.resolved["params"]["radius"] == 3);
  CHECK(cfg.initial_cells.size() == load("disc { radius = 3 }\n").initial_cells.size());
  // print(P) prints the knobs (it was taken for a print{} section with their names as settings)
  std::vector<std::string> lines;
  ScriptHost host;
  host.set_print([&](const std::string& line) { lines.push_back(line); });
  host.load(
      "local P = params { size = 300, vein_spacing = 20, name = 'leaf', flat = true }\nP.own = 1\nprint(P)\n"
      "disc { radius = 2 }\n",
      "p.lua", {});
  REQUIRE(lines.size() == 1);
  CHECK(lines[0] == "params { flat = true, name = \"leaf\", size = 300, vein_spacing = 20 }");
  CHECK(host.load("local P = params { size = 300 }\nprint(P)\ndisc { radius = 2 }\n", "q.lua", {}).print ==
        std::nullopt);
  // no imitation passes for P (it crashed the process): a table like it is a print section
  CHECK_THAT(load_error("print(setmetatable({}, {__name = 'cellform.params', values = 5}))\ndisc { radius = 2 }\n"),
             Contains("print{veins = true} needs veins"));
}
