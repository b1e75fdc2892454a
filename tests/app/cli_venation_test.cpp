// Tests of what a cell run with canalisation says about its petioles: cells no petiole drains, and
// petioles (or canalisation's first pass) due after the run's last step.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {
const char* const kTwoDiscs =
    "run { steps = 30, seed = 1 }\n"
    "division { trigger = 'neighbours', radius = 1.25, min_neighbours = 6, max_cells = 200 }\n"
    "venation { threshold = 10 }\n"
    "disc { radius = 4 }\n";
}  // namespace

TEST_CASE("cells that drain to no petiole are warned about, with run.json's count", "[cli][venation]") {
  TempDir t("cli-unconnected");
  // a second disc far from the first: no link joins them, and only the first has a petiole
  const auto apart = t.write(
      "apart.lua", std::string(kTwoDiscs) + "disc { radius = 4, centre = {30, 0, 0} }\npetiole { at = {0, -4, 0} }\n");
  auto r = cli({"run", apart.string(), "--out", (t.path / "a").string(), "--quiet"});
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(slurp(t.path / "a" / "run.json"));
  const std::size_t lost = j["veins"]["unconnected_cells"];
  const std::size_t cells = j["cells"]["final"];
  CHECK(lost > 0);
  CHECK(lost < cells);
  CHECK_THAT(r.err, Contains("warning: " + std::to_string(lost) + " of " + std::to_string(cells) +
                             " cells have no path through the links to a petiole"));
  // resuming the finished run runs no step: run.json keeps the last canalisation's figures (it said null)
  r = cli({"resume", (t.path / "a").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(t.path / "a" / "run.json"))["veins"] == j["veins"]);
  // a petiole on each part: every cell drains, and nothing is said
  const auto both = t.write("both.lua", std::string(kTwoDiscs) +
                                            "disc { radius = 4, centre = {30, 0, 0} }\npetiole { at = {0, -4, 0} }\n"
                                            "petiole { at = {30, -4, 0} }\n");
  r = cli({"run", both.string(), "--out", (t.path / "b").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(t.path / "b" / "run.json"))["veins"]["unconnected_cells"] == 0);
  CHECK_THAT(r.err, !Contains("warning") && !Contains("no path"));  // (the note of max_cells, reached, is said)
}

