// Tests of app/script_sections.cpp: print sizes, cells placed on each other.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "app/script_host.h"
#include "tests/app/script_test_util.h"
#include "tests/app/test_util.h"

using Catch::Matchers::Contains;
using cellform::test::load;
using cellform::test::load_error;
using cellform::test::TempDir;

TEST_CASE("print sizes no printer can make are refused while the script is read", "[script]") {
  // audit: 1e-320 mm was refused only after the steps, by a memory message saying "inf mm"
  CHECK_THAT(load_error("disc { radius = 2 }\nprint { min_radius = 1e-320 }\n"),
             Contains("test/leaf.lua:2: print.min_radius must be a number from 0.0001 to 1000"));
  CHECK_THAT(load_error("disc { radius = 2 }\nprint { shell = true, shell_thickness = 1e-320 }\n"),
             Contains("test/leaf.lua:2: print.shell_thickness must be a number from 0.0001 to 1000"));
  CHECK_THAT(load_error("disc { radius = 2 }\nprint { voxel_size = 1e-320 }\n"),
             Contains("test/leaf.lua:2: print.voxel_size must be 0, or a number from 1e-05 to 1000"));
  CHECK_NOTHROW(load("disc { radius = 2 }\nprint { shell = true, min_radius = 0.0001, voxel_size = 0.0001 }\n"));
}

TEST_CASE("cells placed at the point of earlier ones are noted, and refused by the thousand", "[script]") {
  // a shape placed twice: noted, naming the call that placed the repeats
  auto cfg = load("disc { radius = 2 }\nline { from = {5, 0, 0}, to = {9, 0, 0} }\ndisc { radius = 2 }\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:3: disc: 19 cells lie at the point of an earlier cell"));
  // a hair apart (within a thousandth of a rest length) is the same point; apart by a hundredth, nothing is said
  cfg = load("disc { radius = 2 }\ndisc { radius = 2, centre = {0, 0, 1e-9} }\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:2: disc: 19 cells lie at the point of an earlier cell (within a "
                                    "thousandth of a rest length"));
  CHECK(load("disc { radius = 2 }\ndisc { radius = 2, centre = {0, 0, 0.01} }\n").notes.empty());
  // one cell{} loop that never moves on: 100,000 at one point took 97 s for 3 steps (each is every other's
  // nearest), refused over 1,000 naming the point; 1,000 are noted
  CHECK_THAT(load_error("for i = 1, 1001 do cell { at = {1, 2, 3} } end\n"),
             Contains("test/leaf.lua:1: cell: 1001 cells lie at the point {1, 2, 3} (within a thousandth of a rest "
                      "length), over 1000"));
  // nor does a loop that moves on by a rounding error: 60,000 cells 1e-9 apart took 28 s for 3 steps
  CHECK_THAT(load_error("for i = 1, 1001 do cell { at = {1 + i * 1e-9, 2, 3} } end\n"),
             Contains("test/leaf.lua:1: cell: 1001 cells lie at the point {1, 2, 3}"));
  cfg = load("cell { at = {0, 0, 0} }\nfor i = 1, 1000 do cell { at = {1, 2, 3} } end\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:2: cell: 999 cells lie at the point of an earlier cell"));
}
