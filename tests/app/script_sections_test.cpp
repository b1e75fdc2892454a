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
