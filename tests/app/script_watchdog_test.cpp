// Tests of the script watchdog (app/script_watchdog.h) through the cellform binary: a script stuck inside
// one Lua library call is stopped; loops of shorter calls, rule calls, Ctrl-Z and callbacks are told apart.
#include <signal.h>
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("a rule stuck in one library call leaves the folder as a rule error does", "[cli][signal][script]") {
  TempDir t("cli-stuck-folder");
  const auto script =
      t.write("grow.lua",
              "local P = params { hang = false }\n"
              "run { steps = 30, seed = 1 }\n"
              "output { checkpoint_every = 5, checkpoint_seconds = 0, every = 5 }\n"
              "division { min_age = 2, max_cells = 5000, rule = function(cell)\n"
              "  if P.hang and cell.step > 12 then local s = string.rep('a', 40)\n"
              "    return string.find(s, string.rep('a?', 40) .. string.rep('a', 40) .. 'b') ~= nil end\n"
              "  return cell.age > 3 end }\n"
              "disc { radius = 4 }\n");
  const fs::path out = t.path / "o", log = t.path / "err.txt";
  pid_t pid = spawn_cellform({"run", script.string(), "--out", out.string(), "--quiet"});
  REQUIRE(pid > 0);
  REQUIRE(exit_within(pid, 60) == 0);
  REQUIRE(fs::exists(out / "frames" / "cells_000030.ply"));
  pid = spawn_cellform_logged(
      {"run", script.string(), "--out", out.string(), "--quiet", "--set", "hang=true", "--lua-seconds", "1"}, log);
  REQUIRE(pid > 0);
  CHECK(exit_within(pid, 30) == 2);
  const std::string said = slurp(log);
  CHECK_THAT(said, Contains("--lua-seconds") && Contains("(in division.rule at step 1") && Contains(" for cell ") &&
                       Contains("the last checkpoint is " + (out / "checkpoint.cfck").string()) &&
                       Contains("cellform resume"));
  // the first run's outputs are gone, the second's frames up to its checkpoint (step 10) and run.json stay
  const std::string run = slurp(out / "run.json");
  CHECK_THAT(run, Contains("\"status\": \"failed\"") && Contains("\"completed\": 10") && Contains("--lua-seconds"));
  CHECK_FALSE(fs::exists(out / "cells.ply"));
  CHECK(fs::exists(out / "frames" / "cells_000010.ply"));
  CHECK_FALSE(fs::exists(out / "frames" / "cells_000015.ply"));
  for (const auto& e : fs::directory_iterator(out)) CHECK(e.path().filename().string().rfind(".partial", 0) != 0);
}

