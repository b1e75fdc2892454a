// Tests of app/output_folder.cpp through the command line: staging, the commit, what a killed or failed run leaves.

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <climits>
#include <set>
#include <thread>

#include "app/run_internal.h"
#include "core/chunk_file.h"
#include "core/errors.h"
#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("a commit stopped between two runs' files leaves no run.json", "[cli]") {
  TempDir t("cli-commit");
  const fs::path dir = t.path / "out", staging = t.path / "staging";
  fs::create_directories(dir / "b.txt" / "inside");  // b.txt cannot be replaced: the move fails there
  std::ofstream(dir / "a.txt") << "old a";
  std::ofstream(dir / "run.json") << R"({"outputs": ["a.txt", "b.txt", "run.json"]})";
  fs::create_directories(staging);
  for (const char* n : {"run.json", "a.txt", "b.txt"}) std::ofstream(staging / n) << "new " << n;
  using cellform::app::commit_outputs;
  // b.txt is checked before anything moves: the earlier outputs stay as they were, run.json with them
  CHECK_THROWS_WITH(commit_outputs(staging, dir, {"run.json", "a.txt", "b.txt"}),
                    Contains("b.txt' is not a file but a folder; move that away, then resume"));
  CHECK(slurp(dir / "a.txt") == "old a");
  CHECK(fs::exists(dir / "run.json"));
  // a named pipe in an output's place is said as such (it read "(a folder?)")
  REQUIRE((fs::create_directories(t.path / "pipe") && ::mkfifo((t.path / "pipe" / "a.txt").c_str(), 0600) == 0));
  CHECK_THROWS_WITH(commit_outputs(staging, t.path / "pipe", {"a.txt"}), Contains("not a file but a named pipe"));
  // a move that fails all the same (here: its path passes the system's limit, the shorter ones do not)
  // leaves no run.json: the old one would not describe the mix
  fs::path deep = t.path / "deep";
  while (deep.string().size() < PATH_MAX - 300) deep /= std::string(200, 'd');
  deep /= std::string(PATH_MAX - 51 - deep.string().size(), 'e');  // deep/run.json fits, deep/bbb...b.txt not
  fs::create_directories(deep);
  const std::string long_name = std::string(60, 'b') + ".txt";
  std::ofstream(deep / "a") << "old a";
  std::ofstream(deep / "old.obj") << "old obj";
  std::ofstream(deep / "run.json") << R"({"program": "cellform", "outputs": ["a", "old.obj", "run.json"]})";
  for (const std::string& n : {std::string("a"), long_name}) std::ofstream(staging / n) << "new " << n;
  CHECK_THROWS_AS(commit_outputs(staging, deep, {"run.json", "a", long_name}), cellform::core::FileError);
  CHECK(slurp(deep / "a") == "new a");         // moved before the failure
  CHECK_FALSE(fs::exists(deep / "run.json"));  // the old one does not describe the mix
  // but both runs' outputs are listed beside them, and the next commit there cleans up after both (an
  // export audit: a run in a folder without run.json left the older run's printable.obj beside its STL)
  const std::string manifest = slurp(deep / cellform::app::kOutputsManifest);
  CHECK_THAT(manifest, Contains("old.obj\n") && Contains("a\n") && Contains(long_name + "\n"));
  fs::remove(staging / long_name);
  std::ofstream(staging / "run.json") << "new run.json";
  REQUIRE_NOTHROW(commit_outputs(staging, deep, {"run.json"}));
  CHECK(slurp(deep / "run.json") == "new run.json");
  CHECK_FALSE(fs::exists(deep / "old.obj"));
  CHECK_FALSE(fs::exists(deep / "a"));
  CHECK_FALSE(fs::exists(deep / cellform::app::kOutputsManifest));
  // Without a run.json the frames it lists stay (review: a resume of the killed run's checkpoint takes up its
  // frames from before the checkpoint, which no run.json lists, and they were deleted); other outputs go
  const fs::path w = t.path / "w", m = w / cellform::app::kOutputsManifest;
  auto commit_run_json = [&](const std::string& text) {
    fs::create_directories(staging);
    std::ofstream(staging / "run.json") << text;
    REQUIRE_NOTHROW(commit_outputs(staging, w, {"run.json"}));
    CHECK(slurp(w / "run.json") == text);
  };
  fs::create_directories(w / "frames");
  std::ofstream(w / "frames" / "cells_000010.ply") << "frame";
  std::ofstream(w / "old.obj") << "old obj";
  std::ofstream(m) << "frames/cells_000010.ply\nold.obj\nrun.json\n";
  commit_run_json("newer run.json");
  CHECK(fs::exists(w / "frames" / "cells_000010.ply"));
  CHECK_FALSE(fs::exists(w / "old.obj"));
  CHECK_FALSE(fs::exists(m));
  // a list beside a cellform run.json (a kill after the new run.json went in) is read too, frames and all
  std::ofstream(w / "run.json") << R"({"program": "cellform", "outputs": ["run.json"]})";
  std::ofstream(m) << "frames/cells_000010.ply\n";
  commit_run_json("newest run.json");
  CHECK_FALSE(fs::exists(w / "frames" / "cells_000010.ply"));
  // a link in the list's place is not followed, and a folder there does not stop the commit
  std::ofstream(w / "mine.txt") << "the user's";
  std::ofstream(t.path / "elsewhere") << "mine.txt\n";
  fs::create_symlink(t.path / "elsewhere", m);
  commit_run_json("run.json again");
  CHECK(slurp(w / "mine.txt") == "the user's");
  CHECK(slurp(t.path / "elsewhere") == "mine.txt\n");  // (the commit's own list replaced the link, then went)
  CHECK_FALSE(fs::exists(fs::symlink_status(m)));
  fs::create_directories(m);
  commit_run_json("run.json once more");
  fs::create_directories(staging);
  for (const char* n : {"run.json", "a.txt", "b.txt"}) std::ofstream(staging / n) << "new " << n;
  // a whole commit moves run.json too, listed in any position
  fs::remove_all(dir / "b.txt");
  REQUIRE_NOTHROW(commit_outputs(staging, dir, {"run.json", "b.txt"}));
  CHECK(slurp(dir / "run.json") == "new run.json");
  CHECK(slurp(dir / "b.txt") == "new b.txt");
}

