// Tests of app/script_values.cpp: values read from a script's tables, checked one by one and together.
#include <catch2/catch.hpp>

#include "app/script_host.h"
#include "tests/app/script_test_util.h"

using Catch::Matchers::Contains;
using cellform::test::load;
using cellform::test::load_error;

TEST_CASE("positions beyond 1e9 model units are refused (their squares would overflow)", "[script]") {
  CHECK_THAT(load_error("disc { radius = 3 }\npetiole { at = {1e300, 0, 0} }\nvenation {}\n"),
             Contains(":2: petiole.at") && Contains("1e+09"));
  CHECK_THAT(load_error("disc { radius = 3 }\nsurface { cells = true, seeds = {{1e12, 0, 0}} }\ncolonisation {}\n"),
             Contains("surface.seeds") && Contains("beyond 1e+09"));
  // a shape too large to place, made so on the command line: the option is named beside the script's line
  CHECK_THAT(load_error("disc { radius = 3 }\n", {{"disc.radius", "1e9"}}),
             Contains("test/leaf.lua:1: disc: ") && Contains("(given by --set disc.radius=1e9)"));
  CHECK_THAT(load_error("disc { radius = 1e9 }\n"), !Contains("given by"));
}

TEST_CASE("directions that mean nothing are refused, not replaced", "[script]") {
  CHECK_THAT(load_error("disc { radius = 2, normal = {0, 0, 0} }\n"), Contains(":1: disc: normal must be a non-zero"));
  CHECK_THAT(load_error("rectangle { width = 2, height = 2, normal = {0, 0, 0} }\n"), Contains("rectangle: normal"));
  // a tiny vector is a direction all the same (its square underflowed: "got {0, 0, 0}")
  CHECK(load("disc { radius = 2, normal = {0, 0, 1e-300} }\n").initial_cells.size() ==
        load("disc { radius = 2 }\n").initial_cells.size());
  CHECK_THAT(load_error("disc { radius = 2 }\nhalf_space { normal = {0, 0, 0} }\n"),
             Contains(":2: half_space.normal must be a non-zero vector"));
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { direction = 'auxin' }\n"),
             Contains(":2: division.direction = \"auxin\"") && Contains("venation{...}"));
}

