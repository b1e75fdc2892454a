// Tests of the tables a script reads: the cell table of rule functions (a misspelt field is an error naming
// the closest one) and the knobs of params{} (read-only, printable).
#include <catch2/catch.hpp>
#include <string>
#include <utility>
#include <vector>

#include "app/script_host.h"
#include "cells/cells.h"
#include "core/errors.h"
#include "tests/app/script_test_util.h"

using Catch::Matchers::Contains;
using cellform::app::ScriptHost;

namespace {
/// Whether the division rule `body` (a Lua expression of `cell`) holds for the first of two cells.
bool divides(const std::string& body, const cellform::cells::Cells& c, const std::string& more = "") {
  ScriptHost host;
  host.load("disc { radius = 2 }\ndivision { rule = function(cell)\n  return " + body + "\nend }\n" + more, "rule.lua",
            {});
  return host.rules().divides(c, 0);
}
const std::string kVeins = "petiole { at = {0, 0, 0} }\nvenation {}\n";
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
  // an error that names no line (level 0) is named at the rule's own line, where the function is defined
  CHECK_THROWS_WITH(divides("error('lvl0', 0)", c), Contains("rule.lua:2: lvl0 (in division.rule at step"));
  // a field the rule cleared itself is no misspelling ("did you mean 'x'?" of cell.x, audit)
  CHECK_THROWS_WITH(divides("(function() cell.x = nil return cell.x == 1 end)()", c),
                    Contains("rule.lua:3: cell.x is nil: the rule set it to nil before reading it"));
  // every documented field reads, and venation's attributes are nil before canalisation made them
  CHECK(divides("cell.type == 'general' and cell.age == 3 and cell.x == 1 and cell.step >= 0 and cell.fixed == false",
                c));
  CHECK(
      divides("cell.id + cell.index + cell.generation + cell.y + cell.z + cell.vx + cell.vy + cell.vz + "
              "cell.neighbours >= 0",
              c));
  CHECK(divides("cell.flow == nil and cell.vein_radius == nil and cell.vein_order == nil and cell.flow_dx == nil", c,
                kVeins));
  // before that first pass, arithmetic on one says why it is nil (a walkthrough got Lua's bare message)
  CHECK_THROWS_WITH(divides("cell.flow / 100 > 1", c, kVeins),
                    Contains("(field 'flow')") &&
                        Contains("; if that is cell.flow, it is nil until the first canalisation pass (at step "
                                 "venation.every): write (cell.flow or 0)"));
  // without venation{} they would be nil for good: an error (a walkthrough's rule never saw a value)
  CHECK_THROWS_WITH(divides("(cell.flow or 0) < 5", c),
                    Contains("rule.lua:3: cell.flow is an attribute canalisation computes, and this script has no "
                             "venation{...}"));
  // os and io are said to be left out, as at the script's top level
  CHECK_THROWS_WITH(divides("os.time() > 0", c), Contains("'os' is left out of cellform scripts"));
  cellform::cells::attribute(c, "flow") = {7, 8};
  CHECK(divides("cell.flow == 7", c));
  cellform::cells::attribute(c, "vein_order") = {2, 0};  // a whole number, as in the files: "2", not "2.0"
  CHECK(divides("math.type(cell.vein_order) == 'integer' and tostring(cell.vein_order) == '2'", c));
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
  // a value set back is no change (a NaN knob is refused: run.json kept null), through nil too
  CHECK_NOTHROW(load("local P = params { n = 3 }\nP.n = 4\nP.n = 3\n"));
  CHECK_NOTHROW(load("local P = params { n = 3 }\nP.n = nil\nP.n = 3\n"));
  // each kind compared whole (without copying a long text each step): its last byte, an integer made a float,
  // -0.0 for 0.0, a boolean; an equal text made anew is no change
  CHECK_THAT(load_error("local P = params { s = string.rep('x', 100000) }\nP.s = string.rep('x', 99999) .. 'y'\n"),
             Contains("changed the knob s"));
  CHECK_THAT(load_error("local P = params { n = 3 }\nP.n = 3.0\n"), Contains("knob n from 3 to 3.0"));
  CHECK_THAT(load_error("local P = params { x = 0.0 }\nP.x = -0.0\n"), Contains("knob x from 0.0 to -0.0"));
  CHECK_THAT(load_error("local P = params { b = true }\nP.b = false\n"), Contains("knob b from true to false"));
  CHECK_NOTHROW(
      load("local P = params { s = string.rep('x', 100000), x = 0.5, b = true }\n"
           "P.s = string.rep('x', 100000)\nP.x = 0.25 * 2\n"));
  // a new field is refused at once, where it is written (a misspelt assignment passed unseen, and run.json
  // and print(P) did not show it), by rawset too
  CHECK_THAT(load_error("local P = params { vein_spacing = 10 }\n\nP.vein_spacin = 20\n"),
             Contains("test/leaf.lua:3: params: the knobs are read-only, and a new one 'vein_spacin' cannot be added"));
  CHECK_THAT(load_error("local P = params { n = 3 }\nrawset(P, 'm', 9)\n"),
             Contains(":2: rawset(params, m, ...): the knobs are read-only"));
  CHECK_THAT(load_error("local P = params { bad = 0/0 }\n"), Contains("a knob is a finite number"));
  // a rule function that changes a knob is stopped after its step, naming the knob and the step (a resume
  // would start again from the knob as made)
  {
    cellform::cells::Cells c;
    cellform::cells::add_cell(c, {1, 0, 0});
    ScriptHost host;
    host.load(
        "local P = params { n = 3, keep = 1 }\ndisc { radius = 2 }\n"
        "division { rule = function(cell) P.keep = 1 if cell.age > 5 then P.n = P.n + 1 end return false end }\n",
        "knob.lua", {});
    auto rules = host.rules();
    c.age = {2};
    rules.divides(c, 0);
    CHECK_NOTHROW(host.check_knobs(6));  // setting a knob to its own value changes nothing
    c.age = {7};
    rules.divides(c, 0);
    CHECK_THROWS_WITH(host.check_knobs(7), Contains("knob.lua:1: params: a rule function changed the knob n from 3 "
                                                    "to 4 by the end of step 7") &&
                                               Contains("the knobs are read-only"));
  }
  {  // nor can a rule function keep state in a new knob
    cellform::cells::Cells c;
    cellform::cells::add_cell(c, {1, 0, 0});
    ScriptHost host;
    host.load(
        "local P = params { n = 3 }\ndisc { radius = 2 }\n"
        "division { rule = function(cell) P.q = cell.id return false end }\n",
        "knob.lua", {});
    auto rules = host.rules();
    CHECK_THROWS_WITH(rules.divides(c, 0), Contains("knob.lua:3:") && Contains("a new one 'q' cannot be added"));
  }
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
      "local P = params { size = 300, vein_spacing = 20, name = 'leaf', flat = true }\nprint(P)\n"
      "disc { radius = 2 }\n",
      "p.lua", {});
  REQUIRE(lines.size() == 1);
  CHECK(lines[0] == "params { flat = true, name = \"leaf\", size = 300, vein_spacing = 20 }");
  CHECK(host.load("local P = params { size = 300 }\nprint(P)\ndisc { radius = 2 }\n", "q.lua", {}).print ==
        std::nullopt);
  // tostring(P) and print with other values say the knobs too (it was "table: 0x...")
  lines.clear();
  ScriptHost other;
  other.set_print([&](const std::string& line) { lines.push_back(line); });
  other.load(
      "local P = params { n = 3 }\nprint('knobs:', P)\nassert(tostring(P) == 'params { n = 3 }')\n"
      "disc { radius = 2 }\n",
      "r.lua", {});
  REQUIRE(lines.size() == 1);
  CHECK(lines[0] == "knobs:\tparams { n = 3 }");
  // a knob is what --set can give and run.json records: a table or a function is refused at params{}
  CHECK_THAT(load_error("local P = params { n = 3, centre = {1, 2, 3} }\ndisc { radius = 2 }\n"),
             Contains("test/leaf.lua:1: params{...}: the knob centre is a table; a knob is a number, a boolean or a "
                      "string") &&
                 Contains("local variable"));
  CHECK_THAT(load_error("local P = params { f = function() end }\n"), Contains("the knob f is a function"));
  // no imitation passes for P (it crashed the process): a table like it is a print section
  CHECK_THAT(load_error("print(setmetatable({}, {__name = 'cellform.params', values = 5}))\ndisc { radius = 2 }\n"),
             Contains("print{veins = true} needs veins"));
}

