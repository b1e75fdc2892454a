// Tests of the cellform command line for a colonisation run whose surface{cells = true} sheet fails while
// it grows (app/run_colonisation.cpp, app/run_sheet.cpp): the failed run.json, its checkpoint and how to go on.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "app/run_internal.h"
#include "core/chunk_file.h"
#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// A failed run's timings: the sheet's steps and its checkpoints, each within the whole run's time.
void check_failed_timings(const nlohmann::json& run) {
  const nlohmann::json& t = run["timings"];
  INFO(t.dump());
  REQUIRE(t.contains("sheet_s"));
  REQUIRE(t.contains("checkpoints_s"));
  CHECK_FALSE(t.contains("simulation_s"));  // no vein grew
  const double sheet = t["sheet_s"], checkpoints = t["checkpoints_s"], total = t["total_s"];
  CHECK(sheet > 0);
  CHECK(checkpoints >= 0);
  CHECK(sheet + checkpoints <= total);
}

}  // namespace

TEST_CASE("a rule error while surface{cells = true}'s sheet grows can go on with the corrected script",
          "[cli][checkpoint]") {
  TempDir t("cli-sheet-script");
  const std::string head =
      "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.3} }\n"
      "division { max_cells = 400, min_age = 3, rule = function(cell)\n"
      "  if cell.step >= 15 then return ";
  const std::string tail =
      " end\n"
      "  return cell.age > 5 end }\n"
      "run { steps = 40 }\n"
      "disc { radius = 4 }\n"
      "petiole { at = {0, -4, 0} }\n"
      "surface { cells = true }\n"
      "colonisation { kill_distance = 1, birth_distance = 2, darts = 20000 }\n";
  const auto broken = t.write("broken.lua", head + "'x'" + tail);
  const auto fixed = t.write("fixed.lua", head + "cell.age > 7" + tail);
  const fs::path out = t.path / "out", fresh = t.path / "fresh";
  const std::string checkpoint = (out / "checkpoint.cfck").string();
  // an earlier run in the folder: the failed run's run.json and checkpoint replace it, not sit beside it
  REQUIRE(cli({"run", fixed.string(), "--out", out.string(), "--quiet"}).code == 0);
  REQUIRE(fs::exists(out / "veins.ply"));
  CliResult r = cli({"run", broken.string(), "--out", out.string(), "--checkpoint-every", "5", "--quiet"});
  REQUIRE(r.code == 2);
  // the error first, then where to go on from
  const std::size_t error = r.err.find("broken.lua:2: division.rule must return true or false");
  const std::size_t where =
      r.err.find("(the last checkpoint is " + checkpoint + ", taken while the sheet grew at step 10)");
  REQUIRE(error != std::string::npos);
  REQUIRE(where != std::string::npos);
  CHECK(error < where);
  CHECK_THAT(r.err, Contains("cellform resume " + checkpoint + " --script " + broken.string()));
  auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "failed");
  CHECK(run["phase"] == "cells");
  check_failed_timings(run);
  CHECK(run["timings"]["checkpoints_s"] > 0);  // those of steps 5 and 10
  CHECK(run["steps"]["sheet_failed"] == 15);
  CHECK(run["steps"]["sheet_completed"] == 10);
  CHECK_FALSE(fs::exists(out / "veins.ply"));
  {  // a rule that changes a knob fails at the step it changed it in, as the message says
    const auto knob =
        t.write("knob.lua", "local P = params { n = 3 }\n" + head + "false end if cell.step == 12 then P.n = 4" + tail);
    const fs::path k = t.path / "knob";
    const CliResult kr = cli({"run", knob.string(), "--out", k.string(), "--checkpoint-every", "5", "--quiet"});
    CHECK(kr.code == 2);
    CHECK_THAT(kr.err, Contains("by the end of step 12"));
    CHECK(nlohmann::json::parse(slurp(k / "run.json"))["steps"]["sheet_failed"] == 12);
  }
  // a plain resume stops at the same step, and names the checkpoint it resumed
  r = cli({"resume", checkpoint, "--out", (t.path / "again").string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("(the last checkpoint is " + checkpoint + ", the one resumed)") && Contains("--script"));
  r = cli({"resume", checkpoint, "--script", fixed.string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  REQUIRE(cli({"run", fixed.string(), "--out", fresh.string(), "--quiet"}).code == 0);
  CHECK(slurp(out / "cells.ply") == slurp(fresh / "cells.ply"));
  CHECK(slurp(out / "veins.ply") == slurp(fresh / "veins.ply"));
  run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "complete");
  CHECK(run["script"]["replaces"][0]["hash"] == cellform::app::script_hash(slurp(broken)));
}

TEST_CASE("a cell sheet that diverges under surface{cells = true} leaves its last good step and a failed run.json",
          "[cli][checkpoint]") {
  TempDir t("cli-sheet-diverged");
  const auto script = t.write("sd.lua",
                              "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.3}, max_speed = 0.1 }\n"
                              "division { trigger = 'age', age = 6, max_cells = 400 }\n"
                              "run { steps = 40 }\n"
                              "disc { radius = 4 }\n"
                              "petiole { at = {0, -4, 0} }\n"
                              "surface { cells = true }\n"
                              "colonisation { kill_distance = 1, birth_distance = 2, darts = 20000 }\n");
  const fs::path out = t.path / "out";
  const std::string checkpoint = (out / "checkpoint.cfck").string();
  const CliResult r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
  REQUIRE(r.code == 1);
  CHECK_THAT(r.err, Contains("the simulation diverged") &&
                        Contains("cellform resume " + checkpoint + " --script " + script.string()));
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "failed");
  CHECK(run["phase"] == "cells");
  check_failed_timings(run);
  const std::uint64_t good = run["steps"]["sheet_completed"];
  CHECK(run["steps"]["sheet_failed"] == good + 1);
  const auto saved = cellform::core::read_chunk_file(slurp(out / "checkpoint.cfck"), "CKPT", 1, "test");
  const auto meta = nlohmann::json::parse(saved.chunks.at("meta"));
  CHECK(meta["mode"] == "sheet");
  CHECK(meta["step"] == good);
}
