// Tests of what a run draws on a terminal (app/progress.cpp, app/run.cpp, app/run_sheet.cpp): the binary
// runs on a pseudo-terminal, as in a user's shell.
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <cerrno>
#include <string>
#include <vector>

#include "test_util.h"

using cellform::test::TempDir;

namespace {

/// Runs the built cellform with `args` on a new pseudo-terminal; returns all it wrote there.
std::string run_on_terminal(const std::vector<std::string>& args) {
  std::vector<std::string> storage;
  std::vector<char*> argv = cellform::test::cellform_argv(args, storage);
  int master = -1;
  const pid_t pid = forkpty(&master, nullptr, nullptr, nullptr);
  REQUIRE(pid >= 0);
  if (pid == 0) {
    execv(argv[0], argv.data());
    _exit(99);
  }
  std::string text;
  char buf[4096];
  for (;;) {
    const ssize_t got = read(master, buf, sizeof buf);
    if (got > 0)
      text.append(buf, static_cast<std::size_t>(got));
    else if (got < 0 && errno == EINTR)
      continue;
    else
      break;  // EIO: the child has gone and the terminal is closed
  }
  close(master);
  int status = 0;
  waitpid(pid, &status, 0);
  CHECK(WIFEXITED(status));
  return text;
}

// Steps 1 to 3 keep the rule busy for a while, so that the bar is drawn (every 0.1 s) before step 5 prints.
const char* kBusyThenPrint =
    "run { steps = 6 }\n"
    "disc { radius = 3 }\n"
    "petiole { at = {0, 0, 0} }\n"
    "division { min_age = 0, rule = function(cell)\n"
    "  if cell.step <= 3 then local x = 0 for i = 1, 1000000 do x = x + i end end\n"
    "  if cell.step == 5 and cell.id == 1 then print('hello at step 5') end\n"
    "  return false end }\n";

/// Whether `text` draws the bar and then has the script's line at the start of a line of its own.
void check_own_line(const std::string& text) {
  const std::size_t line = text.find("script: hello at step 5");
  REQUIRE(line != std::string::npos);
  CHECK(text.rfind("\r[", line) != std::string::npos);  // a bar was drawn before it
  REQUIRE(line > 0);
  CHECK(text[line - 1] == '\n');  // on a terminal "\r\n"
}

}  // namespace

TEST_CASE("a script's print() under the terminal's progress bar starts a line of its own", "[cli]") {
  TempDir dir("terminal");
  SECTION("a cell run") {
    const auto script = dir.write("busy.lua", kBusyThenPrint);
    check_own_line(run_on_terminal({"run", script.string(), "--out", (dir.path / "o").string(), "--threads", "1"}));
  }
  SECTION("the sheet of surface{cells = true}") {
    const auto script =
        dir.write("busy_sheet.lua", std::string(kBusyThenPrint) +
                                        "surface { cells = true }\n"
                                        "colonisation { birth_distance = 1, kill_distance = 0.5, darts = 1e6 }\n");
    check_own_line(run_on_terminal({"run", script.string(), "--out", (dir.path / "o").string(), "--threads", "1"}));
  }
}
