// Tests of what a cell run says as it goes (app/run.cpp), and of run.json's timings.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("a run whose cells reach division.max_cells says when, once", "[cli]") {
  TempDir t("cli-max-cells");
  const auto script = t.write(
      "full.lua", "run { steps = 60 }\ndivision { trigger = 'age', age = 3, max_cells = 50 }\ndisc { radius = 2 }\n");
  auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet"});  // notes: not progress
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("note: the cells reached division.max_cells = 50 at step ") &&
                        Contains("no cell divided after it (raise") && !Contains("division.rule"));
  // a rule is not called after it either: said, since a run kept small never reaches a rule's late code
  const auto ruled =
      t.write("ruled.lua",
              "run { steps = 60 }\ndivision { max_cells = 50, rule = function(c) return c.age > 2 end }\n"
              "disc { radius = 2 }\n");
  r = cli({"run", ruled.string(), "--out", (t.path / "r").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("no cell divided after it, nor was division.rule called (raise"));
  // resumed full: nothing new to say
  r = cli({"resume", (t.path / "o").string(), "--steps", "70"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("max_cells"));
  // resumed at its last step: what that does is said (a print made again, say), and how to go on
  r = cli({"resume", (t.path / "o").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("at its run's last step (70): no step runs, the outputs are made again; give --steps N"));
  // under the limit: nothing said
  r = cli(
      {"run", script.string(), "--out", (t.path / "p").string(), "--set", "division.max_cells=5000", "--steps", "20"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("max_cells"));
}

TEST_CASE("a refused parameter recalls the knobs the run set, which it may come from", "[cli]") {
  TempDir t("cli-knob-hint");
  const auto script =
      t.write("k.lua", "local P = params { scale = 1 }\nrun { steps = 2 }\ndisc { radius = 2 * P.scale }\n");
  auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--set", "scale=-1"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("k.lua:3") && Contains("this run sets the script's knobs scale=-1"));
  // a parameter set directly is named by the message itself: no recall
  r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--set", "cells.time_step=-1"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, !Contains("knobs"));
  // nor when knobs are set too: the message is of the value --set gave
  r = cli(
      {"run", script.string(), "--out", (t.path / "o").string(), "--set", "scale=2", "--set", "cells.time_step=-1"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("cells.time_step") && !Contains("knobs"));
}

TEST_CASE("a colonisation value refused when the veins start recalls the knobs too", "[cli][colonisation]") {
  // marginal growth precomputes its sources over the final blade: too many is found when the run starts
  TempDir t("cli-knob-hint-veins");
  const auto script = t.write("m.lua",
                              "local P = params { scale = 1 }\nleaf {}\n"
                              "colonisation { type = 'open', growth = 'marginal', birth_distance = 1, darts = 300,\n"
                              "  initial_length = 10, length_step = 10, final_length = 3000 * P.scale }\n");
  const auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--set", "scale=10"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("more than 5 x 10^7") && Contains("this run sets the script's knobs scale=10"));
  CHECK_FALSE(std::filesystem::exists(t.path / "o"));
}

TEST_CASE("petioles resting on one point of a grown sheet are refused for closed veins, accepted for open",
          "[cli][colonisation]") {
  // both petioles stand beyond the disc's edge in one line: the nearest point of the sheet is the same
  TempDir t("cli-sheet-seeds");
  const std::string head =
      "division { trigger = 'none' }\nrun { steps = 5, seed = 1 }\ndisc { radius = 3 }\n"
      "petiole { at = {0, -5, 0} }\npetiole { at = {0, -5.6, 0} }\nsurface { cells = true }\n"
      "colonisation { kill_distance = 1, birth_distance = 2, darts = 20000, type = ";
  const auto closed = t.write("closed.lua", head + "'closed' }\n");
  auto r = cli({"run", closed.string(), "--out", (t.path / "c").string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("the petioles at {0, -5, 0} and {0, -5.6, 0} rest on the same point of the grown sheet"));
  const auto open = t.write("open.lua", head + "'open' }\n");
  r = cli({"run", open.string(), "--out", (t.path / "o").string(), "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK(std::filesystem::exists(t.path / "o" / "veins.ply"));
}

TEST_CASE("a rule that yields outside a coroutine is named with its line, step and cell", "[cli]") {
  // audit: the message had no line, in a rule as at the top of a script
  TempDir t("cli-rule-yield");
  const auto script = t.write("yield.lua",
                              "disc { radius = 2 }\n"
                              "division { rule = function(c) coroutine.yield(1) return true end }\n");
  const auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("yield.lua:2: attempt to yield from outside a coroutine (in division.rule at step "));
}

TEST_CASE("run.json's timings give the periodic checkpoints apart from the steps", "[cli][checkpoint]") {
  // a long run's checkpoints can cost as much as its steps (29 of 250 MB in the full-size poplar): said apart
  TempDir t("cli-checkpoint-time");
  const auto cells = t.write("cells.lua", kSmall);
  const auto veins = t.write("ball.lua", kSmallVeins);
  const auto sheet = t.write("sheet.lua", std::string(kSmall) +
                                              "surface { cells = true }\n"
                                              "colonisation { birth_distance = 1, kill_distance = 1, darts = 1e6 }\n");
  for (const auto& script : {cells, veins, sheet}) {
    INFO(script.filename().string());
    auto timings = [&](const std::string& every) {
      const fs::path out = t.path / (script.stem().string() + every);
      const auto r = cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "20", "--set",
                          "output.checkpoint_every=" + every, "--set", "output.checkpoint_seconds=0"});
      INFO(r.err);
      REQUIRE(r.code == 0);
      return nlohmann::json::parse(slurp(out / "run.json"))["timings"];
    };
    const auto none = timings("0"), each = timings("1");
    CHECK(none.at("checkpoints_s") == 0.0);
    CHECK(each.at("checkpoints_s").get<double>() > 0);
    // disjoint parts of the whole: the steps (the sheet's too) do not count the checkpoints
    CHECK(each.at("simulation_s").get<double>() + each.value("sheet_s", 0.0) + each.at("checkpoints_s").get<double>() <=
          each.at("total_s").get<double>());
  }
}

TEST_CASE("fixed cells the moving cells came loose from are noted", "[cli]") {
  TempDir t("cli-loose");
  // one support in the sheet, two far off it: those two hold no link (the shell example's sheet pulled free)
  const auto script = t.write("s.lua",
                              "run { steps = 3 }\ndivision { trigger = 'none' }\ndisc { radius = 2 }\n"
                              "cell { at = {0, 0, 0.5}, fixed = true }\ncell { at = {20, 0, 0}, fixed = true }\n"
                              "cell { at = {-20, 0, 0}, fixed = true }\n");
  auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("note: 2 of the 3 fixed cells are linked to no cell that moves"));
  // all on the sheet: nothing said
  const auto held = t.write("h.lua",
                            "run { steps = 3 }\ndivision { trigger = 'none' }\ndisc { radius = 2 }\n"
                            "cell { at = {0, 0, 0.5}, fixed = true }\n");
  r = cli({"run", held.string(), "--out", (t.path / "h").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("fixed cells"));
  // a support of many fixed cells, touching the sheet with one side only: held through its own links (a review:
  // its inner cells were said to be loose)
  const auto block = t.write("b.lua",
                             "run { steps = 3 }\ndivision { trigger = 'none' }\ndisc { radius = 3 }\n"
                             "for i = 0, 4 do for j = -2, 2 do cell { at = {3.9 + i, j, 0}, fixed = true } end end\n");
  r = cli({"run", block.string(), "--out", (t.path / "b").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("fixed cells"));
}
