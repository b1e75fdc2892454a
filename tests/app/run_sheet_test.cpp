// Tests of surface{cells = true} runs through the command line (app/run_sheet.cpp, app/run_colonisation.cpp):
// the steps its sheet grew, in run.json and on resume.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstring>
#include <nlohmann/json.hpp>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("surface{cells = true}: the steps the sheet grew are recorded, and a resume says it keeps that sheet",
          "[cli]") {
  TempDir t("sheet-steps");
  const auto script = t.write("sheet.lua", std::string(kSmall) +
                                               "surface { cells = true }\n"
                                               "colonisation { birth_distance = 1, kill_distance = 0.5, "
                                               "darts = 1e6, max_steps = 30 }\n");
  const fs::path out = t.path / "o";
  // --steps cuts the sheet (run.steps = 30) and limits the veins
  auto r = cli({"run", script.string(), "--out", out.string(), "--steps", "20", "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["cells"]["steps"] == 20);
  CHECK(run["parameters"]["run"]["steps"] == 20);  // it said 30: run.json's values grew another sheet
  const auto cells = run["cells"]["final"];
  // the same run from run.json's values: the same sheet
  const fs::path again = t.path / "again";
  r = cli({"run", script.string(), "--out", again.string(), "--set",
           "run.steps=" + run["parameters"]["run"]["steps"].dump(), "--set", "colonisation.max_steps=20", "--quiet"});
  REQUIRE(r.code == 0);
  CHECK(slurp(again / "cells.ply") == slurp(out / "cells.ply"));
  // a resume with a higher --steps takes the veins further on that sheet, and says that the sheet stays
  r = cli({"resume", out.string(), "--steps", "40"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("the sheet grew 20 steps") && Contains("a new run grows the whole sheet"));
  run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["cells"]["final"] == cells);
  CHECK(run["cells"]["steps"] == 20);
  CHECK(run["parameters"]["run"]["steps"] == 20);
  // a run of the script's own steps says nothing of the kind on resume
  const fs::path whole = t.path / "whole";
  REQUIRE(cli({"run", script.string(), "--out", whole.string(), "--quiet"}).code == 0);
  CHECK(nlohmann::json::parse(slurp(whole / "run.json"))["cells"]["steps"] == 30);
  r = cli({"resume", whole.string(), "--steps", "40"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("the sheet grew"));
}

TEST_CASE("surface{cells = true}: a seed far off the grown sheet is refused, a near one moves onto it", "[cli]") {
  TempDir t("sheet-seeds");
  const auto run = [&](const std::string& seed) {
    const auto script = t.write("seed.lua", std::string(kSmall) + "surface { cells = true, seeds = {" + seed +
                                                "} }\ncolonisation { birth_distance = 1, kill_distance = 0.5, "
                                                "darts = 1e6, max_steps = 10 }\n");
    return cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet"});
  };
  // 50 units out from a sheet about 8 across: moved there without a word
  const auto far = run("{50, 0, 0}");
  CHECK(far.code == 2);
  // named with the line of surface{...}, the first after kSmall's
  const std::string line = std::to_string(std::count(kSmall, kSmall + std::strlen(kSmall), '\n') + 1);
  CHECK_THAT(far.err, Contains("seed.lua:" + line + ": surface.seeds[1] {50, 0, 0} is 4") &&
                          Contains("model units from the grown sheet") &&
                          Contains("at most half the sheet's size or 3 cell spacings away"));
  const auto near = run("{0, 0, 0.5}");  // half a spacing above the sheet
  INFO(near.err);
  CHECK(near.code == 0);
}
