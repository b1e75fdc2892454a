// Tests of what a cell run says as it goes (app/run.cpp).
#include <catch2/catch.hpp>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;

TEST_CASE("a run whose cells reach division.max_cells says when, once", "[cli]") {
  TempDir t("cli-max-cells");
  const auto script = t.write(
      "full.lua", "run { steps = 60 }\ndivision { trigger = 'age', age = 3, max_cells = 50 }\ndisc { radius = 2 }\n");
  auto r = cli({"run", script.string(), "--out", (t.path / "o").string()});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("note: the cells reached division.max_cells = 50 at step "));
  // resumed full: nothing new to say
  r = cli({"resume", (t.path / "o").string(), "--steps", "70"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("max_cells"));
  // under the limit: nothing said
  r = cli(
      {"run", script.string(), "--out", (t.path / "p").string(), "--set", "division.max_cells=5000", "--steps", "20"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("max_cells"));
}
