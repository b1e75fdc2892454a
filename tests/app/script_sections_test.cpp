// Tests of app/script_sections.cpp: print sizes.
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

TEST_CASE("a script's missing file is said once, where it was looked for, with a name in another case", "[script]") {
  // (a walkthrough: "mesh: mesh './meshes/Rock.obj' does not exist" beside rock.obj, and file = "" read the folder)
  TempDir t("script-missing-file");
  const std::string dir = t.path.string();
  t.write("rock.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  CHECK(load_error("disc { radius = 2 }\nmesh { file = '" + dir + "/Rock.obj' }\n") ==
        "test/leaf.lua:2: mesh.file: '" + dir +
            "/Rock.obj' does not exist; there is 'rock.obj' (names are "
            "case-sensitive)");
  CHECK(load_error("disc { radius = 2 }\nmesh { file = 'meshes/rock.obj' }\n") ==
        "test/leaf.lua:2: mesh.file: 'meshes/rock.obj' does not exist (read from the script's folder: "
        "test/meshes/rock.obj)");
  CHECK_THAT(load_error("disc { radius = 2 }\nmesh { file = '~/rock.obj' }\n"),
             Contains("mesh.file: '~/rock.obj' does not exist ('~' is not expanded in a script"));
  CHECK_THAT(load_error("disc { radius = 2 }\nmesh { file = '' }\n"),
             Contains("test/leaf.lua:2: mesh.file is empty: give the file's path"));
  CHECK_THAT(load_error("volume { file = '" + dir + "/ROCK.obj', seeds = {{0, 0, 0}} }\n"),
             Contains("test/leaf.lua:1: volume.file: '" + dir + "/ROCK.obj' does not exist; there is 'rock.obj'"));
  CHECK_THAT(load_error("leaf { file = 'outline.svg' }\ncolonisation {}\n"),
             Contains("test/leaf.lua:1: leaf.file: 'outline.svg' does not exist (read from the script's folder"));
}