TEST_CASE("a value that fails a check of several parameters is reported where it was given", "[script]") {
  // the time step's stability limit depends on the force weights: checked after the section is read
  CHECK_THAT(load_error("run { steps = 3 }\ncells { time_step = 5 }\ndisc { radius = 3 }\n"),
             Contains("test/leaf.lua:2:") && Contains("cells.time_step 5 is above the stable limit"));
  CHECK_THAT(load_error("cells { }\ndisc { radius = 3 }\n", {{"cells.time_step", "4"}}),
             Contains("--set cells.time_step=4: cells.time_step 4"));
  // a --set of another weight that lowered the limit is named too
  CHECK_THAT(load_error("cells { rest_length = 1 }\ndisc { radius = 3 }\n",
                        {{"cells.spring", "100000"}, {"cells.max_speed", "5"}}),
             Contains("test/leaf.lua:1: cells.time_step") && Contains("(with --set cells.spring=100000)"));
  CHECK_THAT(load_error("cells { }\ndisc { radius = 3 }\n", {{"cells.time_step", "3"}, {"cells.spring", "3"}}),
             Contains("--set cells.time_step=3: ") && Contains("(with --set cells.spring=3)"));
  // the straightening factor is named by the script's name, and the message names the term that binds
  const std::string veined = "cells { }\ndisc { radius = 3 }\npetiole { at = {0, -3, 0} }\nvenation { }\n";
  CHECK_THAT(load_error(veined, {{"cells.vein_cohesion", "1e6"}}),
             Contains("test/leaf.lua:1: cells.time_step") && Contains("(with --set cells.vein_cohesion=1e6)") &&
                 Contains("the largest term is cells.vein.cohesion 0.05 times cells.vein_cohesion 1e+06"));
  // without canalisation no cell joins a vein tree: the straightening terms bound nothing
  CHECK_NOTHROW(load("cells { }\ndisc { radius = 3 }\n", {{"cells.vein_cohesion", "1e6"}}));
  CHECK_NOTHROW(load("cells { cohesion = 40, time_step = 0.1 }\ndisc { radius = 3 }\n"));  // was refused
  CHECK_THAT(load_error("cells { cohesion = 4000, time_step = 0.1 }\ndisc { radius = 3 }\n"),
             Contains("the largest term is cells.cohesion 4000)"));  // the plain term still binds
  CHECK_THAT(load_error("cells { spring = 1000 }\ndisc { radius = 3 }\n"),
             Contains("the largest term is cells.spring 1000)"));
  // a --set value is named as the --set, not as the script line that set another value
  const std::string print =
      "disc { radius = 3 }\npetiole { at = {0, 0, 0} }\nvenation { }\nprint { formats = \"stl\" }\n";
  CHECK_THAT(load_error(print, {{"print.formats", "stl,stp"}}),
             Contains("--set print.formats=stl,stp: print.formats: unknown format 'stp'"));
  CHECK_THAT(load_error(print, {{"print.voxel_size", "1"}}), Contains("--set print.voxel_size=1: print.voxel_size"));
  CHECK_THAT(load_error("disc { radius = 3 }\npetiole { at = {0, 0, 0} }\nvenation { }\nprint { voxel_size = 1 }\n"),
             Contains("test/leaf.lua:4: print.voxel_size"));
  // surface{cells = true} without a start for the veins: said with the section's line, before any growth
  CHECK_THAT(load_error("disc { radius = 3 }\nsurface { cells = true }\ncolonisation { type = \"open\" }\n"),
             Contains("test/leaf.lua:2: surface{cells = true} needs seeds"));
}

TEST_CASE("a knob's text default is checked whole for UTF-8, past a NUL", "[script]") {
  CHECK_THAT(load_error(std::string("local P = params { name = 'a\\0\xff' }\ndisc { radius = 2 }\n")),
             Contains("test/leaf.lua:1: params{...}: the knob name's default is not UTF-8 text"));
  CHECK_NOTHROW(load(std::string("local P = params { name = 'a\\0b' }\ndisc { radius = 2 }\n")));
}

