// Tests of a checkpoint that cannot be written (a full disk, a folder in the way): the outputs still go in and
// say so, an earlier run's checkpoint in the folder is never lost, and no hint offers a retry that is not one.
#include <algorithm>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("a checkpoint that cannot be written still leaves the outputs, and says so", "[cli][checkpoint]") {
  TempDir t("cli-no-checkpoint");
  const auto cells = t.write("small.lua", kSmall);
  const auto veins = t.write("leaf.lua",
                             "leaf { shape = 'ellipse' }\n"
                             "colonisation { type = 'open', growth = 'none', initial_length = 30, darts = 20000 }\n");
  for (const fs::path& script : {cells, veins}) {
    INFO(script.filename().string());
    const fs::path out = t.path / script.stem();
    fs::create_directories(out / "checkpoint.cfck");  // a folder in the way: the checkpoint cannot be written
    // periodic checkpoints every step fail too: said once, and the run goes on to its end
    const auto r = cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "5", "--set",
                        "output.checkpoint_every=1", "--set", "output.checkpoint_seconds=0"});
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
  }
}

TEST_CASE("a re-run that can write no checkpoint leaves the folder's earlier run, checkpoint and all",
          "[cli][checkpoint]") {
  // a full disk (here a file size limit between the other outputs' sizes and the checkpoint's): the re-run's
  // smaller files went in and the earlier run's checkpoint went, leaving neither run to resume
  TempDir t("cli-keep-earlier");
  const auto cells = t.write("small.lua", std::string(kSmall) + "venation { threshold = 10 }\n");
  const auto veins = t.write("ball.lua",
                             "volume { ball = { radius = 5 }, seeds = {{0, 0, 0}} }\n"
                             "colonisation { type = 'open', birth_distance = 1, kill_distance = 1, darts = 1e6 }\n");
  for (const fs::path& script : {cells, veins}) {
    INFO(script.filename().string());
    const fs::path out = t.path / script.stem();
    REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "30"}).code == 0);
    const std::string record = slurp(out / "run.json"), checkpoint = slurp(out / "checkpoint.cfck");
    std::size_t largest_other = 0;
    for (const auto& name : nlohmann::json::parse(record)["outputs"])
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
    for (const auto& name : nlohmann::json::parse(record)["outputs"])
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
  REQUIRE(fs::file_size(whole / "printable.stl") > limit);
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
