// Tests of app/script_placement.cpp: cells placed on each other, mesh{} obstacles in other units than the cells.
#include <catch2/catch.hpp>

#include <string>

#include "app/script_host.h"
#include "tests/app/script_test_util.h"
#include "tests/app/test_util.h"

using Catch::Matchers::Contains;
using cellform::test::load;
using cellform::test::load_error;
using cellform::test::TempDir;

TEST_CASE("cells placed at the point of earlier ones are noted, and refused by the thousand", "[script]") {
  // a shape placed twice: noted, naming the call that placed the repeats
  auto cfg = load("disc { radius = 2 }\nline { from = {5, 0, 0}, to = {9, 0, 0} }\ndisc { radius = 2 }\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:3: disc: 19 cells lie at the point of an earlier cell"));
  // a hair apart (in one box of a thousandth of a rest length) is the same point; a hundredth apart, nothing is said
  cfg = load("disc { radius = 2 }\ndisc { radius = 2, centre = {0, 0, 1e-9} }\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:2: disc: 19 cells lie at the point of an earlier cell (rounded to "
                                    "a thousandth of a rest length"));
  CHECK(load("disc { radius = 2 }\ndisc { radius = 2, centre = {0, 0, 0.01} }\n").notes.empty());
  // one cell{} loop that never moves on: 100,000 at one point took 97 s for 3 steps (each is every other's
  // nearest), refused over 1,000 naming the point; 1,000 are noted
  CHECK_THAT(load_error("for i = 1, 1001 do cell { at = {1, 2, 3} } end\n"),
             Contains("test/leaf.lua:1: cell: 1001 cells lie at the point {1, 2, 3} (rounded to a thousandth of a "
                      "rest length), over 1000"));
  // nor does a loop that moves on by a rounding error: 60,000 cells 1e-9 apart took 28 s for 3 steps
  CHECK_THAT(load_error("for i = 1, 1001 do cell { at = {1 + i * 1e-9, 2, 3} } end\n"),
             Contains("test/leaf.lua:1: cell: 1001 cells lie at the point {1, 2, 3}"));
  cfg = load("cell { at = {0, 0, 0} }\nfor i = 1, 1000 do cell { at = {1, 2, 3} } end\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:2: cell: 999 cells lie at the point of an earlier cell"));
}

TEST_CASE("a mesh obstacle in other units than the cells is noted, and run.json records what it held", "[script]") {
  // (a designer's walkthrough: a wall drawn in millimetres, 100 units from the cells, and a rock scaled to 0.0005
  // units were taken without a word, and run.json held only the file's name)
  TempDir t("script-lost-meshes");
  auto triangle = [&](const std::string& name, double x, double size) {
    return t
        .write(name, "v " + std::to_string(x) + " 0 0\nv " + std::to_string(x + 0.6 * size) + " 0 0\nv " +
                         std::to_string(x) + " " + std::to_string(0.8 * size) + " 0\nf 1 2 3\n")
        .string();
  };
  t.write("cube.obj",
          "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
          "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
  // a disc of radius 2 spans sqrt(4^2 + (2 sqrt 3)^2) = 5.2915; a triangle 0.0005 across, one 98 away, one 8 away
  const std::string disc = "disc { radius = 2 }\n";
  auto cfg = load(disc + "mesh { file = '" + triangle("tiny.obj", 5, 0.0005) + "' }\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:2: mesh{...}: '" + (t.path / "tiny.obj").string() +
                                    "' is 0.0005 model units across, less than a rest length (cells.rest_length = 1)"));
  cfg = load(disc + "mesh { file = '" + triangle("far.obj", 100, 10) + "' }\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("' lies 98 model units from the cells placed at the start, which span 5.2915 (it "
                                    "spans 10)") &&
                               Contains("mesh.scale"));
  cfg = load(disc + "mesh { file = '" + triangle("near.obj", 10, 10) + "', scale = 2 }\n");
  CHECK(cfg.notes.empty());
  // run.json's record: its triangles, its box in model units (scaled) and its file's fingerprint
  const auto& rec = cfg.resolved["constraints"][0];
  CHECK(rec["triangles"] == 1);
  CHECK(rec["bounds"]["min"] == nlohmann::json::array({20.0, 0.0, 0.0}));
  CHECK(rec["bounds"]["max"] == nlohmann::json::array({32.0, 16.0, 0.0}));
  CHECK(rec["fingerprint"].get<std::string>().rfind("fnv1a64:", 0) == 0);
  // offset moves it after the scale (a site model drawn far from the origin): the far one brought to the cells
  cfg = load(disc + "mesh { file = '" + triangle("far.obj", 100, 10) + "', scale = 0.5, offset = {-47, 1, 2} }\n");
  CHECK(cfg.notes.empty());
  CHECK(cfg.resolved["constraints"][0]["bounds"]["min"] == nlohmann::json::array({3.0, 1.0, 2.0}));
  CHECK(cfg.scene.obstacles.meshes[0].vertices[1] == cellform::core::Vec3(3 + 0.5 * 6, 1, 2));
  CHECK(cfg.resolved["constraints"][0]["offset"] == nlohmann::json::array({-47.0, 1.0, 2.0}));
  // a volume or surface file too; without a file an offset moves nothing, and says so
  cfg = load("volume { file = '" + (t.path / "cube.obj").string() +
             "', offset = {10, 0, 0}, seeds = {{10.5, 0.5, 0.5}} }\n"
             "colonisation {}\n");
  CHECK(cfg.colonisation->domain.mesh.vertices[0].x() >= 10);
  CHECK_THAT(load_error("volume { box = {min = {0, 0, 0}, max = {1, 1, 1}}, offset = {1, 0, 0} }\ncolonisation {}\n"),
             Contains("test/leaf.lua:1: volume.offset moves the coordinates of a mesh file (volume{file = ...}), and "
                      "there is none here"));
}
