// Tests of the print{} section as a script gives it: its formats, and the checks that need several of its
// values at once, made before the run.
#include <catch2/catch.hpp>

#include "tests/app/script_test_util.h"

using Catch::Matchers::Contains;
using cellform::test::load;
using cellform::test::load_error;

TEST_CASE("print values that contradict each other are refused before the run: voxel, vein radius, shell",
          "[script][print]") {
  CHECK_THAT(load_error("dsic { radius = 3 }\n"),
             Contains(":1: attempt to call a nil value (global 'dsic'); did you mean 'disc'?"));
  CHECK_THAT(load_error("disc { radius = 3 }\nfrobnicate()\n"), Contains(":2:") && Contains("; no such function"));
  // what a designer reaches for first, named by what the functions make (a walkthrough's obstacle{} got no more)
  CHECK_THAT(
      load_error("disc { radius = 3 }\nobstacle { file = 'rock.obj' }\n"),
      Contains("no such function (shapes: disc,") && Contains("obstacles: ground, half_space, ball, box, mesh;"));
  // a section's own name is not suggested for itself
  CHECK_THAT(load_error("run = nil\nrun { steps = 3 }\n"),
             Contains(":2:") && Contains("; the script set it to nil before this call") && !Contains("did you mean"));
  CHECK_THAT(load_error("disc { radius = 3 }\nvenation {}\npetiole {}\nprint { voxel_size = 1, min_radius = 0.4 }\n"),
             Contains(":4: print.voxel_size (1 mm) exceeds print.min_radius (0.4 mm)"));
  // a shell's wall needs two voxels across; min_radius binds only a print of veins
  CHECK_THAT(load_error("disc { radius = 3 }\nprint { shell = true, voxel_size = 0.4, shell_thickness = 0.6 }\n"),
             Contains(":2: print.voxel_size (0.4 mm) exceeds half of print.shell_thickness (0.6 mm)"));
  CHECK_NOTHROW(load("disc { radius = 3 }\nprint { shell = true, voxel_size = 0.5, shell_thickness = 1 }\n"));
  CHECK_THAT(load_error("disc { radius = 3 }\nvenation {}\npetiole {}\nprint { shell = true, voxel_size = 0.5, "
                        "shell_thickness = 1 }\n"),
             Contains(":4: print.voxel_size (0.5 mm) exceeds print.min_radius (0.4 mm)"));
  CHECK_NOTHROW(
      load("disc { radius = 3 }\nvenation {}\npetiole {}\nprint { shell = true, veins = false, "
           "voxel_size = 0.5, shell_thickness = 1 }\n"));
  // a shell thicker than the whole print (the auto scale fits the form to size, its walls come on top)
  CHECK_THAT(load_error("disc { radius = 3 }\nprint { shell = true, size = 20, shell_thickness = 30 }\n"),
             Contains(":2: print.shell_thickness (30 mm) is not less than print.size (20 mm"));
  CHECK_NOTHROW(load("disc { radius = 3 }\nprint { shell = true, size = 20, shell_thickness = 19 }\n"));
  CHECK_THAT(load_error("disc { radius = 3 }\nvenation {}\npetiole {}\nprint { size = 20, min_radius = 10 }\n"),
             Contains(":4: print.min_radius (10 mm) makes every vein at least 20 mm thick, not less than print.size"));
  CHECK_NOTHROW(load("disc { radius = 3 }\nprint { shell = true, scale = 1, shell_thickness = 30 }\n"));
  // a cut at least the print's largest extent leaves nothing (said after the whole run before)
  CHECK_THAT(load_error("disc { radius = 3 }\nprint { shell = true, flat_base = 120 }\n"),
             Contains(":2: print.flat_base (120 mm) is not less than print.size (120 mm") &&
                 Contains("would cut the whole form away"));
  CHECK_NOTHROW(load("disc { radius = 3 }\nprint { shell = true, flat_base = 119 }\n"));  // the height decides
  CHECK_NOTHROW(load("disc { radius = 3 }\nprint { shell = true, scale = 1, flat_base = 500 }\n"));
  CHECK_NOTHROW(
      load("disc { radius = 3 }\nvenation {}\npetiole {}\nprint { size = 20, shell_thickness = 30 }\n"));  // no shell
}

TEST_CASE("print formats are case-blind", "[script]") {
  const auto cfg = load("disc { radius = 3 }\nprint { shell = true, veins = false, formats = \"STL, Obj\" }\n");
  REQUIRE(cfg.print);
  CHECK(cfg.print->formats == std::vector<std::string>{"stl", "obj"});
}

TEST_CASE("an enormous error message is cut to a few thousand bytes, its start and its end", "[script]") {
  // "test/leaf.lua:1: " (17 bytes), a million bytes of "ab", and "the end": the first 3,000 and the last
  // 1,000 bytes stay (audit: the reason at the end of a nested coroutine's error was the part cut)
  const std::string e = load_error("error(string.rep('ab', 500000) .. 'the end')\n");
  CHECK(e.rfind("test/leaf.lua:1: abab", 0) == 0);
  const std::string middle = "... (996024 bytes of the message left out) ...";
  REQUIRE(e.size() == 3000 + middle.size() + 1000);
  CHECK(e.substr(3000, middle.size()) == middle);
  CHECK(e.substr(17, 2983).find_first_not_of("ab") == std::string::npos);
  CHECK(e.substr(e.size() - 7) == "the end");
  CHECK(e.substr(e.size() - 1000, 993).find_first_not_of("ab") == std::string::npos);
}

TEST_CASE("a print with nothing to print is named where it was asked for", "[script]") {
  CHECK_THAT(load_error("disc { radius = 2 }\nvenation {}\nprint { veins = false }\n"),
             Contains("test/leaf.lua:3: print{...} with veins = false needs shell = true"));
  // by a --set: the --set is named, not the script's print{} line
  CHECK_THAT(load_error("disc { radius = 2 }\nvenation {}\nprint {}\n", {{"print.veins", "false"}}),
             Contains("--set print.veins=false: print{...} with veins = false needs shell = true"));
}
