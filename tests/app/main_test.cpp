// Tests of how the cellform process ends on signals (app/main.cpp, app::exit_process).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstring>
#include <nlohmann/json.hpp>
#include <thread>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {
const char* const kLong = "division { trigger = 'none' }\nrun { steps = 1000000 }\ndisc { radius = 20 }\n";
}  // namespace

TEST_CASE("one stop sent twice at once by one process (GNU timeout: to the process and its group) is one Ctrl-C",
          "[cli][signal]") {
  TempDir t("cli-timeout");
  const auto script = t.write("long.lua", kLong);
  for (const int sig : {SIGINT, SIGTERM}) {
    INFO(strsignal(sig));
    const std::string n = std::to_string(sig);  // (not "o" + std::to_string(sig): a false GCC 12 warning)
    const fs::path out = t.path / ("o" + n), log = t.path / ("err" + n);
    const pid_t pid =
        spawn_cellform_logged({"run", script.string(), "--out", out.string(), "--quiet", "--lua-memory", "100"}, log);
    REQUIRE(pid > 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    kill(pid, sig);
    // apart, so the second is not merged with the first while pending (timeout's two come microseconds apart)
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    kill(pid, sig);
    CHECK(wait_exit(pid) == 130);
    const std::string said = slurp(log);
    CHECK_THAT(said, !Contains("quit:"));
    const std::string stop = "the steps stop after the current one";
    CHECK(said.find(stop) != std::string::npos);
    CHECK(said.find(stop) == said.rfind(stop));  // said once: one stop
    // in a log no progress line is half drawn: the message takes no blank line before it
    CHECK(said.rfind("cellform: ", 0) == 0);
    CHECK_THAT(said, !Contains("\n\n"));
    // the command to go on gives the script limit again (a checkpoint does not keep it)
    CHECK_THAT(said, Contains("continue with: cellform resume ") && Contains(" --lua-memory 100\n"));
    CHECK(fs::exists(out / "checkpoint.cfck"));
    CHECK(nlohmann::json::parse(slurp(out / "run.json"))["status"] == "interrupted");
  }
}

TEST_CASE("a Ctrl-C stops a shell loop of runs, not only the run it came in", "[cli][signal]") {
  // A terminal's Ctrl-C reaches the shell and the run (one process group). bash goes on with the next
  // run if that one merely exited, even with 130; only a run that ended by SIGINT stops the loop.
  TempDir t("cli-loop");
  t.write("long.lua", kLong);
  const std::string exe = std::string(CELLFORM_BINARY_DIR) + "/bin/cellform";
  const pid_t shell = fork();
  if (shell == 0) {
    setsid();  // its own process group, as a terminal's foreground job
    if (chdir(t.path.c_str()) != 0) _exit(98);
    execl("/bin/bash", "bash", "-c",
          "for i in 1 2; do \"$0\" run long.lua --out o$i --quiet 2>/dev/null; echo \"$i $?\" >> after; done; "
          "echo went-on >> after",
          exe.c_str(), static_cast<char*>(nullptr));
    _exit(99);
  }
  REQUIRE(shell > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  killpg(shell, SIGINT);
  const int status = exit_within(shell, 60);
  if (status == -2) killpg(shell, SIGKILL);  // the loop went on with a run of a million steps
  CHECK(status == 130);                      // bash itself ended by SIGINT
  CHECK(fs::exists(t.path / "o1" / "checkpoint.cfck"));
  CHECK(nlohmann::json::parse(slurp(t.path / "o1" / "run.json"))["status"] == "interrupted");
  CHECK_FALSE(fs::exists(t.path / "o2"));
  CHECK_FALSE(fs::exists(t.path / "after"));
}

TEST_CASE("SIGTERM stops a run as Ctrl-C does and exits 130", "[cli][signal]") {
  TempDir t("cli-term");
  const auto script = t.write("long.lua", kLong);
  const fs::path out = t.path / "o";
  const fs::path log = t.path / "err.txt";
  const pid_t pid = spawn_cellform_logged({"run", script.string(), "--out", out.string(), "--quiet"}, log);
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  kill(pid, SIGTERM);
  int signal = -1;
  CHECK(wait_exit(pid, &signal) == 130);
  CHECK(signal == 0);  // an exit: a SIGTERM reaches this process alone, not the shell
  // a run without print{} is not told about a printable solid
  CHECK_THAT(slurp(log), Catch::Matchers::Contains("the steps stop after the current one") &&
                             !Catch::Matchers::Contains("printable"));
  CHECK(fs::exists(out / "checkpoint.cfck"));
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["status"] == "interrupted");
}

TEST_CASE("a second Ctrl-C quits at once, says what the folder keeps, and the next run clears what it left",
          "[cli][signal]") {
  TempDir t("cli-int-twice");
  const auto script =
      t.write("long.lua", "division { trigger = 'none' }\nrun { steps = 1000000 }\ndisc { radius = 80 }\n");
  const fs::path out = t.path / "o", log = t.path / "err.txt";
  const pid_t pid =
      spawn_cellform_logged({"run", script.string(), "--out", out.string(), "--quiet", "--threads", "1"}, log);
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  kill(pid, SIGINT);
  std::this_thread::sleep_for(std::chrono::milliseconds(5));  // delivered apart, within the step and the writing
  kill_from_another_process(pid, SIGINT);                     // (a second from this process would be the same stop)
  CHECK(wait_exit(pid) == 130);
  CHECK_THAT(slurp(log), Contains("quit: the output folder keeps its last checkpoint, if one was written"));
  CHECK_FALSE(fs::exists(out / "run.json"));
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "2"}).code == 0);
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string name = e.path().filename().string();
    CHECK(name.find(".partial") == std::string::npos);
    CHECK(name.find(".tmp-") == std::string::npos);
  }
}

TEST_CASE("a first Ctrl-C during the print says it skips the print, and a second quits", "[cli][signal]") {
  // (a walkthrough: the message said the steps stop, and that a second Ctrl-C would skip the print it skipped)
  TempDir t("cli-int-print");
  const auto script = t.write("shell.lua", slow_print_script("3"));
  const fs::path out = t.path / "o", log = t.path / "err.txt";
  const pid_t pid = spawn_cellform_logged({"run", script.string(), "--out", out.string()}, log);
  REQUIRE(pid > 0);
  REQUIRE(wait_for_text(log, "thickening", 30));  // the print has started
  kill(pid, SIGINT);
  const int code = wait_exit(pid);
  INFO(slurp(log));
  CHECK(code == 130);
  CHECK_THAT(slurp(log),
             Contains("interrupted during the print: the printable solid is skipped") && !Contains("the steps stop"));
  CHECK(fs::exists(out / "cells.ply"));
  CHECK_FALSE(fs::exists(out / "printable.stl"));
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["print"]["error"] == "interrupted");
}
