// Tests of app/script_sections.cpp: the memory limit of the run's control groups; print sizes.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "app/script_host.h"
#include "tests/app/script_test_util.h"
#include "tests/app/test_util.h"

using Catch::Matchers::Contains;
using cellform::app::control_group_memory_limit;
using cellform::test::load;
using cellform::test::load_error;
using cellform::test::TempDir;

TEST_CASE("the memory limit is the lowest of the run's control groups, from its own up to the root", "[script]") {
  TempDir t("cgroup-limit");
  auto put = [&](const std::string& name, const std::string& text) {
    std::filesystem::create_directories((t.path / name).parent_path());
    t.write(name, text);
  };
  // v2: the job's group (unlimited) inside a user slice with 4 GB, inside the root
  put("v2/user.slice/memory.max", "4000000000\n");
  put("v2/user.slice/job/memory.max", "max\n");
  std::istringstream v2("0::/user.slice/job\n");
  CHECK(control_group_memory_limit(v2, t.path / "v2") == 4e9);
  put("v2/user.slice/job/memory.max", "2500000000\n");  // the job's own, lower
  std::istringstream v2b("0::/user.slice/job\n");
  CHECK(control_group_memory_limit(v2b, t.path / "v2") == 2.5e9);
  // v1: only the memory controller's line counts, under memory/; the unlimited value is just very large
  put("v1/memory/docker/abc/memory.limit_in_bytes", "1000000000\n");
  put("v1/memory/memory.limit_in_bytes", "9223372036854771712\n");
  // a group named by another controller's line, with a lower limit in the memory hierarchy: not the run's
  put("v1/memory/other/memory.limit_in_bytes", "5\n");
  std::istringstream v1("12:cpu,cpuacct:/other\n11:memory:/docker/abc\n");
  CHECK(control_group_memory_limit(v1, t.path / "v1") == 1e9);
  // no limit anywhere, a missing file, a line that is no group
  std::istringstream none("0::/\n");
  CHECK(std::isinf(control_group_memory_limit(none, t.path / "v2")));
  std::istringstream junk("garbage\n0::/nowhere/at/all\n");
  CHECK(std::isinf(control_group_memory_limit(junk, t.path / "v2")));
}

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