TEST_CASE("functions the sandbox leaves out are said to be left out, not taken for misspelt ones", "[script]") {
  using cellform::test::load_error;
  for (const char* line : {"dofile('x.lua')", "require('x')", "local f = io.open('x')", "os.exit(1)", "load('x')()"}) {
    INFO(line);
    const std::string e = load_error(std::string("disc { radius = 2 }\n") + line + "\n");
    CHECK_THAT(
        e, Contains("test/leaf.lua:2:") && Contains("is left out of cellform scripts") && !Contains("did you mean"));
  }
  // nesting beyond Lua's parser limit names the script (it said "C stack overflow" alone)
  CHECK_THAT(load_error("local t = " + std::string(300, '{') + std::string(300, '}') + "\n"),
             Contains("test/leaf.lua: C stack overflow: the script nests deeper than Lua allows"));
  // a misspelt function of cellform's is still named
  CHECK_THAT(load_error("dsic { radius = 2 }\n"), Contains("did you mean 'disc'?") && !Contains("left out"));
}

TEST_CASE("rule results out of range are stopped at the rule's line, naming the cell", "[script]") {
  cellform::cells::Cells c;
  cellform::cells::add_cell(c, {1, 0, 0});
  cellform::cells::add_cell(c, {-1, 0, 0});
  c.type[1] = cellform::cells::CellType::petiole;
  // a source beyond a constant's range (1e30) summed past the files' 32-bit flows with no script line
  {
    ScriptHost host;
    host.load(
        "disc { radius = 2 }\npetiole { at = {0, 0, 0} }\nvenation { source = function(cell)\n  return 1e31 end }\n",
        "s.lua", {});
    host.set_step(4);
    CHECK_THROWS_WITH(host.source_rule()(c, 0),
                      Contains("s.lua:3: venation.source must return a number from 0 to 1e30") &&
                          Contains("got 1e+31") && Contains("at step 4 for cell 0"));
  }
  // a source that is no number: said with its type and the cell's id (not its index)
  for (const char* value : {"nil", "'1'", "{}"}) {
    ScriptHost host;
    host.load("disc { radius = 2 }\npetiole { at = {0, 0, 0} }\nvenation { source = function(cell)\n  return " +
                  std::string(value) + " end }\n",
              "s.lua", {});
    host.set_step(2);
    cellform::cells::Cells d = c;
    d.id[0] = 41;
    const std::string type = value == std::string("nil") ? "nil" : value[0] == '\'' ? "string" : "table";
    INFO(value);
    CHECK_THROWS_WITH(host.source_rule()(d, 0), Contains("s.lua:3: venation.source must return a number") &&
                                                    Contains("got " + type) && Contains("at step 2 for cell 41"));
  }
  // a direction rule following the flow returns 0, 0, 0 where there is none (a petiole): the error says why
  ScriptHost host;
  host.load(
      "disc { radius = 2 }\ndivision { direction = function(cell)\n  return {cell.flow_dx, cell.flow_dy, cell.flow_dz} "
      "end }\n",
      "d.lua", {});
  for (const char* a : {"flow_dx", "flow_dy", "flow_dz"}) cellform::cells::attribute(c, a) = {1, 0};
  CHECK(host.rules().split_direction(c, 0).x() == 1);
  // what a bad direction was is said (a walkthrough's was always the same message)
  for (const auto& [ret, got] :
       std::vector<std::pair<std::string, std::string>>{{"{1, 0}", "{1, 0}"},
                                                        {"nil", "nil"},
                                                        {"'x'", "string"},
                                                        {"{x = 1, y = 0, z = 0}", "a table without items"},
                                                        {"{0/0, 0, 0}", "{NaN, 0, 0}"},
                                                        {"1, 0", "1, 0, nil"},
                                                        {"{1, '0', 0}", "{1, string, 0}"}}) {
    ScriptHost bad;
    bad.load("disc { radius = 2 }\ndivision { direction = function(cell)\n  return " + ret + " end }\n", "b.lua", {});
    INFO(ret);
    CHECK_THROWS_WITH(
        bad.rules().split_direction(c, 0),
        Contains("b.lua:2: division.direction must return {x, y, z} (or x, y, z) of finite numbers, got " + got));
  }
  CHECK_THROWS_WITH(host.rules().split_direction(c, 1),
                    Contains("d.lua:2: division.direction returned a zero vector") &&
                        Contains("flow_dx, flow_dy, flow_dz are all 0: a petiole, or a cell no flow reaches"));
}
