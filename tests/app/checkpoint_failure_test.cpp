// Tests of a checkpoint that cannot be written (a full disk; a folder in its place is refused): the outputs still go in
// and say so, an earlier run's checkpoint in the folder is never lost, and no hint offers a retry that is not one.
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {
/// A cell run with canalisation and a 3-D space colonisation, small, written into `t`.
std::vector<fs::path> cell_and_vein_scripts(const TempDir& t) {
  return {t.write("small.lua", std::string(kSmall) + "venation { threshold = 10 }\n"),
          t.write("ball.lua", kSmallVeins)};
}
}  // namespace

TEST_CASE("a checkpoint that cannot be written still leaves the outputs, and says so", "[cli][checkpoint]") {
  TempDir t("cli-no-checkpoint");
  for (const fs::path& script : cell_and_vein_scripts(t)) {
    INFO(script.filename().string());
    // a full disk (a file size limit between the outputs' sizes and the smallest checkpoint's): periodic
    // checkpoints every step fail too: said once, and the run goes on to its end
    const std::vector<std::string> args = {"run",
                                           script.string(),
                                           "--quiet",
                                           "--set",
                                           "output.checkpoint_every=1",
                                           "--set",
                                           "output.checkpoint_seconds=0",
                                           "--out"};
    auto run_into = [&](const fs::path& out, const std::string& steps) {
      std::vector<std::string> a = args;
      a.insert(a.end(), {out.string(), "--steps", steps});
      return cli(a);
    };
    const fs::path first = t.path / (script.stem().string() + "1"), whole = t.path / (script.stem().string() + "5");
    REQUIRE(run_into(first, "1").code == 0);
    REQUIRE(run_into(whole, "5").code == 0);
    const std::size_t limit = fs::file_size(first / "checkpoint.cfck") - 1;
    // (a copy of the list: the parsed document is a temporary, gone before a C++20 loop body runs; ASan)
    for (const auto& name : nlohmann::json(nlohmann::json::parse(slurp(whole / "run.json"))["outputs"]))
      REQUIRE(fs::file_size(whole / name.get<std::string>()) + 100 < limit);
    const fs::path out = t.path / (script.stem().string() + "L");  // a name as long: checkpoints record it
    CliResult r;
    {
      FileSizeLimit small(limit);
      r = run_into(out, "5");
    }
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("checkpoint.cfck") && Contains("this run cannot be resumed"));
    const std::string goes_on = "the run goes on";
    CHECK(r.err.find(goes_on) != std::string::npos);
    CHECK(r.err.find(goes_on) == r.err.rfind(goes_on));
    const auto run = nlohmann::json::parse(slurp(out / "run.json"));
    CHECK(run["checkpoint"].is_null());
    CHECK_THAT(run["checkpoint_error"].get<std::string>(), Contains("checkpoint.cfck"));
    CHECK(!run.contains("checkpoint_step"));
    for (const auto& name : run["outputs"]) CHECK(fs::is_regular_file(out / name.get<std::string>()));
    CHECK(run["outputs"].size() >= 3);
    CHECK_FALSE(fs::exists(out / "checkpoint.cfck"));
  }
}

TEST_CASE("a folder where a run writes its checkpoint or run.json is refused before the first step",
          "[cli][checkpoint]") {
  // it was found only at the first checkpoint: the run went on unable to be resumed, and its run.json said
  // "complete" beside exit code 1
  TempDir t("cli-folder-in-the-way");
  const auto cells = t.write("small.lua", kSmall);
  const auto veins = t.write("ball.lua", kSmallVeins);
  for (const fs::path& script : {cells, veins})
    for (const char* name : {"checkpoint.cfck", "run.json"}) {
      INFO(script.filename().string() << " " << name);
      const fs::path out = t.path / (script.stem().string() + "-" + name);
      fs::create_directories(out / name / "x");
      const auto r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
      CHECK(r.code == 2);
      std::string said = "'";  // (built by += : g++ 12 warns of "literal" + a temporary string)
      said += (out / name).string();
      said += "' is a folder where this run may write its ";
      said += name;
      CHECK_THAT(r.err, Contains(said + ": choose another --out folder, or move that folder away"));
      std::size_t entries = 0;  // nothing made beside it
      for ([[maybe_unused]] const auto& e : fs::directory_iterator(out)) ++entries;
      CHECK(entries == 1);
      CHECK(fs::is_directory(out / name / "x"));
    }
}

