// Tests of the script host's checks of settings that would have no effect in the run: another trigger's or
// split direction's fields, a shell's without a shell, an SVG's without one; and of run.json's shape records.
#include <catch2/catch.hpp>
#include <string>

#include "app/script_host.h"
#include "tests/app/script_test_util.h"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

using cellform::test::load;
using cellform::test::load_error;

namespace {
/// The one note that loading `script` (with the --set `sets`) gives; the test fails unless there is exactly one.
std::string one_note(const std::string& script, const cellform::app::Overrides& sets = {}) {
  const auto cfg = load(script, sets);
  REQUIRE(cfg.notes.size() == 1);
  return cfg.notes[0];
}
}  // namespace

TEST_CASE("a setting of the other division trigger is refused, not dropped unseen", "[script]") {
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { trigger = 'neighbours', age = 5 }\n"),
             Contains(":2: division.age has no effect with trigger = \"neighbours\""));
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { radius = 2 }\n"),  // the default trigger is age
             Contains(":2: division.radius has no effect with trigger = \"age\""));
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { trigger = 'none', min_neighbours = 4 }\n"),
             Contains("division.min_neighbours has no effect with trigger = \"none\""));
  CHECK(load("disc { radius = 2 }\ndivision { trigger = 'neighbours', radius = 2, min_neighbours = 5 }\n")
            .scene.cells.division.min_neighbours == 5);
  CHECK(load("disc { radius = 2 }\ndivision { trigger = 'age', age = 7 }\n").scene.cells.division.division_age == 7);
}

TEST_CASE("settings without effect in this run (a shell's without a shell, svg_size without an SVG) are noted",
          "[script]") {
  const auto cfg =
      load("disc { radius = 2 }\nvenation {}\nprint { shell = false, shell_thickness = 2, close_holes = 3 }\n");
  REQUIRE(cfg.notes.size() == 2);
  CHECK_THAT(cfg.notes[0], Contains(":3: print.shell_thickness has no effect: print.shell is false"));
  CHECK_THAT(cfg.notes[1], Contains(":3: print.close_holes has no effect"));
  // turned off from the command line: the note names the option, and the run still loads
  CHECK_THAT(one_note("disc { radius = 2 }\nvenation {}\nprint { shell = true, shell_thickness = 2 }\n",
                      {{"print.shell", "false"}}),
             Contains("print.shell_thickness has no effect"));
  CHECK(load("disc { radius = 2 }\nprint { shell = true, shell_thickness = 2 }\n").notes.empty());
  // print.size sets the scale only when scale = 0 (a print 7 times smaller than asked went unsaid)
  CHECK_THAT(one_note("disc { radius = 2 }\nvenation {}\nprint { scale = 2, size = 80 }\n"),
             Contains(":3: print.size has no effect: print.scale is set"));
  CHECK_THAT(one_note("disc { radius = 2 }\nvenation {}\nprint { size = 80 }\n", {{"print.scale", "2"}}),
             Contains("print.size has no effect"));
  CHECK(load("disc { radius = 2 }\nvenation {}\nprint { scale = 2 }\n").notes.empty());
  // adaptivity above the default thins the round veins too (by about half at 1)
  CHECK_THAT(one_note("disc { radius = 2 }\nvenation {}\nprint { adaptivity = 0.6 }\n"),
             Contains(":3: print.adaptivity = 0.6 simplifies curved surfaces too"));
  CHECK(load("disc { radius = 2 }\nvenation {}\nprint { adaptivity = 0.2 }\n").notes.empty());
  // a blade that does not grow keeps its initial length
  const auto fixed = load("leaf {}\ncolonisation { growth = 'none', final_length = 500, length_step = 5 }\n");
  REQUIRE(fixed.notes.size() == 2);
  CHECK_THAT(fixed.notes[0], Contains(":2: colonisation.final_length has no effect with growth = \"none\""));
  CHECK_THAT(fixed.notes[1], Contains("colonisation.length_step has no effect"));
  CHECK_FALSE(fixed.resolved["colonisation"].contains("final_length"));
  CHECK(load("leaf {}\ncolonisation { growth = 'marginal', final_length = 500 }\n").notes.empty());
  // run.json gives the values used: no final length for a blade that keeps its size, given or not, and b_v
  CHECK_FALSE(load("leaf {}\ncolonisation { growth = 'none' }\n").resolved["colonisation"].contains("final_length"));
  CHECK(load("leaf {}\ncolonisation { birth_distance = 3 }\n").resolved["colonisation"]["vein_birth_distance"] == 3);
  // veins.svg comes only from space colonisation in a leaf
  CHECK_THAT(one_note("disc { radius = 2 }\noutput { svg_size = 50 }\n"),
             Contains(":2: output.svg_size has no effect"));
  CHECK(load("volume { ball = { radius = 5 } }\ncolonisation {}\noutput { svg_size = 50 }\n").notes.size() == 1);
  CHECK(load("output { svg_size = 50 }\nleaf {}\ncolonisation {}\n").notes.empty());
  const auto paths = load("disc { radius = 2 }\noutput { svg_size = 50,\n  svg_paths = 'veins' }\n");
  REQUIRE(paths.notes.size() == 2);
  CHECK_THAT(paths.notes[1], Contains(":2: output.svg_paths has no effect"));
  CHECK(load("output { svg_paths = 'veins' }\nleaf {}\ncolonisation {}\n").output.svg_join_veins);
  CHECK_THAT(load_error("output { svg_paths = 'joined' }\nleaf {}\ncolonisation {}\n"),
             Contains(":1: output.svg_paths") && Contains("widths") && Contains("veins"));
  const auto blade = load("output { svg_size = 50 }\ncolonisation {}\n");  // a leaf, the default blade: said
  REQUIRE(blade.notes.size() == 1);
  CHECK_THAT(blade.notes[0], Contains(":2: no leaf{...}, volume{...} or surface{...}: the veins grow in leaf{}'s"));
  // a drawing under 1 mm is a blot of 0.1 mm strokes: refused, naming where it was given
  CHECK_THAT(load_error("leaf {}\ncolonisation {}\noutput { svg_size = 0.001 }\n"),
             Contains(":3: output.svg_size must be 0, or a number from 1 to 100000, got 0.001"));
  CHECK_THAT(load_error("leaf {}\ncolonisation {}\n", {{"output.svg_size", "0.5"}}),
             Contains("--set output.svg_size=0.5") && Contains("got 0.5"));
  CHECK(load("leaf {}\ncolonisation {}\noutput { svg_size = 1 }\n").output.svg_size == 1);
}