TEST_CASE("an unwritable output location fails clearly", "[cli]") {
  TempDir t("cli-unwritable");
  const auto script = t.write("small.lua", kSmall);
  const auto file = t.write("a-file", "x");
  auto r = cli({"run", script.string(), "--out", file.string(), "--quiet", "--steps", "2"});
  CHECK(r.code == 2);  // a usage error, said before the script is read
  CHECK_THAT(r.err, Contains("--out " + file.string() + " is a file, not a folder"));
  CHECK(slurp(file) == "x");
  // a file inside the path: the same mistake, refused by the system; also an input error
  r = cli({"run", script.string(), "--out", (file / "sub").string(), "--quiet", "--steps", "2"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("cannot write outputs") && Contains("cannot create directory"));
  CHECK(slurp(file) == "x");
  r = cli({"run", script.string(), "--out", "/proc/self/no-folder-here", "--quiet", "--steps", "2"});
  CHECK(r.code == 2);
  CHECK_FALSE(fs::exists("/proc/self/no-folder-here"));
  // a folder that exists but takes no file (/proc): an input error too, said of the folder given
  r = cli({"run", script.string(), "--out", "/proc", "--quiet", "--steps", "2"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("cannot write in '/proc'") && !Contains(".partial"));
  // a symbolic link to nothing is said as such (it was "File exists")
  fs::create_symlink(t.path / "nowhere", t.path / "dangling");
  r = cli({"run", script.string(), "--out", (t.path / "dangling").string(), "--quiet", "--steps", "2"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("dangling' is a symbolic link to '") && Contains("nowhere', which does not exist"));
  // a name too long for the file system, under folders the run had to make: those go again
  r = cli({"run", script.string(), "--out", (t.path / "newtop" / "mid" / std::string(300, 'x')).string(), "--quiet",
           "--steps", "2"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("cannot create directory"));
  CHECK_FALSE(fs::exists(t.path / "newtop"));
  // a folder named run.json in the output folder is said as such (it was "not valid JSON") and kept
  fs::create_directories(t.path / "o" / "run.json");
  r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet", "--steps", "2"});
  CHECK(r.code == 2);  // an input error: another folder, or that one moved away
  CHECK_THAT(r.err, Contains("run.json' is a folder where this run may write its run.json"));
  CHECK(fs::is_directory(t.path / "o" / "run.json"));
  CHECK_FALSE(fs::exists(t.path / "o" / "cells.ply"));
  // so is a file in the place of frames/ when frames are asked for: before the run, not after
  fs::create_directories(t.path / "o3");
  t.write("o3/frames", "a note\n");
  r = cli({"run", script.string(), "--out", (t.path / "o3").string(), "--quiet", "--steps", "2", "--set",
           "output.every=1"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("frames' is not a folder; output.every writes the frames into frames/"));
  CHECK_FALSE(fs::exists(t.path / "o3" / "checkpoint.cfck"));
  fs::create_directories(t.path / "o5");  // a link to nothing is no folder either
  fs::create_symlink(t.path / "nowhere", t.path / "o5" / "frames");
  r = cli({"run", script.string(), "--out", (t.path / "o5").string(), "--quiet", "--steps", "2", "--set",
           "output.every=1"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("frames' is not a folder"));
  for (const auto& e : fs::directory_iterator(t.path / "o3"))  // no staging folder is left
    CHECK(e.path().filename().string().rfind(".partial", 0) != 0);
  // a folder whose files' paths would be too long for the system (each name within its own limit)
  fs::path deep = t.path / "o4";
  while (deep.string().size() < PATH_MAX - 40) deep /= std::string(200, 'd');
  r = cli({"run", script.string(), "--out", deep.string(), "--quiet", "--steps", "2"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("path is too long"));
}

TEST_CASE(
    "a run removes the staging folders and checkpoint drafts of killed runs (with the folder locked, all), and only "
    "those",
    "[cli]") {
  TempDir t("cli-stale");
  const auto script = t.write("small.lua", kSmall);
  const fs::path out = t.path / "out";
  fs::create_directories(out / ".partial-999999999");  // no such process (beyond any pid_max)
  std::ofstream(out / ".partial-999999999" / "veins.ply") << "half";
  // a process with that id runs (a container gives ids again): but no run writes in a folder it cannot lock
  const fs::path live = out / (".partial-" + std::to_string(::getppid()));
  fs::create_directories(live);
  fs::create_directories(out / ".partial-notes");                               // not a run's
  std::ofstream(out / "checkpoint.cfck.tmp-999999999") << "half a checkpoint";  // a killed run's
  const fs::path live_tmp = out / ("checkpoint.cfck.tmp-" + std::to_string(::getppid()));
  std::ofstream(live_tmp) << "being written";
  // a run killed but not yet reaped by its parent (a zombie: kill(pid, 0) still succeeds) is gone too
  const pid_t zombie = ::fork();
  if (zombie == 0) ::_exit(0);
  REQUIRE(zombie > 0);
  siginfo_t info{};
  REQUIRE(::waitid(P_PID, static_cast<id_t>(zombie), &info, WEXITED | WNOWAIT) == 0);  // exited, not reaped
  REQUIRE(::kill(zombie, 0) == 0);
  const fs::path killed = out / (".partial-" + std::to_string(zombie));
  fs::create_directories(killed);
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--steps", "3", "--quiet"}).code == 0);
  ::waitpid(zombie, nullptr, 0);
  CHECK_FALSE(fs::exists(killed));
  CHECK_FALSE(fs::exists(out / ".partial-999999999"));
  CHECK_FALSE(fs::exists(out / "checkpoint.cfck.tmp-999999999"));
  CHECK_FALSE(fs::exists(live));
  CHECK_FALSE(fs::exists(live_tmp));
  CHECK(fs::exists(out / ".partial-notes"));
  CHECK(fs::exists(out / "cells.ply"));
}

TEST_CASE("a rule that fails in a step before any checkpoint leaves no empty output folder", "[cli]") {
  TempDir t("cli-rule-fails");
  const auto script = t.write("bad.lua",
                              "run { steps = 20 }\ndisc { radius = 3 }\npetiole { at = {0, -3, 0} }\n"
                              "venation { source = function(c) if c.step >= 5 then return nil end return 1 end }\n");
  const fs::path out = t.path / "o";
  const auto r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("bad.lua:4:") && Contains("step 5"));
  // a number out of range is written as the script would write it
  const auto negative =
      t.write("negative.lua",
              "run { steps = 20 }\ndisc { radius = 3 }\npetiole { at = {0, -3, 0} }\n"
              "venation { source = function(c) if c.step >= 3 then return -0.25 end return 1 end }\n");
  const auto n = cli({"run", negative.string(), "--out", (t.path / "n").string(), "--quiet"});
  CHECK(n.code == 2);
  CHECK_THAT(n.err,
             Contains("must return a number from 0 to 1e30 (as a constant source), got -0.25 (") && Contains("step 3"));
  // a rule that changes a knob of params{} stops after that step, as a failing rule does
  const auto knob = t.write("knob.lua",
                            "local P = params { n = 3 }\nrun { steps = 20 }\ndisc { radius = 3 }\n"
                            "division { rule = function(c) if c.step == 6 then P.n = 4 end return false end }\n");
  const auto k = cli({"run", knob.string(), "--out", (t.path / "k").string(), "--quiet"});
  CHECK(k.code == 2);
  CHECK_THAT(k.err,
             Contains("knob.lua:1: params: a rule function changed the knob n from 3 to 4 by the end of step 6"));
  CHECK_FALSE(fs::exists(t.path / "k"));
  CHECK_FALSE(fs::exists(out));
  // nor the folders it made to hold it
  CHECK(cli({"run", script.string(), "--out", (t.path / "nest" / "a" / "b").string(), "--quiet"}).code == 2);
  CHECK_FALSE(fs::exists(t.path / "nest"));
  CHECK(cli({"run", script.string(), "--out", (t.path / "nest" / "a" / "b").string() + "/", "--quiet"}).code == 2);
  CHECK_FALSE(fs::exists(t.path / "nest"));  // a trailing slash too
  // a folder that was there stays, with what it held
  fs::create_directories(out);
  std::ofstream(out / "notes.txt") << "mine";
  CHECK(cli({"run", script.string(), "--out", out.string(), "--quiet"}).code == 2);
  CHECK(slurp(out / "notes.txt") == "mine");
}

TEST_CASE("a folder whose run.json another program wrote is refused, and nothing in it is deleted", "[cli]") {
  TempDir t("cli-foreign");
  const auto script = t.write("small.lua", kSmall);
  const fs::path dir = t.path / "out", outside = t.path / "outside";
  fs::create_directories(dir);
  fs::create_directories(outside);
  t.write("out/notes.txt", "mine");
  t.write("outside/data.txt", "mine too");
  fs::create_directory_symlink("../outside", dir / "lnk");
  const std::string foreign = R"({"tool": "other", "outputs": ["notes.txt", "lnk/data.txt"]})";
  t.write("out/run.json", foreign);
  auto r = cli({"run", script.string(), "--out", dir.string(), "--quiet", "--steps", "2"});
  CHECK(r.code == 2);  // an input error, as the README's exit codes say
  CHECK_THAT(r.err, Contains("run.json' was not written by cellform"));
  CHECK(slurp(dir / "run.json") == foreign);
  CHECK(fs::exists(dir / "notes.txt"));
  CHECK(fs::exists(outside / "data.txt"));
  CHECK_FALSE(fs::exists(dir / "cells.ply"));
  t.write("out/run.json", "{\"program\": \"cellform\", \"outp");  // cut short: no program's whole file
  r = cli({"run", script.string(), "--out", dir.string(), "--quiet", "--steps", "2"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("run.json' is not valid JSON"));
  // cellform's own run.json that lists a file through a link (or outside frames/) deletes nothing there
  t.write("out/run.json", R"({"program": "cellform", "outputs": ["lnk/data.txt", "frames/../notes.txt", "x/y.ply"]})");
  fs::create_directories(dir / "x");
  t.write("out/x/y.ply", "kept");
  r = cli({"run", script.string(), "--out", dir.string(), "--quiet", "--steps", "2"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK(fs::exists(outside / "data.txt"));
  CHECK(fs::exists(dir / "notes.txt"));
  CHECK(fs::exists(dir / "x" / "y.ply"));
  CHECK(fs::exists(dir / "cells.ply"));
}

TEST_CASE("two runs never write into one folder at once", "[cli]") {
  TempDir t("cli-lock");
  const auto script = t.write("small.lua", kSmall);
  const fs::path dir = t.path / "out";
  fs::create_directories(dir);
  {
    const cellform::app::FolderLock held(dir);  // as a run in another process holds it
    const auto r = cli({"run", script.string(), "--out", dir.string(), "--quiet", "--steps", "2"});
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("another cellform run") && Contains("is writing to"));
    CHECK(fs::is_empty(dir));  // no staging folder, no outputs
    // a resume of that folder before the run wrote its checkpoint says that a run is writing there
    const auto resumed = cli({"resume", dir.string()});
    CHECK(resumed.code != 0);
    CHECK_THAT(resumed.err, Contains("is a folder with no checkpoint.cfck in it") &&
                                Contains("; another cellform run") && Contains("is writing to"));
  }
  CHECK(cli({"run", script.string(), "--out", dir.string(), "--quiet", "--steps", "2"}).code == 0);  // released
}

TEST_CASE("a folder where a run writes one of its files is refused before the first step", "[cli]") {
  // found only at the end, it cost the whole run (the checkpoint was kept, to resume from once it was moved)
  TempDir t("cli-commit-fails");
  const auto script = t.write("small.lua", kSmall);
  for (const char* name : {"cells.ply", "cells.obj"}) {
    const fs::path dir = t.path / (std::string("out-") + name);
    fs::create_directories(dir / name / "inside");
    const auto r = cli({"run", script.string(), "--out", dir.string(), "--quiet", "--steps", "3"});
    CHECK(r.code == 2);
    CHECK_THAT(r.err,
               Contains(std::string(name) + "' is a folder where this run may write its " + name) && !Contains("step"));
    CHECK(fs::exists(dir / name / "inside"));  // left as it was
    CHECK(!fs::exists(dir / "run.json"));
  }
  // and so for space colonisation
  const auto veins = t.write("veins.lua", "leaf {}\ncolonisation { initial_length = 20, final_length = 24 }\n");
  const fs::path vdir = t.path / "veins";
  fs::create_directories(vdir / "veins.svg" / "inside");
  const auto v = cli({"run", veins.string(), "--out", vdir.string(), "--quiet"});
  CHECK(v.code == 2);
  CHECK_THAT(v.err, Contains("veins.svg' is a folder where this run may write its veins.svg"));
  CHECK(!fs::exists(vdir / "checkpoint.cfck"));
  // a folder named for a file this run does not write is none of its business
  fs::create_directories(t.path / "other" / "veins.png" / "inside");
  fs::create_directories(t.path / "other" / "printable.vdb");
  CHECK(cli({"run", script.string(), "--out", (t.path / "other").string(), "--quiet", "--steps", "3"}).code == 0);
}

TEST_CASE("an output folder given through a missing folder and back out (--out new/../z) creates only z", "[cli]") {
  TempDir t("cli-out-dots");
  fs::create_directories(t.path / "have");
  using cellform::app::out_folder;
  CHECK(out_folder(t.path / "new" / ".." / "z") == t.path / "z");
  CHECK(out_folder(t.path / "a" / "b" / ".." / ".." / "c") == t.path / "c");
  CHECK(out_folder(t.path / "have" / ".." / "z") == t.path / "have" / ".." / "z");  // an existing folder stays
  CHECK(out_folder(fs::path("new") / "..") == fs::path("."));
  CHECK(out_folder(fs::path("..") / "x") == fs::path("..") / "x");
  CHECK(out_folder(t.path / "new" / "." / ".." / "y") == t.path / "y");
  // a file in the way is left for the system to refuse ("not a directory"), as before
  std::ofstream(t.path / "afile") << "x";
  CHECK(out_folder(t.path / "afile" / ".." / "z") == t.path / "afile" / ".." / "z");
  const auto script = t.write("s.lua", "disc { radius = 2 }\nrun { steps = 1 }\n");
  REQUIRE(cli({"run", script.string(), "--out", (t.path / "new" / ".." / "z").string(), "--quiet"}).code == 0);
  CHECK(fs::exists(t.path / "z" / "run.json"));
  CHECK_FALSE(fs::exists(t.path / "new"));
}

TEST_CASE("a checkpoint over an earlier run's marks that run's run.json superseded, and only cellform's", "[cli]") {
  TempDir t("cli-superseded-unit");
  const fs::path dir = t.path / "out";
  fs::create_directories(dir);
  const std::string earlier = R"({"program": "cellform", "status": "complete", "outputs": ["cells.ply"]})";
  t.write("out/run.json", earlier);
  cellform::app::write_checkpoint(dir / "checkpoint.cfck", "bytes");
  const auto marked = nlohmann::json::parse(slurp(dir / "run.json"));
  CHECK(marked["status"] == "superseded");
  CHECK_THAT(marked["superseded"].get<std::string>(), Contains("cellform resume this folder continues"));
  CHECK(marked["outputs"] == nlohmann::json::array({"cells.ply"}));  // kept for the cleanup at the commit
  const std::string once = slurp(dir / "run.json");
  cellform::app::write_checkpoint(dir / "checkpoint.cfck", "more bytes");
  CHECK(slurp(dir / "run.json") == once);  // marked once
  // another program's file, or none, is left alone
  const std::string foreign = R"({"tool": "other", "status": "complete"})";
  t.write("out/run.json", foreign);
  cellform::app::write_checkpoint(dir / "checkpoint.cfck", "bytes");
  CHECK(slurp(dir / "run.json") == foreign);
  fs::remove(dir / "run.json");
  cellform::app::write_checkpoint(dir / "checkpoint.cfck", "bytes");
  CHECK_FALSE(fs::exists(dir / "run.json"));
}

TEST_CASE("a run that could write no checkpoint drops an earlier run's; errors name the files in the folder", "[cli]") {
  TempDir t("cli-drop-checkpoint");
  const fs::path dir = t.path / "out";
  fs::create_directories(dir);
  using cellform::app::drop_earlier_checkpoint;
  const nlohmann::json none = {{"checkpoint", nullptr}}, own = {{"checkpoint", "checkpoint.cfck"}};
  t.write("out/checkpoint.cfck", "earlier run's");
  drop_earlier_checkpoint(dir, own, {});  // this run's checkpoint is there: kept
  CHECK(fs::exists(dir / "checkpoint.cfck"));
  drop_earlier_checkpoint(dir, none, dir / "checkpoint.cfck");  // the one this run resumed: kept
  CHECK(fs::exists(dir / "checkpoint.cfck"));
  drop_earlier_checkpoint(dir, none, t.path / "elsewhere.cfck");  // another run's, beside outputs it is not of
  CHECK_FALSE(fs::exists(dir / "checkpoint.cfck"));
  drop_earlier_checkpoint(dir, none, {});  // none there: nothing to do
  const fs::path staging = dir / ".partial-12";
  const cellform::core::FileError e("cannot write '" + (staging / "printable.stl").string() + "': disk full");
  CHECK(cellform::app::output_error(e, staging, dir) ==
        "cannot write '" + (dir / "printable.stl").string() + "': disk full");
}

TEST_CASE("own_record: the run.json a no-step resume of the folder's own checkpoint puts back", "[cli]") {
  TempDir t("cli-own-record");
  const fs::path dir = t.path / "out", other = t.path / "other";
  fs::create_directories(dir);
  fs::create_directories(other);
  t.write("out/checkpoint.cfck", "bytes");
  t.write("other/checkpoint.cfck", "bytes");
  t.write("out/run.json", "record");
  using cellform::app::own_record;
  CHECK(own_record(dir / "checkpoint.cfck", dir) == std::optional<std::string>("record"));
  CHECK(own_record(t.path / "out" / ".." / "out" / "checkpoint.cfck", dir).has_value());  // the same file
  CHECK_FALSE(own_record(other / "checkpoint.cfck", dir).has_value());  // another folder's: nothing to put back
  fs::remove(dir / "run.json");
  CHECK(own_record(dir / "checkpoint.cfck", dir) == std::optional<std::string>(""));
  fs::remove(dir / "checkpoint.cfck");
  CHECK_FALSE(own_record(other / "checkpoint.cfck", dir).has_value());
}

TEST_CASE("a run killed after its first checkpoint leaves the earlier run.json marked superseded", "[cli][signal]") {
  TempDir t("cli-superseded");
  const auto script =
      t.write("long.lua", "division { trigger = 'none' }\nrun { steps = 1000000 }\ndisc { radius = 20 }\n");
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "2"}).code == 0);
  const auto before = nlohmann::json::parse(slurp(out / "run.json"));
  REQUIRE(before["status"] == "complete");
  // a second run into the folder, killed (as a third Ctrl-C or SIGKILL does) once it wrote a checkpoint
  const pid_t pid =
      spawn_cellform({"run", script.string(), "--out", out.string(), "--quiet", "--checkpoint-every", "1"});
  REQUIRE(pid > 0);
  bool marked = false;
  for (int i = 0; i < 600 && !marked; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    try {
      marked = nlohmann::json::parse(slurp(out / "run.json"))["status"] == "superseded";
    } catch (const std::exception&) {
    }
  }
  kill(pid, SIGKILL);
  wait_exit(pid);
  REQUIRE(marked);  // it said "complete" beside the later run's checkpoint
  const auto after = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(after["outputs"] == before["outputs"]);
  CHECK(after["steps"] == before["steps"]);
  // a run into the folder then commits as usual
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "3"}).code == 0);
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["status"] == "complete");
}

TEST_CASE("a run killed after a checkpoint keeps its frames up to it: the resume takes them up", "[cli][signal]") {
  TempDir t("cli-killed-frames");
  const auto script = t.write("frames.lua",
                              "division { trigger = 'none' }\nrun { steps = 1000000 }\ndisc { radius = 12 }\n"
                              "output { every = 2 }\n");
  const fs::path out = t.path / "o";
  const pid_t pid =
      spawn_cellform({"run", script.string(), "--out", out.string(), "--quiet", "--checkpoint-every", "3"});
  REQUIRE(pid > 0);
  const fs::path staging = out / (".partial-" + std::to_string(pid));
  // killed once it has written a checkpoint after three frames (steps 0, 2, 4: the checkpoint of step 6 or later)
  bool ready = false;
  for (int i = 0; i < 1200 && !ready; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
    std::error_code ec;
    ready = fs::exists(staging / "frames" / "cells_000006.ply", ec) && fs::exists(out / "checkpoint.cfck", ec);
  }
  kill(pid, SIGKILL);
  wait_exit(pid);
  REQUIRE(ready);
  const std::string bytes = slurp(out / "checkpoint.cfck");
  const auto meta = nlohmann::json::parse(cellform::core::read_chunk_file(bytes, "CKPT", 1, "test").chunks.at("meta"));
  const std::uint64_t at = meta["step"].get<std::uint64_t>();
  REQUIRE(at >= 3);
  // the staging folder is known by the checkpoint it last wrote (not by its process id, which a container
  // gives again, or which another process may hold now)
  // (two lines when the kill came while it replaced the checkpoint: the one it wrote, and the one before)
  CHECK_THAT(slurp(staging / cellform::app::kStagingMark),
             Catch::Matchers::Contains(cellform::app::checkpoint_mark(bytes) + "\n"));
  // a decoy: another killed run's staging folder, with frames of its own, is not taken
  fs::create_directories(out / ".partial-1" / "frames");
  std::ofstream(out / ".partial-1" / "frames" / "cells_000000.ply") << "another run's";
  std::ofstream(out / ".partial-1" / cellform::app::kStagingMark) << "fnv1a64:0000000000000000\n";
  // a run of another script into the folder that fails before its first checkpoint leaves the checkpoint
  // there, and with it the frames it needs (they were deleted with the killed run's staging folder)
  const auto bad = t.write("bad.lua",
                           "run { steps = 10 }\ndisc { radius = 3 }\ndivision { rule = function(c)\n"
                           "  if c.step >= 2 then return nil end return false end }\n");
  CliResult r = cli({"run", bad.string(), "--out", out.string(), "--quiet"});
  REQUIRE(r.code == 2);
  CHECK(slurp(out / "checkpoint.cfck") == bytes);
  CHECK(fs::exists(staging / "frames" / "cells_000002.ply"));
  CHECK_FALSE(fs::exists(out / ".partial-1"));  // the decoy, marked with no checkpoint there, is gone
  // the resume lists and keeps every frame, as a run that was never killed
  const std::string target = std::to_string(at + 4);
  r = cli({"resume", out.string(), "--steps", target, "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_FALSE(fs::exists(staging));
  const fs::path fresh = t.path / "fresh";
  REQUIRE(cli({"run", script.string(), "--out", fresh.string(), "--quiet", "--steps", target}).code == 0);
  const auto listed = nlohmann::json::parse(slurp(out / "run.json"))["outputs"];
  const auto expected = nlohmann::json::parse(slurp(fresh / "run.json"))["outputs"];
  std::set<std::string> a(listed.begin(), listed.end()), b(expected.begin(), expected.end());
  CHECK(a == b);
  for (const std::string& n : b)
    if (n.rfind("frames/", 0) == 0) {
      INFO(n);
      CHECK(slurp(out / n) == slurp(fresh / n));
    }
}

TEST_CASE("a command whose standard output cannot be written fails instead of saying success", "[cli]") {
  // what params, check --json and --version print is their product: lost on a full disk, it is no success
  // (and run --help's, which exited 0: audit)
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"params"}, {"--version"}, {"run", "--help"}, {"resume", "-h"}}) {
    const int full = ::open("/dev/full", O_WRONLY);
    REQUIRE(full >= 0);
    const pid_t pid = spawn_cellform(args, full);
    ::close(full);
    REQUIRE(pid > 0);
    CHECK(exit_within(pid, 60) == 1);
  }
  // check's report lost is not "not printable" (1): 2, as a file it cannot read
  TempDir t("cli-check-full");
  auto facet = [](const char* a, const char* b, const char* c) {
    return std::string("facet normal 0 0 0\nouter loop\nvertex ") + a + "\nvertex " + b + "\nvertex " + c +
           "\nendloop\nendfacet\n";
  };
  const auto stl = t.write("tetra.stl", std::string("solid t\n") + facet("0 0 0", "0 1 0", "1 0 0") +
                                            facet("0 0 0", "1 0 0", "0 0 1") + facet("0 0 0", "0 0 1", "0 1 0") +
                                            facet("1 0 0", "0 1 0", "0 0 1") + "endsolid t\n");
  REQUIRE(cli({"check", stl.string()}).code == 0);
  const int full = ::open("/dev/full", O_WRONLY);
  REQUIRE(full >= 0);
  const pid_t checked = spawn_cellform({"check", stl.string()}, full);
  ::close(full);
  CHECK(exit_within(checked, 60) == 2);
  // written somewhere that takes it, the same commands succeed
  const int null = ::open("/dev/null", O_WRONLY);
  REQUIRE(null >= 0);
  const pid_t pid = spawn_cellform({"params"}, null);
  ::close(null);
  CHECK(exit_within(pid, 60) == 0);
}

