// Tests of app/memory.cpp: the memory limits a print is checked against.
#include "app/memory.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "tests/app/test_util.h"

using Catch::Matchers::Contains;
using cellform::app::control_group_memory_limit;
using cellform::app::memory_headroom;
using cellform::app::tightest_headroom;
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

TEST_CASE("the headroom is the tightest of the address-space limit, the container's and the machine's", "[memory]") {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  CHECK(std::isinf(tightest_headroom(inf, 1e9, inf, 5e8, nan).bytes));  // nothing known: no bound
  const auto as = tightest_headroom(2.5e9, 1e9, inf, 5e8, 20e9);        // ulimit -v 2.5 GB, 1 GB mapped
  CHECK(as.bytes == 1.5e9);
  CHECK_THAT(as.name, Contains("ulimit -v"));
  const auto group = tightest_headroom(inf, 1e9, 4e9, 5e8, 20e9);  // the container's limit less what is resident
  CHECK(group.bytes == 3.5e9);
  CHECK_THAT(group.name, Contains("container"));
  const auto machine = tightest_headroom(inf, nan, 64e9, nan, 3e9);
  CHECK(machine.bytes == 3e9);
  CHECK_THAT(machine.name, Contains("machine"));
  CHECK(tightest_headroom(1e9, 2e9, inf, 0, inf).bytes == 0);  // over the limit already: nothing left, not negative
}

TEST_CASE("this process's headroom is positive, and named where it is bounded", "[memory]") {
  const auto room = memory_headroom();
  CHECK(room.bytes > 0);
  if (std::isfinite(room.bytes)) CHECK_FALSE(room.name.empty());
}