TEST_CASE("a setting of another trigger is refused in the script, and noted when a --set chose the trigger",
          "[script]") {
  const std::string src = "disc { radius = 2 }\ndivision { trigger = 'neighbours', radius = 2, min_neighbours = 5 }\n";
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { trigger = 'age', radius = 2 }\n"),
             Contains(":2: division.radius has no effect with trigger = \"age\""));
  // the script's line was blamed for the --set (a sweep over triggers could not run)
  const auto set = load(src, {{"division.trigger", "age"}});
  CHECK(set.scene.cells.division.trigger == cellform::cells::DivisionTrigger::age);
  REQUIRE(set.notes.size() == 2);
  CHECK_THAT(set.notes[0], StartsWith("--set division.trigger=age: division.radius has no effect with trigger"));
  CHECK_FALSE(set.resolved["division"].contains("radius"));  // run.json: not applied
  CHECK(set.resolved["division"]["trigger"] == "age");
  const auto rule = load(src, {{"division.age", "7"}});  // a field of the unused trigger by --set: noted
  REQUIRE(rule.notes.size() == 1);
  CHECK_THAT(rule.notes[0], StartsWith("--set division.age=7: division.age has no effect"));
}

TEST_CASE("a field of another split direction is refused, not dropped unseen", "[script]") {
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { direction = 'random', axis = {0, 1, 0} }\n"),
             Contains(":2: division.axis has no effect with direction = \"random\""));
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { direction = 'axis', centre = {5, 5, 5} }\n"),
             Contains(":2: division.centre has no effect with direction = \"axis\""));
  // a --set that chose the direction (it cannot remove the script's fields): noted, and the run goes on
  const auto set =
      load("disc { radius = 2 }\ndivision { direction = 'circumferential', axis = {0, 0, 1}, centre = {0, 0, 0} }\n",
           {{"division.direction", "radial"}});
  CHECK(set.scene.cells.division.direction == cellform::cells::SplitDirection::radial);
  REQUIRE(set.notes.size() == 1);
  CHECK_THAT(set.notes[0], Contains("--set division.direction=radial: division.axis has no effect with direction = "
                                    "\"radial\""));
  CHECK_THAT(
      load_error("disc { radius = 2 }\ndivision { direction = function(c) return {1, 0, 0} end, axis = {0, 1, 0} }\n"),
      Contains("division.axis has no effect with direction = a function"));
  const auto d =
      load("disc { radius = 2 }\ndivision { direction = 'circumferential', axis = {0, 0, 1}, centre = {1, 2, 0} }\n")
          .scene.cells.division;
  CHECK(d.centre == cellform::core::Vec3(1, 2, 0));
  CHECK(load("disc { radius = 2 }\ndivision { direction = 'radial', centre = {1, 2, 0} }\n")
            .scene.cells.division.centre == cellform::core::Vec3(1, 2, 0));
}