TEST_CASE("numbers are taken exactly or refused: no NaN knob, no rounded seed", "[script]") {
  using cellform::test::load;
  // a knob of NaN or infinity was taken, and run.json recorded it as null
  for (const char* x : {"0/0", "math.huge", "-math.huge"})
    CHECK_THAT(load_error(std::string("local P = params { x = ") + x + " }\ndisc { radius = 2 }\n"),
               Contains("test/leaf.lua:1: params{...}: the knob x is") && Contains("a knob is a finite number"));
  // a Lua integer beyond 2^53 was rounded to a double (seed 9007199254740993 ran as ...992)
  CHECK_THAT(load_error("run { seed = 9007199254740993 }\ndisc { radius = 2 }\n"),
             Contains("run.seed must be a whole number of at most 2^53") && Contains("9007199254740993"));
  CHECK(load("run { seed = 9007199254740992 }\ndisc { radius = 2 }\n").seed == 9007199254740992ull);
  CHECK_THAT(load_error("run { steps = 1 }\ndisc { radius = 2 }\n", {{"run.seed", "9007199254740993"}}),
             Contains("--set run.seed=9007199254740993: run.seed must be a whole number of at most 2^53"));
  CHECK_THAT(load_error("run { seed = math.maxinteger }\ndisc { radius = 2 }\n"), Contains("run.seed must be"));
  // a float just past the limit is quoted in full (9.00719925474099e+15 looked like the limit itself)
  CHECK_THAT(load_error("run { seed = 2^53 + 2 }\ndisc { radius = 2 }\n"),
             Contains("from 0 to 9007199254740992, got 9007199254740994"));
  // a refusal quotes the value as given: 0/0 was "-nan", and 1.0000001 read as the allowed 1
  CHECK_THAT(load_error("disc { radius = 0/0 }\n"), Contains("disc.radius must be a number > 0, got NaN"));
  CHECK_THAT(load_error("disc { radius = 2 }\ncells { drag = {1, 1, 1.0000001} }\n"),
             Contains("cells.drag must be {x, y, z} with each from 0 to 1, got {1, 1, 1.0000001}"));
  CHECK_THAT(load_error("disc { radius = 2 }\ncells { drag = {1, 0/0, 1} }\n"), Contains("got {1, NaN, 1}"));
  // an entry beside the three is refused, not dropped unseen
  CHECK_THAT(
      load_error("disc { radius = 2 }\ncells { drag = {0.5, 0.5, 0.5, [10] = 1} }\n"),
      Contains("cells.drag must be {x, y, z}") && Contains("got a table with an entry beside x, y and z (key [10])"));
  CHECK_THAT(load_error("disc { radius = 2 }\ncells { drag = table.pack(0.5, 0.5, 0.5) }\n"), Contains("(key 'n')"));
  CHECK(load("disc { radius = 2 }\ncells { drag = {0.5, 0.5, 0.5} }\n").scene.cells.drag.x() == 0.5);
  CHECK_THAT(load_error("disc { radius = 2 }\ncells { drag = {0.5, 0.5, 0.5, [true] = 1} }\n"),
             Contains("(key [true])"));
  // a key is named by its raw value: its __tostring ran script code inside the host, and an error it raised
  // jumped past the host's restores, so the memory limit and the watchdog were off for the rest of the script,
  // and in a coroutine the host kept the dead coroutine's state and crashed (review of app/)
  const std::string raising_key =
      "local k = setmetatable({}, {__tostring = function() error('boom') end})\n"
      "local ok, e = pcall(cells, {unary = {0, 0, 0, [k] = 1}})\n"
      "assert(not ok and e:find('key %[a table%]'), e)\n";
  cellform::app::ScriptLimits small;
  small.memory_bytes = 32u << 20;
  CHECK_THAT(
      load_error(raising_key + "local t = {}\nfor i = 1, 2000000 do t[i] = string.rep('x', 64) .. i end\n", {}, small),
      Contains("leaf.lua:5:") && Contains("memory limit of 32 MiB"));
  const auto in_coroutine = load("local co = coroutine.wrap(function()\n" + raising_key +
                                 "end)\nco()\nco = nil\n"
                                 "for i = 1, 300 do local t = {} for j = 1, 20000 do t[j] = {j} end end\n"
                                 "disc { radius = 2 }\n");
  CHECK(in_coroutine.initial_cells.size() == 19);
  // --set of a whole knob is taken exactly, beyond 2^53 too
  const auto cfg = load("local P = params { n = 3 }\ndisc { radius = 2 }\n", {{"n", "9007199254740993"}});
  CHECK(cfg.resolved["params"]["n"].get<std::int64_t>() == 9007199254740993LL);
}

TEST_CASE("a boolean is true or false alike in a script, a knob and --set", "[script]") {
  // --set print.shell=1 was taken as true, while print { shell = 1 } and --set of a boolean knob were refused
  for (const char* text : {"1", "0", "yes", "True"}) {
    CAPTURE(text);
    CHECK_THAT(load_error("disc { radius = 2 }\nprint { }\n", {{"print.shell", text}}),
               Contains("print.shell must be true or false") && Contains(std::string("got \"") + text + "\""));
    CHECK_THAT(load_error("local P = params { flag = true }\ndisc { radius = 2 }\n", {{"flag", text}}),
               Contains("expected true or false"));
  }
  CHECK_THAT(load_error("disc { radius = 2 }\nprint { shell = 1 }\n"), Contains("print.shell must be true or false"));
  CHECK(load("disc { radius = 2 }\nprint { }\n", {{"print.shell", "true"}}).resolved["print"]["shell"] == true);
  CHECK(load("disc { radius = 2 }\npetiole { at = {0, 0, 0} }\nvenation { }\nprint { shell = true }\n",
             {{"print.shell", "false"}})
            .resolved["print"]["shell"] == false);
}