TEST_CASE("a re-run that can write no checkpoint leaves the folder's earlier run, checkpoint and all",
          "[cli][checkpoint]") {
  // a full disk (here a file size limit between the other outputs' sizes and the checkpoint's): the re-run's
  // smaller files went in and the earlier run's checkpoint went, leaving neither run to resume
  TempDir t("cli-keep-earlier");
  for (const fs::path& script : cell_and_vein_scripts(t)) {
    INFO(script.filename().string());
    const fs::path out = t.path / script.stem();
    REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "30"}).code == 0);
    const std::string record = slurp(out / "run.json"), checkpoint = slurp(out / "checkpoint.cfck");
    std::size_t largest_other = 0;
    for (const auto& name : nlohmann::json(nlohmann::json::parse(record)["outputs"]))
      largest_other = std::max<std::size_t>(largest_other, fs::file_size(out / name.get<std::string>()));
    const std::size_t limit = checkpoint.size() - 1;  // the same run again: the other files fit, the checkpoint not
    REQUIRE(largest_other + 1000 < limit);
    CliResult r;
    {
      FileSizeLimit small(limit);
      r = cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "30"});
    }
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("checkpoint.cfck") && Contains("nothing in " + out.string() + "/ changed"));
    CHECK(slurp(out / "run.json") == record);
    CHECK(slurp(out / "checkpoint.cfck") == checkpoint);
    for (const auto& name : nlohmann::json(nlohmann::json::parse(record)["outputs"]))
      CHECK(fs::is_regular_file(out / name.get<std::string>()));
    std::size_t entries = 0;  // no staging folder or temporary left
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(out)) ++entries;
    CHECK(entries == nlohmann::json::parse(record)["outputs"].size() + 1);  // run.json's list holds itself
    // the earlier run goes on from its checkpoint as before
    CHECK(cli({"resume", out.string(), "--steps", "32", "--quiet"}).code == 0);
  }
}

TEST_CASE("a print that fails after only a periodic checkpoint offers no quick retry of the print",
          "[cli][checkpoint]") {
  // the final checkpoint did not fit, the one of step 29 did: "to print again: cellform resume ... --set
  // print.NAME=VALUE" would grow step 30 again before printing, which is not what it promised
  TempDir t("cli-no-retry");
  const auto script = t.write("sheet.lua", std::string(kSmall) + "venation { threshold = 10 }\nprint { size = 60 }\n");
  const std::vector<std::string> args = {"run",   script.string(), "--quiet",
                                         "--set", "size=100000",   "--checkpoint-every",
                                         "1",     "--set",         "output.checkpoint_seconds=0",
                                         "--out"};
  auto with_out = [&](const fs::path& out) {
    std::vector<std::string> a = args;
    a.push_back(out.string());
    return a;
  };
  const fs::path whole = t.path / "whole";
  REQUIRE(cli(with_out(whole)).code == 0);  // the sheet grows every step: each checkpoint is larger
  const std::size_t limit = fs::file_size(whole / "checkpoint.cfck") - 1;
  REQUIRE(fs::file_size(whole / "printable.stl") > limit + 1);  // so that the second half's limit lets it fail
  REQUIRE(fs::file_size(whole / "cells.ply") + 1000 < limit);
  CliResult r;
  {
    FileSizeLimit small(limit);
    r = cli(with_out(t.path / "limit"));  // a name as long as "whole": a checkpoint records its folder
  }
  INFO(r.err);
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("printable.stl") && Contains("of step 29"));
  CHECK_THAT(r.err, !Contains("to print again"));
  // with the final checkpoint written, the hint stays
  {
    FileSizeLimit small(fs::file_size(whole / "printable.stl") - 1);
    r = cli(with_out(t.path / "print"));
  }
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("to print again with other print.* values"));
}