TEST_CASE("a petiole due after the run's last step is noted before the steps", "[cli][venation]") {
  TempDir t("cli-late-petiole");
  const auto late = t.write(
      "late.lua", std::string(kTwoDiscs) + "petiole { at = {0, -4, 0} }\npetiole { at = {0, 4, 0}, step = 500 }\n");
  auto r = cli({"run", late.string(), "--out", (t.path / "a").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("late.lua:6: the petiole due at step 500 comes after the run's last step (30)") &&
                        Contains("this run does not place it"));  // (a resume with --steps does)
  // reached: no note
  r = cli({"run", late.string(), "--out", (t.path / "b").string(), "--quiet", "--steps", "500", "--set",
           "division.max_cells=70"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("comes after the run's last step"));
}

TEST_CASE("canalisation whose first pass comes after the run's last step is noted before the steps",
          "[cli][venation]") {
  TempDir t("cli-late-canalisation");
  const auto late = t.write("late.lua", std::string(kTwoDiscs) + "petiole { at = {0, -4, 0} }\n");
  // audit: venation.every above the steps said nothing, and veins.ply was empty
  auto r = cli({"run", late.string(), "--out", (t.path / "a").string(), "--quiet", "--set", "venation.every=50"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("late.lua:3: canalisation first runs at step venation.every = 50, after the run's last "
                             "step (30), so no vein grows in this run"));
  CHECK(nlohmann::json::parse(slurp(t.path / "a" / "run.json"))["veins"]["vein_cells"] == 0);
  // reached (step 30 is a pass of every = 30): no note, and veins
  r = cli({"run", late.string(), "--out", (t.path / "b").string(), "--quiet", "--set", "venation.every=30"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("canalisation first runs"));
  CHECK(nlohmann::json::parse(slurp(t.path / "b" / "run.json"))["veins"]["vein_cells"] > 0);
}

TEST_CASE("a print with no vein grown yet says what to change, not to print again", "[cli][venation]") {
  TempDir t("cli-nothing-to-print");
  const auto early =
      t.write("early.lua", std::string(kTwoDiscs) + "petiole { at = {0, -4, 0} }\nprint { veins = true, size = 40 }\n");
  // (the script's whole run: one cut short by --steps skips the print instead)
  const auto r = cli({"run", early.string(), "--out", (t.path / "a").string(), "--quiet", "--set", "run.steps=1",
                      "--set", "venation.threshold=1000"});
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("nothing to print yet (no vein has grown; run longer"));
  // other print.* values cannot help: the hint that they can is not given
  CHECK_THAT(r.err, !Contains("to print again with other print.* values"));
  CHECK(fs::exists(t.path / "a" / "checkpoint.cfck"));
}

TEST_CASE("run.json's vein figures are the last canalisation's, through resumes that reach none", "[cli][venation]") {
  TempDir t("cli-every");
  const auto script =
      t.write("every.lua",
              "division { trigger = 'neighbours', radius = 1.25, min_neighbours = 6, max_cells = 200 }\n"
              "venation { threshold = 10, every = 10 }\n"
              "disc { radius = 4 }\npetiole { at = {0, -4, 0} }\n");
  const fs::path out = t.path / "o", fresh = t.path / "f";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "20"}).code == 0);
  const auto at20 = nlohmann::json::parse(slurp(out / "run.json"))["veins"];
  REQUIRE(at20["vein_cells"].get<int>() > 0);  // a vein grew by step 20, so unchanged figures say something
  // steps 21 to 25 run no canalisation: the figures stay those of step 20, as in a run of 25 steps
  REQUIRE(cli({"resume", out.string(), "--steps", "25", "--quiet"}).code == 0);
  REQUIRE(cli({"run", script.string(), "--out", fresh.string(), "--quiet", "--steps", "25"}).code == 0);
  const auto expected = nlohmann::json::parse(slurp(fresh / "run.json"))["veins"];
  CHECK(expected == at20);
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["veins"] == expected);
  REQUIRE(cli({"resume", out.string(), "--quiet"}).code == 0);  // and through one that runs no step
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["veins"] == expected);
}

TEST_CASE("a petiole no vein has reached yet is not printed as a ball apart from the form", "[cli][venation]") {
  // the second petiole appears at the last step: no cell has drained to it long enough to become a vein
  TempDir t("cli-lone-petiole");
  const auto script = t.write("lone.lua", std::string(kTwoDiscs) +
                                              "petiole { at = {0, -4, 0} }\npetiole { at = {0, 4, 0}, step = 30 }\n"
                                              "print { min_radius = 0.5, size = 40 }\n");
  const auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(slurp(t.path / "o" / "run.json"));
  const std::size_t vein_cells = j["veins"]["vein_cells"];
  REQUIRE(vein_cells > 0);
  CHECK(j["print"]["segments"] == vein_cells);  // one per vein cell, to its parent: as veins.ply's edges
  CHECK(j["print"]["parts"] == 1);
}