TEST_CASE("a checkpoint that cannot be written leaves the earlier run's run.json as it was", "[cli]") {
  // a full disk, here a folder in the checkpoint's place: the folder's checkpoint is still the earlier
  // run's, so its run.json must not say that a later run's replaced it
  TempDir t("cli-ckpt-fail");
  const auto script = t.write("small.lua", kSmall);
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "2"}).code == 0);
  const std::string before = slurp(out / "run.json");
  fs::remove(out / "checkpoint.cfck");
  fs::create_directories(out / "checkpoint.cfck" / "in-the-way");
  CHECK_THROWS(cellform::app::write_checkpoint(out / "checkpoint.cfck", "bytes"));
  CHECK(slurp(out / "run.json") == before);
  fs::remove_all(out / "checkpoint.cfck");  // written: the earlier run is superseded
  cellform::app::write_checkpoint(out / "checkpoint.cfck", "bytes");
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["status"] == "superseded");
}

TEST_CASE("a full disk keeps the frames up to the last checkpoint, as a script error does", "[cli][files]") {
  TempDir t("full-disk-frames");
  const auto script = t.write("small.lua", kSmall);
  const fs::path out = t.path / "o";
  // RLIMIT_FSIZE fails writes past 14,000 bytes as a full disk would (EFBIG; SIGXFSZ ignored): the checkpoints
  // of steps 5 and 10 fit (5.4 and 9.6 kB) and the one of step 15 does not (17.4 kB: a warning, the run goes
  // on); frame 15 fits (12.1 kB), frame 20 (20.3 kB) does not, and stops the run
  const auto r = [&] {
    const FileSizeLimit limit(14000);
    return cli({"run", script.string(), "--out", out.string(), "--set", "output.every=5", "--checkpoint-every", "5",
                "--quiet"});
  }();
  INFO(r.err);
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("cells_000020.ply") && Contains("cellform resume continues from it"));
  // the frames the checkpoint of step 10 needs stay, with a run.json that says so (they were deleted)
  for (const char* f : {"frames/cells_000000.ply", "frames/cells_000005.ply", "frames/cells_000010.ply"})
    CHECK(fs::exists(out / f));
  CHECK_FALSE(fs::exists(out / "frames/cells_000015.ply"));  // after the checkpoint: a resume writes it again
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "failed");
  CHECK(run["steps"]["completed"] == 10);
  // and the resume with room again writes the frames from there on, as an unbroken run does
  const auto resumed = cli({"resume", (out / "checkpoint.cfck").string(), "--quiet"});
  INFO(resumed.err);
  REQUIRE(resumed.code == 0);
  const fs::path fresh = t.path / "fresh";
  REQUIRE(cli({"run", script.string(), "--out", fresh.string(), "--set", "output.every=5", "--checkpoint-every", "5",
               "--quiet"})
              .code == 0);
  for (const char* f : {"frames/cells_000000.ply", "frames/cells_000010.ply", "frames/cells_000015.ply",
                        "frames/cells_000030.ply", "cells.ply"}) {
    INFO(f);
    CHECK(slurp(out / f) == slurp(fresh / f));
  }
  // a resume that runs no step and cannot write its outputs leaves the finished run as it was (here its
  // checkpoint does not fit either; on a small tmpfs where it did, a failed run.json replaced the outputs)
  const std::string cells = slurp(out / "cells.ply");
  const auto again = [&] {
    const FileSizeLimit limit(12000);
    return cli({"resume", (out / "checkpoint.cfck").string(), "--quiet"});
  }();
  CHECK(again.code == 1);
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["status"] == "complete");
  CHECK(slurp(out / "cells.ply") == cells);
  CHECK(fs::exists(out / "frames/cells_000030.ply"));
}