TEST_CASE("a resume into another run's folder that can write no checkpoint leaves that run as it was",
          "[cli][checkpoint]") {
  // review: a resume that ran no step (the outputs made again) skipped the check, and with --out into another
  // run's folder deleted that run's checkpoint
  TempDir t("cli-keep-other");
  for (const fs::path& script : cell_and_vein_scripts(t)) {
    INFO(script.filename().string());
    const fs::path a = t.path / (script.stem().string() + "A"), b = t.path / (script.stem().string() + "B");
    REQUIRE(cli({"run", script.string(), "--out", a.string(), "--quiet", "--steps", "30"}).code == 0);
    REQUIRE(cli({"run", script.string(), "--out", b.string(), "--quiet", "--steps", "30", "--seed", "7"}).code == 0);
    const std::string record = slurp(b / "run.json"), checkpoint = slurp(b / "checkpoint.cfck");
    const std::size_t limit = fs::file_size(a / "checkpoint.cfck") - 1;  // A's state, written into B
    for (const auto& name : nlohmann::json(nlohmann::json::parse(slurp(a / "run.json"))["outputs"]))
      REQUIRE(fs::file_size(a / name.get<std::string>()) + 1000 < limit);
    CliResult r;
    {
      FileSizeLimit small(limit);
      r = cli({"resume", (a / "checkpoint.cfck").string(), "--out", b.string(), "--quiet"});  // no step runs
    }
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("this run's outputs are not written") && Contains(b.string()));
    CHECK(slurp(b / "run.json") == record);
    CHECK(slurp(b / "checkpoint.cfck") == checkpoint);
  }
}

TEST_CASE("a Ctrl-C while the sheet grows, whose checkpoint fails, leaves another run's folder as it was",
          "[cli][checkpoint][signal]") {
  // review: the interrupted sheet's outputs replaced the folder's run, checkpoint and all
  TempDir t("cli-keep-sheet");
  const auto other = t.write("small.lua", kSmall);
  const auto sheet = t.write("sheet.lua",
                             "division { trigger = 'none' }\nrun { steps = 1000000 }\ndisc { radius = 6 }\n"
                             "petiole { at = {0, -6, 0} }\nsurface { cells = true }\n"
                             "colonisation { birth_distance = 1, kill_distance = 1, darts = 1e6 }\n");
  auto interrupted = [&](const fs::path& out) {
    const fs::path log = t.path / "log.txt";
    const pid_t pid = spawn_cellform_logged(
        {"run", sheet.string(), "--out", out.string(), "--quiet", "--set", "output.checkpoint_every=0"}, log);
    REQUIRE(pid > 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(800));  // the sheet grows (no periodic checkpoint)
    kill(pid, SIGINT);
    const int code = wait_exit(pid);
    return std::pair{code, slurp(log)};
  };
  const fs::path reference = t.path / "R", kept = t.path / "K";  // names of one length: checkpoints record them
  const auto [code, said] = interrupted(reference);
  INFO(said);
  REQUIRE(code == 130);
  const std::size_t limit = fs::file_size(reference / "checkpoint.cfck") - 200;  // (the step's digits vary)
  REQUIRE(fs::file_size(reference / "cells.ply") + 1000 < limit);
  REQUIRE(cli({"run", other.string(), "--out", kept.string(), "--quiet"}).code == 0);
  const std::string record = slurp(kept / "run.json"), checkpoint = slurp(kept / "checkpoint.cfck");
  std::pair<int, std::string> r;
  {
    FileSizeLimit small(limit);
    r = interrupted(kept);
  }
  INFO(r.second);
  CHECK(r.first == 130);  // a Ctrl-C ends cellform by SIGINT, whatever the outputs did
  CHECK_THAT(r.second, Contains("this run's outputs are not written"));
  CHECK(slurp(kept / "run.json") == record);
  CHECK(slurp(kept / "checkpoint.cfck") == checkpoint);
}