TEST_CASE("every frame of a run with venation has the same properties, the first too", "[cli][venation]") {
  // a sequence imported into Houdini or Blender keeps one attribute layout: the first frame, of the cells
  // as placed, had no flow or vein attributes
  TempDir t("cli-frame-layout");
  const auto script =
      t.write("frames.lua", std::string(kTwoDiscs) + "petiole { at = {0, -4, 0} }\noutput { every = 10 }\n");
  REQUIRE(cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet"}).code == 0);
  auto properties = [](const std::string& ply) {
    std::string out;
    std::istringstream in(ply.substr(0, ply.find("end_header")));
    for (std::string line; std::getline(in, line);)
      if (line.rfind("property", 0) == 0) out += line + "\n";
    return out;
  };
  const std::string first = properties(slurp(t.path / "o" / "frames/cells_000000.ply"));
  CHECK_THAT(first, Contains("flow") && Contains("vein_order"));
  CHECK(first == properties(slurp(t.path / "o" / "frames/cells_000010.ply")));
  CHECK(first == properties(slurp(t.path / "o" / "cells.ply")));
  // --steps 0 (an export audit): its cells.ply had none of them, and no frame was written, though a
  // sequence starts with the cells as placed; the frame and cells.ply are now one and the same
  REQUIRE(cli({"run", script.string(), "--out", (t.path / "zero").string(), "--quiet", "--steps", "0"}).code == 0);
  CHECK(properties(slurp(t.path / "zero" / "cells.ply")) == first);
  CHECK(slurp(t.path / "zero" / "frames/cells_000000.ply") == slurp(t.path / "o" / "frames/cells_000000.ply"));
  CHECK(slurp(t.path / "zero" / "cells.ply") == slurp(t.path / "zero" / "frames/cells_000000.ply"));
}

TEST_CASE("the first frame's vein attributes are not seen by the rules before canalisation made them",
          "[cli][venation]") {
  // frame 0 gets them on a copy: a rule of step 1 reads nil, as in a run without frames
  TempDir t("cli-frame-rules");
  const auto script = t.write("rules.lua",
                              "run { steps = 3, seed = 1 }\nvenation { threshold = 10 }\ndisc { radius = 4 }\n"
                              "petiole { at = {0, -4, 0} }\noutput { every = 1 }\n"
                              "division { rule = function(cell)\n  if cell.step == 1 and cell.flow ~= nil then "
                              "error('flow seen') end\n  return cell.age > 1\nend }\n");
  const auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet", "--steps", "3"});
  CHECK_THAT(r.err, !Contains("flow seen"));
  CHECK(r.code == 0);
  CHECK(fs::exists(t.path / "o" / "frames/cells_000003.ply"));
}

TEST_CASE("a petiole that grew no vein is noted, with where it is and why", "[cli][venation]") {
  TempDir t("cli-veinless");
  // the second petiole comes at step 110 onto the vein the first one has grown along the strip: it
  // collects only the cells nearer to it than to that vein
  const auto late = t.write("late.lua",
                            "division { trigger = 'none' }\nrun { steps = 120 }\nvenation { threshold = 12 }\n"
                            "rectangle { width = 16, height = 4 }\npetiole { at = {-8, 0, 0} }\n"
                            "petiole { at = {2, 0, 0}, step = 110 }\n");
  auto r = cli({"run", late.string(), "--out", (t.path / "a").string(), "--quiet"});  // (a note, not progress)
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("note: the petiole at {2") && Contains("grew no vein") &&
                        Contains("venation.threshold (12)") && !Contains("the petiole at {-8"));
  // a source rule that gives no auxin: running longer cannot help, which is said (a walkthrough was told to)
  const auto dry = t.write("dry.lua",
                           "division { trigger = 'none' }\nrun { steps = 30 }\n"
                           "venation { threshold = 12, source = function(cell) return 0 end }\n"
                           "rectangle { width = 16, height = 4 }\npetiole { at = {-8, 0, 0} }\n");
  r = cli({"run", dry.string(), "--out", (t.path / "dry").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("(0 in all)") && Contains("No auxin flows anywhere: the cells make none") &&
                        !Contains("run longer"));
  // placed at the start, it collects its own half of the strip and grows veins: nothing is said
  const auto early = t.write("early.lua",
                             "division { trigger = 'none' }\nrun { steps = 120 }\nvenation { threshold = 12 }\n"
                             "rectangle { width = 16, height = 4 }\npetiole { at = {-8, 0, 0} }\n"
                             "petiole { at = {8, 0, 0} }\n");
  r = cli({"run", early.string(), "--out", (t.path / "b").string()});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("grew no vein"));
  // beyond link_range from every cell (though within the 3 rest lengths a petiole may be placed at): no
  // link at all, which is said instead of the veins it did not meet
  const auto apart = t.write("apart.lua",
                             "division { trigger = 'none' }\nrun { steps = 20 }\nvenation { threshold = 5 }\n"
                             "disc { radius = 3 }\npetiole { at = {0, -5.5, 0} }\n");
  r = cli({"run", apart.string(), "--out", (t.path / "c").string()});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("note: the petiole at {0, -5.5, 0}") && Contains("it is linked to no cell") &&
                        Contains("(the nearest linked cell is 2.") && !Contains("where veins already run"));
  // added at the run's last step, next to a cell: not linked yet, which the note says (it blamed the distance)
  const auto last =
      t.write("last.lua",
              "division { trigger = 'none' }\nrun { steps = 20 }\nvenation { threshold = 5 }\n"
              "disc { radius = 3 }\npetiole { at = {0, -3, 0} }\npetiole { at = {0, 3.4, 0}, step = 20 }\n");
  r = cli({"run", last.string(), "--out", (t.path / "d").string()});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("note: the petiole at {0, 3.4, 0}") && Contains("it is linked to no cell") &&
                        Contains("A petiole due at the run's last step is linked only in the next step"));
  // a petiole apart from the form that divided at the last step: the distance to the form is said, not the
  // half rest length to its own new daughter
  const auto split = t.write("split.lua",
                             "division { trigger = 'age', age = 5 }\nrun { steps = 5 }\nvenation { threshold = 5 }\n"
                             "disc { radius = 3 }\npetiole { at = {0, -5.5, 0} }\n");
  r = cli({"run", split.string(), "--out", (t.path / "e").string()});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("note: the petiole at {0, -5.5, 0}") && Contains("(the nearest linked cell is 2."));
}

