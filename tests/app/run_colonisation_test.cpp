// Tests of what a space-colonisation run says at its end (app/run_colonisation.cpp).
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {
// a closed box 20 x 20 x `thick` (model units), its top at z = thick
std::string slab(double thick) {
  const std::string t = std::to_string(thick);
  return "v -10 -10 0\nv 10 -10 0\nv 10 10 0\nv -10 10 0\nv -10 -10 " + t + "\nv 10 -10 " + t + "\nv 10 10 " + t +
         "\nv -10 10 " + t +
         "\nf 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 "
         "8\n";
}
}  // namespace

TEST_CASE("veins that stall behind a thin wall of a surface say why, and how to go on", "[cli][colonisation]") {
  TempDir t("cli-thin-wall");
  t.write("thin.obj", slab(2));
  t.write("thick.obj", slab(8));
  const std::string rule =
      "colonisation { type = 'open', kill_distance = 1, birth_distance = 3, darts = 20000 }\nrun { seed = 1 }\n";
  // 2 segments thick: a source on the floor pulls the ceiling's node straight down, and its step lands back
  const auto thin = t.write("thin.lua", "surface { file = 'thin.obj', seeds = {{0, 0, 2}} }\n" + rule);
  auto r = cli({"run", thin.string(), "--out", (t.path / "a").string(), "--quiet"});
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(slurp(t.path / "a" / "run.json"));
  CHECK(j["status"] == "stalled");
  const std::size_t left = j["veins"]["sources_left"];
  CHECK(left > 0);
  CHECK_THAT(r.err, Contains("note: " + std::to_string(left) + " auxin sources are left") &&
                        Contains("thinner than about 3 vein segments") && Contains("surface{scale = ...}"));
  // 8 thick: the veins go round the rim, and nothing is said
  const auto thick = t.write("thick.lua", "surface { file = 'thick.obj', seeds = {{0, 0, 8}} }\n" + rule);
  r = cli({"run", thick.string(), "--out", (t.path / "b").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(t.path / "b" / "run.json"))["status"] == "complete");
  CHECK_THAT(r.err, !Contains("auxin sources are left"));
}

TEST_CASE("a 3-D domain thousands of segments across, as a mesh drawn in mm gives, is noted at the start",
          "[cli][colonisation]") {
  TempDir t("cli-large-domain");
  t.write("plate.obj", "v 0 0 0\nv 2000 0 0\nv 2000 2000 0\nv 0 2000 0\nf 1 2 3\nf 1 3 4\n");
  const std::string rule = "colonisation { birth_distance = 3, kill_distance = 1, darts = 1e-5, max_steps = 2 }\n";
  const auto mm = t.write("mm.lua", "surface { file = 'plate.obj', seeds = {{1000, 1000, 0}} }\n" + rule);
  auto r = cli({"run", mm.string(), "--out", (t.path / "a").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("note: the surface spans 2000 vein segments (model units) at its longest") &&
                        Contains("wants surface{scale = ...}"));
  // scaled to 100 segments: nothing is said
  const auto scaled =
      t.write("scaled.lua", "surface { file = 'plate.obj', scale = 0.05, seeds = {{50, 50, 0}} }\n" + rule);
  r = cli({"run", scaled.string(), "--out", (t.path / "b").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("at its longest"));
  // a box is given in segments: said, without the mesh's remedy
  const auto box = t.write("box.lua", "volume { box = { min = {0, 0, 0}, max = {1500, 10, 10} } }\n" + rule);
  r = cli({"run", box.string(), "--out", (t.path / "c").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err,
             Contains("note: the volume spans 1500 vein segments (model units) at its longest") && !Contains("scale"));
}

TEST_CASE("a colonisation quick try with --steps ends before any vein: the print is skipped, and says why",
          "[cli][colonisation]") {
  TempDir t("cli-col-short-try");
  // darts land on the marginal leaf only once it has grown: none in the first 3 steps
  const auto script = t.write("leaf.lua",
                              "leaf { shape = 'ellipse' }\ncolonisation { type = 'open', kill_distance = 1, "
                              "birth_distance = 1, growth = 'marginal', initial_length = 0.5, final_length = 40, "
                              "length_step = 0.2, darts = 200, max_steps = 400 }\nprint { formats = 'stl' }\n");
  auto r = cli({"run", script.string(), "--out", (t.path / "a").string(), "--steps", "3", "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("print: skipped: nothing to print yet at step 3 (no vein has grown; the run was cut "
                             "short at step 3 of the script's 400)"));
  auto j = nlohmann::json::parse(slurp(t.path / "a" / "run.json"));
  CHECK(j["status"] == "stopped at max_steps");
  CHECK(j["print"].contains("skipped"));
  CHECK(!fs::exists(t.path / "a" / "printable.stl"));
  // the whole script with nothing grown still fails, as it asked for a print
  r = cli({"run", script.string(), "--out", (t.path / "b").string(), "--steps", "3", "--set",
           "colonisation.max_steps=3", "--quiet"});
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("nothing to print: no vein grew") && !Contains("skipped"));
  // a quick try long enough to grow veins prints them
  r = cli({"run", script.string(), "--out", (t.path / "c").string(), "--steps", "60", "--quiet"});
  CHECK(r.code == 0);
  CHECK(fs::exists(t.path / "c" / "printable.stl"));
}