TEST_CASE("a resume whose checkpoint fails in its own folder names the checkpoint it resumed, still there",
          "[cli][checkpoint]") {
  // review: run.json said checkpoint null and the message "this run cannot be resumed", though the checkpoint
  // resumed stays (the commit keeps it) and a resume of it makes the same steps again
  TempDir t("cli-resumed-kept");
  const auto script = t.write("small.lua", std::string(kSmall) + "venation { threshold = 10 }\n");
  const fs::path whole = t.path / "W", part = t.path / "P";  // names of one length: checkpoints record them
  REQUIRE(cli({"run", script.string(), "--out", whole.string(), "--quiet", "--steps", "40"}).code == 0);
  REQUIRE(cli({"run", script.string(), "--out", part.string(), "--quiet", "--steps", "20"}).code == 0);
  const std::string resumed = slurp(part / "checkpoint.cfck");
  const std::size_t limit = fs::file_size(whole / "checkpoint.cfck") - 1;
  for (const auto& name : nlohmann::json(nlohmann::json::parse(slurp(whole / "run.json"))["outputs"]))
    REQUIRE(fs::file_size(whole / name.get<std::string>()) + 1000 < limit);
  CliResult r;
  {
    FileSizeLimit small(limit);
    r = cli({"resume", part.string(), "--steps", "40", "--quiet"});
  }
  INFO(r.err);
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("the checkpoint resumed (step 20), is as it was") && !Contains("cannot be resumed"));
  const auto run = nlohmann::json::parse(slurp(part / "run.json"));
  CHECK(run.at("checkpoint") == "checkpoint.cfck");
  CHECK(run.at("checkpoint_step") == 20);
  CHECK(slurp(part / "checkpoint.cfck") == resumed);
  // and it is so: resumed again, the same result as the run that went through
  REQUIRE(cli({"resume", part.string(), "--steps", "40", "--quiet"}).code == 0);
  CHECK(slurp(part / "cells.ply") == slurp(whole / "cells.ply"));
}

TEST_CASE("a print that fails, then run.json too, does not say that the other outputs are written",
          "[cli][checkpoint]") {
  // a full disk: printable.stl failed, then run.json, and the outputs were dropped; the print's failure said
  // "(the other outputs and the checkpoint are written)" before that
  TempDir t("cli-print-then-record");
  const auto script = t.write("sheet.lua",
                              "local P = params { note = 'a note' }\nrun { steps = 0 }\ndisc { radius = 2 }\n"
                              "print { shell = true, veins = false, size = 40 }\n");
  // a long parameter is in run.json twice (overrides, parameters) and in the checkpoint once: a file size
  // limit between the two lets the checkpoint and the cell files in, but not printable.stl and run.json
  const std::vector<std::string> args = {"run",  script.string(), "--quiet", "--set", "note=" + std::string(3000, 'n'),
                                         "--out"};
  const fs::path whole = t.path / "whole", out = t.path / "out";
  auto with_out = [&](const fs::path& o) {
    std::vector<std::string> a = args;
    a.push_back(o.string());
    return a;
  };
  REQUIRE(cli(with_out(whole)).code == 0);
  const std::size_t checkpoint = fs::file_size(whole / "checkpoint.cfck"), record = fs::file_size(whole / "run.json");
  REQUIRE(checkpoint + 1000 < record);
  REQUIRE(fs::file_size(whole / "cells.ply") < checkpoint);
  CliResult r;
  {
    FileSizeLimit small((checkpoint + record) / 2);
    r = cli(with_out(out));
  }
  INFO(r.err);
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("printable.stl") && Contains("run.json") && !Contains("outputs and the checkpoint are"));
  CHECK_THAT(r.err, !Contains("other outputs are written"));
  CHECK_THAT(r.err, Contains("cellform resume continues from it"));
  CHECK(!fs::exists(out / "run.json"));
  CHECK(cli({"resume", (out / "checkpoint.cfck").string(), "--quiet"}).code == 0);  // the checkpoint is whole
  CHECK(slurp(out / "cells.ply") == slurp(whole / "cells.ply"));
}