TEST_CASE("a division rule with trigger settings is refused, not half applied", "[script]") {
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { rule = function(cell) return true end, trigger = 'age' }\n"),
             Contains(":2: division.trigger has no effect with division.rule"));
  CHECK_THAT(load_error("disc { radius = 2 }\ndivision { age = 4, rule = function(cell) return true end }\n"),
             Contains(":2: division.age has no effect"));
  // the rule alone, and the split settings it does not replace, load
  const auto cfg = load(
      "disc { radius = 2 }\ndivision { rule = function(cell) return true end, probability = 0.5, "
      "max_cells = 100 }\n");
  CHECK(cfg.scene.cells.division.max_cells == 100);
}

TEST_CASE("run.json's shapes say how many cells each placed, in whole numbers", "[script]") {
  const auto cfg = load("disc { radius = 1 }\ncell { at = {5, 0, 0} }\npetiole { at = {0, 0, 0}, step = 100 }\n");
  const auto& shapes = cfg.resolved.at("shapes");
  REQUIRE(shapes.size() == 3);
  CHECK(shapes[0]["cells"] == 7);  // a unit disc on the unit lattice: the centre and its six neighbours
  CHECK(shapes[1]["cells"] == 1);
  CHECK_FALSE(shapes[2].contains("cells"));  // a petiole turns the nearest cell, or adds one, at its step
  CHECK(shapes[2]["step"].is_number_unsigned());
  CHECK(shapes[2]["step"] == 100);
  // every value each shape was placed with, given or default
  const auto all = load(
      "rectangle { width = 2, height = 2, centre = {10, 0, 0} }\nsphere { radius = 2, centre = {0, 9, 0} }\n"
      "line { from = {0, 0, 5}, to = {3, 0, 5} }\ndisc { radius = 1, normal = {0, 1, 0} }\ncell { at = {1, 2, 3} }\n");
  const auto& r = all.resolved.at("shapes");
  REQUIRE(r.size() == 5);
  CHECK(r[0]["centre"] == nlohmann::json::array({10.0, 0.0, 0.0}));
  CHECK(r[0]["normal"] == nlohmann::json::array({0.0, 0.0, 1.0}));
  CHECK(r[1]["centre"] == nlohmann::json::array({0.0, 9.0, 0.0}));
  CHECK(r[2]["from"] == nlohmann::json::array({0.0, 0.0, 5.0}));
  CHECK(r[2]["to"] == nlohmann::json::array({3.0, 0.0, 5.0}));
  CHECK(r[3]["normal"] == nlohmann::json::array({0.0, 1.0, 0.0}));
  CHECK(r[4]["fixed"] == false);
}

TEST_CASE("run.json lists the first 1,000 shape calls and counts the rest", "[script]") {
  // a point cloud placed cell by cell made a run.json of 40 MB (250,000 calls), and 100,000 ball{} calls one
  // of 14 MB (review of app/)
  const auto cfg = cellform::test::load(
      "for i = 1, 1500 do cell { at = {i, 0, 0} } end\ndisc { radius = 2 }\n"
      "for i = 1, 1200 do ball { centre = {i, 50, 0}, radius = 0.1 } end\n");
  REQUIRE(cfg.resolved["constraints"].size() == 1000);
  CHECK(cfg.resolved["constraints"][999]["centre"][0] == 1000.0);
  CHECK(cfg.resolved["constraints_not_listed"] == 200);
  CHECK(cfg.scene.obstacles.spheres.size() == 1200);  // all of them stand
  CHECK(cfg.initial_cells.size() > 1500);
  REQUIRE(cfg.resolved["shapes"].size() == 1000);
  CHECK(cfg.resolved["shapes"][999]["at"][0] == 1000.0);
  CHECK(cfg.resolved["shapes_not_listed"]["calls"] == 501);  // 500 cells and the disc
  CHECK(cfg.resolved["shapes_not_listed"]["cells"].get<std::size_t>() == cfg.initial_cells.size() - 1000);
}