TEST_CASE("a quick try with --steps ends before any vein: the print is skipped, and the note says why",
          "[cli][venation]") {
  TempDir t("cli-short-try");
  const auto script = t.write("leaf.lua",
                              "run { steps = 300 }\nvenation { threshold = 30 }\ndisc { radius = 3 }\n"
                              "petiole { at = {0, -3, 0} }\nprint { size = 40 }\n");
  auto r = cli({"run", script.string(), "--out", (t.path / "a").string(), "--steps", "5", "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("print: skipped: nothing to print yet at step 5 (no vein has grown; the run was cut short "
                             "at step 5 of the script's 300)") &&
                        Contains("No vein has grown anywhere yet: run longer") &&
                        !Contains("where veins already run") && !Contains("stopped with an error"));
  auto j = nlohmann::json::parse(slurp(t.path / "a" / "run.json"));
  CHECK(j["status"] == "complete");
  CHECK(j["print"].contains("skipped"));
  CHECK(!fs::exists(t.path / "a" / "printable.stl"));
  // resuming that checkpoint, no step to run, skips it again (it failed, exit 1)
  r = cli({"resume", (t.path / "a").string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("print: skipped: nothing to print yet at step 5"));
  // a print that growth cannot make (a shell of a line of cells) still fails a short try
  const auto line = t.write("line.lua",
                            "run { steps = 300 }\nline { from = {0, 0, 0}, to = {5, 0, 0} }\n"
                            "print { veins = false, shell = true }\n");
  r = cli({"run", line.string(), "--out", (t.path / "c").string(), "--steps", "5", "--quiet"});
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("no sheet of triangles") && !Contains("skipped"));
  // a print of veins with the sheet is skipped too: not made of the sheet alone, nor failed (a flat base 2 mm
  // high does not fit the flat disc of step 5; before, the try printed the sheet and failed there)
  const auto shell = t.write("shell.lua",
                             "run { steps = 300 }\nvenation { threshold = 30 }\ndisc { radius = 3 }\n"
                             "petiole { at = {0, -3, 0} }\nprint { size = 40, shell = true, flat_base = 2 }\n");
  r = cli({"run", shell.string(), "--out", (t.path / "s").string(), "--steps", "5", "--quiet"});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("print: skipped: nothing to print yet at step 5") && !Contains("flat_base"));
  CHECK(!fs::exists(t.path / "s" / "printable.stl"));
  // the whole script with nothing to print (too high a threshold) still fails, as it asked for a print
  r = cli(
      {"run", script.string(), "--out", (t.path / "b").string(), "--steps", "5", "--set", "run.steps=5", "--quiet"});
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("print: nothing to print yet"));
  CHECK(nlohmann::json::parse(slurp(t.path / "b" / "run.json"))["status"] == "print failed");
}