TEST_CASE("a sheet rule stuck in one library call leaves a colonisation run's folder as a rule error does",
          "[cli][signal][script][colonisation]") {
  TempDir t("cli-stuck-sheet");
  const auto script =
      t.write("sheet.lua",
              "local P = params { hang = false }\n"
              "run { steps = 30, seed = 1 }\n"
              "output { checkpoint_every = 3, checkpoint_seconds = 0 }\n"
              "division { min_age = 2, max_cells = 400, rule = function(cell)\n"
              "  if P.hang and cell.step > 7 then local s = string.rep('a', 40)\n"
              "    return string.find(s, string.rep('a?', 40) .. string.rep('a', 40) .. 'b') ~= nil end\n"
              "  return cell.age > 3 end }\n"
              "disc { radius = 4 }\n"
              "petiole { at = {0, -4, 0} }\n"
              "surface { cells = true }\n"
              "colonisation { kill_distance = 1, birth_distance = 2, darts = 20000 }\n");
  const fs::path out = t.path / "o", log = t.path / "err.txt";
  pid_t pid = spawn_cellform({"run", script.string(), "--out", out.string(), "--quiet"});
  REQUIRE(pid > 0);
  REQUIRE(exit_within(pid, 60) == 0);
  REQUIRE(fs::exists(out / "veins.ply"));
  pid = spawn_cellform_logged(
      {"run", script.string(), "--out", out.string(), "--quiet", "--set", "hang=true", "--lua-seconds", "1"}, log);
  REQUIRE(pid > 0);
  CHECK(exit_within(pid, 30) == 2);
  const std::string said = slurp(log);
  CHECK_THAT(said, Contains("--lua-seconds") && Contains("(in step 8 of the cell sheet)") &&
                       Contains("the last checkpoint is " + (out / "checkpoint.cfck").string()) &&
                       Contains("taken while the sheet grew at step 6") && Contains("cellform resume"));
  // the first run's outputs are gone; run.json says this one failed while the sheet grew
  const std::string run = slurp(out / "run.json");
  CHECK_THAT(run, Contains("\"status\": \"failed\"") && Contains("\"sheet_completed\": 6") &&
                      Contains("\"sheet_failed\": 8") && Contains("--lua-seconds"));
  CHECK_FALSE(fs::exists(out / "veins.ply"));
  for (const auto& e : fs::directory_iterator(out)) CHECK(e.path().filename().string().rfind(".partial", 0) != 0);
  // and the corrected script goes on from that checkpoint (the run's --set hang=true goes on too)
  std::string fixed = slurp(script);
  fixed.replace(fixed.find("P.hang and"), 10, "false and");
  const auto r =
      cli({"resume", (out / "checkpoint.cfck").string(), "--script", t.write("fixed.lua", fixed).string(), "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK(fs::exists(out / "veins.ply"));
}

TEST_CASE("a script stuck inside one library call is stopped by its time limit, or soon after a Ctrl-C",
          "[cli][signal][script]") {
  TempDir t("cli-stuck");
  // a pattern that backtracks through 2^40 ways: one call of string.find, out of reach of the budget's hook
  const auto script = t.write("stuck.lua",
                              "local s = string.rep('a', 40)\n"
                              "string.find(s, string.rep('a?', 40) .. string.rep('a', 40) .. 'b')\n"
                              "disc { radius = 2 }\n");
  const fs::path out = t.path / "o", log = t.path / "err.txt";
  pid_t pid = spawn_cellform_logged({"run", script.string(), "--out", out.string(), "--lua-seconds", "1"}, log);
  REQUIRE(pid > 0);
  CHECK(exit_within(pid, 20) == 2);
  CHECK_THAT(slurp(log),
             Contains("stuck.lua") && Contains("one call of a Lua library function") && Contains("--lua-seconds"));
  CHECK_FALSE(fs::exists(out));
  // the default limit (60 s) is not waited for after a Ctrl-C
  pid = spawn_cellform_logged({"run", script.string(), "--out", out.string()}, log);
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(pid, SIGINT);
  CHECK(exit_within(pid, 20) == 130);
  CHECK_THAT(slurp(log), Contains("cannot stop cleanly"));
  // a rule function stuck the same way in a run
  const auto rule =
      t.write("rule.lua",
              "disc { radius = 2 }\n"
              "division { rule = function(cell) local s = string.rep('a', 40)\n"
              "  return string.find(s, string.rep('a?', 40) .. string.rep('a', 40) .. 'b') ~= nil end }\n");
  pid = spawn_cellform_logged({"run", rule.string(), "--out", out.string(), "--lua-seconds", "1"}, log);
  REQUIRE(pid > 0);
  CHECK(exit_within(pid, 20) == 2);
  CHECK_THAT(slurp(log), Contains("rule.lua") && Contains("--lua-seconds"));
  CHECK_FALSE(fs::exists(out / "cells.ply"));
  // and stopped by a Ctrl-C: the message names the rule too
  pid = spawn_cellform_logged({"run", rule.string(), "--out", out.string()}, log);
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  kill(pid, SIGINT);
  CHECK(exit_within(pid, 20) == 130);
  CHECK_THAT(slurp(log), Contains("cannot stop cleanly (in division.rule at step 5 for cell ") &&
                             Contains("rule.lua is inside one call"));
  // one call that calls back (gsub's replacement) is one call: its callbacks do not restart the clock, and a
  // Ctrl-C acts at them
  const auto callback = t.write("callback.lua",
                                "local s = string.rep(string.rep('a', 22) .. 'cb', 40)\n"
                                "string.gsub(s, 'a-a-a-a-a-a-a-a-a-b', string.len)\n"
                                "disc { radius = 2 }\n");
  pid = spawn_cellform({"run", callback.string(), "--out", out.string(), "--quiet", "--lua-seconds", "1"});
  REQUIRE(pid > 0);
  CHECK(exit_within(pid, 20) == 2);
  pid = spawn_cellform({"run", callback.string(), "--out", out.string(), "--quiet"});
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(pid, SIGINT);
  CHECK(exit_within(pid, 20) == 130);
  // the limit is the script's CPU time: a run stopped (Ctrl-Z) for longer is not killed when it continues
  pid = spawn_cellform({"run", script.string(), "--out", out.string(), "--quiet", "--lua-seconds", "2"});
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(pid, SIGSTOP);
  std::this_thread::sleep_for(std::chrono::milliseconds(3000));
  kill(pid, SIGCONT);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  CHECK(waitpid(pid, nullptr, WNOHANG) == 0);  // still running
  CHECK(exit_within(pid, 20) == 2);
  // a stop the script escapes (a looping xpcall handler runs with Lua's hook off, and each fresh coroutine
  // looks like progress) is ended after 2 s: it ran until killed
  const auto escape = t.write("escape.lua",
                              "xpcall(function() while true do end end, function(e)\n"
                              "  while true do coroutine.resume(coroutine.create(function() local x = 1 end)) end\n"
                              "end)\n");
  pid = spawn_cellform_logged({"run", escape.string(), "--out", out.string(), "--lua-instructions", "1000000"}, log);
  REQUIRE(pid > 0);
  CHECK(exit_within(pid, 20) == 2);
  CHECK_THAT(slurp(log), Contains("did not stop when it was stopped"));
  // such a handler that prints in a loop (each print looked like a library call that ended: it ran 11 minutes
  // and wrote 14 GB, review) ends at its first print, in a rule too
  const auto printing =
      t.write("printing.lua",
              "disc { radius = 2 }\n"
              "division { rule = function(c)\n"
              "  xpcall(function() while true do end end, function(e) while true do print('x') end end)\n"
              "  return false\n"
              "end }\n");
  pid = spawn_cellform_logged({"run", printing.string(), "--out", out.string()}, log);
  REQUIRE(pid > 0);
  CHECK(exit_within(pid, 20) == 2);
  CHECK_THAT(slurp(log), Contains("printing.lua:3: a rule function ran more than 10000000 instructions"));
  CHECK(fs::file_size(log) < 10000);
  // a Ctrl-C during a loop of short library calls (few instructions between them) acts within a second
  const auto loop = t.write("loop.lua",
                            "local s = ('a'):rep(150)\n"
                            "for i = 1, 1000 do local r = s:find('[^Y]-[^Y]-[^Y]-X') end\n");
  pid = spawn_cellform({"run", loop.string(), "--out", out.string(), "--quiet"});
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(pid, SIGINT);
  CHECK(exit_within(pid, 5) == 130);
  // many short library calls are not one long one: a loop of 40 ms calls runs its 2 s with a limit of 1 s
  const auto slow = t.write("slow.lua",
                            "local s = string.rep('a', 2e7)\n"
                            "local n = 0\n"
                            "for i = 1, 50 do n = n + #s:upper() end\n"
                            "disc { radius = 2 }\nrun { steps = 1 }\n");
  pid = spawn_cellform({"run", slow.string(), "--out", (t.path / "slow").string(), "--quiet", "--lua-seconds", "1"});
  REQUIRE(pid > 0);
  CHECK(exit_within(pid, 60) == 0);
  // nor do rule calls that fill a step; a Ctrl-C there ends the run after the step, with its outputs
  const auto busy = t.write("busy.lua",
                            "local S = string.rep('a', 1e7)\n"
                            "disc { radius = 3 }\nrun { steps = 100000 }\n"
                            "division { rule = function(c) return #S:upper() < 0 end }\n");
  pid = spawn_cellform({"run", busy.string(), "--out", (t.path / "busy").string(), "--quiet", "--lua-seconds", "1"});
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(3000));
  kill(pid, SIGINT);
  CHECK(exit_within(pid, 60) == 130);
  CHECK(fs::exists(t.path / "busy" / "cells.ply"));
  CHECK(fs::exists(t.path / "busy" / "checkpoint.cfck"));
  // the folder stays usable: the next run there clears what the stopped one left
  const auto quick = t.write("quick.lua", "disc { radius = 2 }\nrun { steps = 2 }\n");
  CHECK(cli({"run", quick.string(), "--out", out.string(), "--quiet"}).code == 0);
  int hidden = 0;
  for (const auto& e : fs::directory_iterator(out)) hidden += e.path().filename().string()[0] == '.';
  CHECK(hidden == 0);
}