TEST_CASE("the speed limit scales with the rest length unless given", "[script]") {
  // a form modelled at rest length 1e7 moves about 1e6 units per time unit: the fixed limit of 1e6 stopped
  // it as diverged (with advice about the time step that did not apply)
  for (const double rest : {1.0, 25.0, 1e7}) {
    const auto cfg = load("cells { rest_length = " + std::to_string(rest) +
                          " }\ndisc { radius = " + std::to_string(3 * rest) + " }\n");
    CHECK(cfg.scene.cells.max_speed == 1e6 * cfg.scene.cells.rest_length);
    CHECK_FALSE(cfg.resolved["cells"].contains("max_speed"));  // re-derived from the rest length on a resume
  }
  const auto given = load("cells { rest_length = 1e7, max_speed = 5 }\ndisc { radius = 3e7 }\n");
  CHECK(given.scene.cells.max_speed == 5);
  CHECK(load("disc { radius = 3 }\n", {{"cells.max_speed", "7"}}).scene.cells.max_speed == 7);
}

TEST_CASE("a knob's name is one --set can give, and no section's parameter's", "[script]") {
  // audit: params { ["cells.spring"] = 2 } was set by --set cells.spring=5 together with cells{spring}
  CHECK_THAT(load_error("local P = params { [\"cells.spring\"] = 2 }\ndisc { radius = 2 }\n"),
             Contains("test/leaf.lua:1: params{...}: the knob name 'cells.spring' is a section's parameter too"));
  CHECK_THAT(load_error("local P = params { [\"cells.vein.cohesion\"] = 2 }\ndisc { radius = 2 }\n"),
             Contains("the knob name 'cells.vein.cohesion' is a section's parameter too"));  // (review)
  for (const char* name : {"", "bad name", "a=b"}) {
    INFO(name);
    CHECK_THAT(
        load_error(std::string("local P = params { [\"") + name + "\"] = 2 }\ndisc { radius = 2 }\n"),
        Contains("test/leaf.lua:1: params{...}: the knob name '") && Contains("' cannot be given to --set NAME=VALUE"));
  }
  // a dotted name of no parameter stays (older scripts may have them)
  CHECK_NOTHROW(load("local P = params { _size2 = 2, Size = 3, ['my.size'] = 4 }\ndisc { radius = 2 }\n"));
}

TEST_CASE("a division.direction that names no choice is refused, with the nearest choice", "[script]") {
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { direction = 'tangnet' }\n"),
             Contains(":2: division.direction must be one of \"random\"") && Contains("did you mean \"tangent\"?"));
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision {}\n", {{"division.direction", "radiall"}}),
             Contains("--set division.direction=radiall: division.direction must be one of"));
}

TEST_CASE("a --set vector needs three numbers", "[script]") {
  CHECK_THAT(load_error("disc { radius = 2 }\ncells {}\n", {{"cells.unary", "0,-1"}}),
             Contains("--set cells.unary=0,-1: cells.unary must be {x, y, z}") && Contains("--set cells.unary=X,Y,Z"));
}

TEST_CASE("print.formats naming no format is refused", "[script]") {
  CHECK_THAT(load_error("disc { radius = 2 }\nvenation {}\nprint { formats = ' , ' }\n"),
             Contains(":3: print.formats must name at least one of stl, obj, ply, scad, vdb"));
  CHECK_THAT(load_error("disc { radius = 2 }\nvenation {}\nprint {}\n", {{"print.formats", ","}}),
             Contains("--set print.formats=,: print.formats must name at least one"));
}

TEST_CASE("a zero division.axis is refused at its line", "[script]") {
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { direction = 'axis', axis = {0, 0, 0} }\n"),
             Contains("test/leaf.lua:2: division.axis must be a non-zero vector for direction = \"axis\""));
}
