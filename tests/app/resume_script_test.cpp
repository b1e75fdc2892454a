// Tests of runs that an error stops (a rule that fails, a petiole far from the cells, cells that diverge):
// what they leave (checkpoint, frames, a run.json that says failed) and `cellform resume --script`, which
// goes on from that checkpoint with the corrected script.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/run_internal.h"
#include "core/chunk_file.h"
#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("a rule error names the checkpoint of this run, never one left by an earlier run", "[cli][checkpoint]") {
  TempDir t("cli-late-rule");
  // the division rule breaks from step 9 on: the run stops there with the script's line
  const auto script = t.write("late.lua",
                              "cells { time_step = 0.2, separation = 0.05 }\n"
                              "division { max_cells = 300, rule = function(cell)\n"
                              "  if cell.step >= 9 then return 'x' end\n"
                              "  return cell.age > 4 end }\n"
                              "run { steps = 30 }\n"
                              "disc { radius = 3 }\n"
                              "petiole { at = {0, 0, 0} }\n");
  const fs::path out = t.path / "out";
  fs::create_directories(out);
  t.write("out/checkpoint.cfck", "left by an earlier run");
  const CliResult first = cli({"run", script.string(), "--out", out.string(), "--quiet"});
  CHECK(first.code == 2);
  CHECK_THAT(first.err, Contains("late.lua:2: division.rule must return true or false"));
  CHECK_THAT(first.err, !Contains("the last checkpoint is"));  // the stale file is not this run's
  CHECK_THAT(first.err, Contains("no checkpoint of this run was written before step 10, so there is nothing to go on "
                                 "from; output.checkpoint_every and output.checkpoint_minutes, or --checkpoint-every "
                                 "N, set how often one is"));
  const CliResult second = cli({"run", script.string(), "--out", out.string(), "--checkpoint-every", "4", "--quiet"});
  CHECK(second.code == 2);
  CHECK_THAT(second.err, Contains("(the last checkpoint is " + (out / "checkpoint.cfck").string() + ", of step 8)"));
  // that checkpoint (step 8) resumes into the same error, and says it is the one resumed
  const fs::path kept = t.path / "step8.cfck";
  fs::copy_file(out / "checkpoint.cfck", kept);
  const CliResult resumed = cli({"resume", kept.string(), "--out", (t.path / "again").string(), "--quiet"});
  CHECK(resumed.code == 2);
  CHECK_THAT(resumed.err, Contains("(the last checkpoint is " + kept.string() + ", the one resumed)"));
  // a checkpoint is also due output.checkpoint_minutes after the last one (and not within checkpoint_seconds),
  // whatever the step: at a microsecond and none, after every step, so the run keeps step 9
  const fs::path timed = t.path / "timed";
  const CliResult third = cli({"run", script.string(), "--out", timed.string(), "--quiet", "--set",
                               "output.checkpoint_minutes=0.00000001", "--set", "output.checkpoint_seconds=0"});
  CHECK(third.code == 2);
  CHECK_THAT(third.err, Contains("(the last checkpoint is " + (timed / "checkpoint.cfck").string() + ", of step 9)"));
  CHECK(nlohmann::json::parse(slurp(timed / "run.json"))["steps"]["completed"] == 9);
}

TEST_CASE("a run stopped by a script error goes on from its checkpoint with the corrected script",
          "[cli][checkpoint]") {
  TempDir t("cli-resume-script");
  // the rule breaks from step 25 on; the corrected copy differs only there, so steps 1 to 24 are the same
  const std::string head =
      "cells { time_step = 0.2, separation = 0.05 }\n"
      "division { max_cells = 3000, rule = function(cell)\n"
      "  if cell.step >= 25 then return ";
  const std::string tail =
      " end\n"
      "  return cell.age > 4 end }\n"
      "run { steps = 40 }\n"
      "disc { radius = 3 }\n"
      "petiole { at = {0, 0, 0} }\n"
      "venation { threshold = 10 }\n"
      "output { every = 10 }\n";
  const auto broken = t.write("broken.lua", head + "'x'" + tail);
  const auto fixed = t.write("fixed.lua", head + "cell.age > 6" + tail);
  const fs::path out = t.path / "out", fresh = t.path / "fresh";
  const fs::path checkpoint = out / "checkpoint.cfck";
  // an earlier run in the folder: the failed run's run.json and checkpoint replace it, not sit beside it
  REQUIRE(cli({"run", fixed.string(), "--out", out.string(), "--steps", "3", "--quiet"}).code == 0);
  REQUIRE(fs::exists(out / "cells.ply"));
  const CliResult failed = cli({"run", broken.string(), "--out", out.string(), "--checkpoint-every", "10", "--quiet"});
  REQUIRE(failed.code == 2);
  CHECK_THAT(failed.err, Contains("at step 25"));
  CHECK_THAT(failed.err, Contains("cellform resume " + checkpoint.string() + " --script " + broken.string()));
  {  // the script's limits are not in the checkpoint: the command given carries those that differ from the defaults
    const fs::path limited = t.path / "limited";
    const CliResult l = cli({"run", broken.string(), "--out", limited.string(), "--checkpoint-every", "10", "--quiet",
                             "--lua-memory", "100", "--lua-seconds", "30", "--lua-instructions", "600000000"});
    REQUIRE(l.code == 2);
    CHECK_THAT(l.err, Contains(" --lua-instructions 600000000 --lua-memory 100 --lua-seconds 30"));
    CHECK_THAT(failed.err, !Contains("--lua-"));
  }
  // the folder shows the run up to its checkpoint (step 20): the frames so far and a run.json that says why
  auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "failed");
  CHECK_THAT(run["error"].get<std::string>(), Contains("broken.lua:2: division.rule must return true or false"));
  CHECK(run["steps"]["completed"] == 20);
  CHECK(run["steps"]["failed"] == 25);
  CHECK(run["timings"].at("checkpoints_s").get<double>() > 0);  // those of steps 10 and 20
  CHECK(run["outputs"] == nlohmann::json::array({"frames/cells_000000.ply", "frames/cells_000010.ply",
                                                 "frames/cells_000020.ply", "run.json"}));
  CHECK(fs::exists(out / "frames/cells_000020.ply"));
  CHECK_FALSE(fs::exists(out / "frames/cells_000030.ply"));
  CHECK_FALSE(fs::exists(out / "cells.ply"));  // the failed step's cells are not the run's
  // the checkpoint keeps the broken script: a plain resume stops at the same step again
  CliResult r = cli({"resume", checkpoint.string(), "--out", (t.path / "again").string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("at step 25"));
  r = cli({"resume", checkpoint.string(), "--script", fixed.string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  // the same cells as a run of the corrected script from the start
  REQUIRE(cli({"run", fixed.string(), "--out", fresh.string(), "--quiet"}).code == 0);
  CHECK(slurp(out / "cells.ply") == slurp(fresh / "cells.ply"));
  CHECK(slurp(out / "veins.ply") == slurp(fresh / "veins.ply"));
  for (const char* f : {"frames/cells_000010.ply", "frames/cells_000020.ply", "frames/cells_000030.ply"}) {
    INFO(f);  // the failed run's frames stay, as the run's
    CHECK(slurp(out / f) == slurp(fresh / f));
  }
  run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "complete");
  CHECK(run["outputs"].size() == nlohmann::json::parse(slurp(fresh / "run.json"))["outputs"].size());
  CHECK(run["steps"]["first"] == 20);
  CHECK(run["steps"]["completed"] == 40);
  CHECK(run["script"]["hash"] == cellform::app::script_hash(slurp(fixed)));
  // what it replaced: the broken script up to step 20, with its values, and a copy of that checkpoint
  REQUIRE(run["script"]["replaces"].size() == 1);
  const auto replaced = run["script"]["replaces"][0];
  CHECK(replaced["hash"] == cellform::app::script_hash(slurp(broken)));
  CHECK(replaced["until_step"] == 20);
  CHECK(replaced["parameters"]["division"]["max_cells"] == 3000);
  CHECK(replaced["parameters"]["output"]["checkpoint_every"] == 10);  // as the run had them (--checkpoint-every)
  CHECK(replaced["parameters"]["run"]["seed"] == 1);
  CHECK(replaced["checkpoint"] == "checkpoint-step20.cfck");
  CHECK_THAT(r.err, Contains("the checkpoint resumed is kept as " + (out / "checkpoint-step20.cfck").string()));
  const auto at20 = cellform::core::read_chunk_file(slurp(out / "checkpoint-step20.cfck"), "CKPT", 1, "test");
  CHECK(at20.chunks.at("script") == slurp(broken));
  // the new checkpoint keeps the corrected script, so it resumes without --script, and remembers the old one
  const auto saved = cellform::core::read_chunk_file(slurp(checkpoint), "CKPT", 1, "test");
  CHECK(saved.chunks.at("script") == slurp(fixed));
  r = cli({"resume", checkpoint.string(), "--steps", "45", "--quiet"});
  CHECK(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["script"]["replaces"] == run["script"]["replaces"]);
  // the same script again is a plain resume: it keeps the step count the run was going to (45, its --steps;
  // it went on to the script's run.steps), makes no copy and adds nothing to replaces
  r = cli({"resume", checkpoint.string(), "--script", fixed.string()});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("at its run's last step (45): no step runs"));
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["steps"]["completed"] == 45);
  r = cli({"resume", checkpoint.string(), "--steps", "46", "--script", fixed.string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("is the script the checkpoint keeps, unchanged: this is a plain resume"));
  CHECK_FALSE(fs::exists(out / "checkpoint-step45.cfck"));
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["script"]["replaces"] == run["script"]["replaces"]);
  CHECK(replaced["parameters"]["run"]["steps"] == 40);
  // with --steps too: the replaced run's values are still its own (its 40 steps, not this resume's 50)
  const fs::path other = t.path / "other";
  r = cli({"resume", (out / "checkpoint-step20.cfck").string(), "--out", other.string(), "--script", fixed.string(),
           "--steps", "50", "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto other_run = nlohmann::json::parse(slurp(other / "run.json"));
  CHECK(other_run["steps"]["completed"] == 50);
  CHECK(other_run["script"]["replaces"][0]["parameters"]["run"]["steps"] == 40);
  CHECK(other_run["script"]["replaces"][0]["until_step"] == 20);
  // the kept copy resumed into its folder (to undo the --script) keeps the folder's own, later checkpoint too:
  // it was replaced with no copy and no word (audit)
  const std::string at46 = slurp(checkpoint);
  r = cli(
      {"resume", (out / "checkpoint-step20.cfck").string(), "--script", fixed.string(), "--steps", "25", "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("the folder's own checkpoint.cfck (step 46) is kept as " +
                             (out / "checkpoint-step46.cfck").string()));
  CHECK(slurp(out / "checkpoint-step46.cfck") == at46);
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["steps"]["completed"] == 25);
}

TEST_CASE("resume --script is refused clearly where it cannot apply", "[cli][checkpoint]") {
  TempDir t("cli-resume-script-bad");
  const auto script = t.write("small.lua", kSmall);
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "5"}).code == 0);
  const std::string checkpoint = (out / "checkpoint.cfck").string();
  const std::string before = slurp(out / "checkpoint.cfck");
  CliResult r = cli({"run", script.string(), "--script", script.string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--script is for cellform resume"));
  r = cli({"resume", checkpoint, "--script", (t.path / "missing.lua").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--script: file '" + (t.path / "missing.lua").string() + "' does not exist"));
  r = cli({"resume", checkpoint, "--script", checkpoint});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("is a checkpoint; give the edited growth script"));
  r = cli({"resume", checkpoint, "--script", t.write("broken.lua", "cells {\n").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("broken.lua:2:") && Contains("with --script"));
  const auto veins = t.write("veins.lua", "leaf {}\ncolonisation { initial_length = 20, final_length = 24 }\n");
  r = cli({"resume", checkpoint, "--script", veins.string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err,
             Contains("is of a cell run, but --script " + veins.string() + " describes a space-colonisation run"));
  CHECK_THAT(r.err, !Contains("warning"));  // no word on its shapes first: they are beside the point
  // an obstacle over the checkpoint's cells, as a new run refuses one (it would throw them to its far side)
  const auto walled = t.write("walled.lua", std::string(kSmall) + "ball { centre = {0, 0, 0}, radius = 1 }\n");
  r = cli({"resume", checkpoint, "--script", walled.string(), "--steps", "6", "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("obstacles must start outside the cells") &&
                        Contains(walled.string() + " places it over the cells of the checkpoint's step 5"));
  CHECK(slurp(out / "checkpoint.cfck") == before);  // every refusal left it as it was
  {  // venation{} added to a run without a petiole cell: its petiole{} must come after the checkpoint's step
    std::string bare = kSmall;
    bare.erase(bare.find("petiole {"));
    const fs::path o2 = t.path / "bare";
    REQUIRE(cli({"run", t.write("bare.lua", bare).string(), "--out", o2.string(), "--quiet", "--steps", "5"}).code ==
            0);
    const auto veined = t.write("veined.lua", bare + "petiole { at = {0, -3, 0} }\nvenation { threshold = 5 }\n");
    r = cli({"resume", o2.string(), "--script", veined.string(), "--steps", "8", "--quiet"});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("veined.lua:7: venation needs a petiole cell by its first pass (step 6), and the "
                               "checkpoint's cells (step 5) have none") &&
                          Contains("give it step = 6"));
    // due after that first pass: the run would fail at it
    const auto late = t.write("late.lua", bare + "petiole { at = {0, -3, 0}, step = 7 }\nvenation { threshold = 5 }\n");
    r = cli({"resume", o2.string(), "--script", late.string(), "--steps", "8", "--quiet"});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("give it step = 6"));
    // none at all
    r = cli({"resume", o2.string(), "--script", t.write("none.lua", bare + "venation { threshold = 5 }\n").string(),
             "--steps", "8", "--quiet"});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("add petiole{at = {x, y, z}, step = 6}"));
    const auto later =
        t.write("later.lua", bare + "petiole { at = {0, -3, 0}, step = 6 }\nvenation { threshold = 5 }\n");
    r = cli({"resume", o2.string(), "--script", later.string(), "--steps", "8", "--quiet"});
    INFO(r.err);
    CHECK(r.code == 0);
  }
  // a physics value may not change on a plain resume, but may with an edited script
  r = cli({"resume", checkpoint, "--steps", "8", "--set", "cells.spring=2", "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("to change cells.spring, give it a script, the run's own or an edited copy: cellform "
                             "resume ") &&
                        Contains(" --steps 8 --set cells.spring=2 (or start a new run)"));
  {  // the command it gives does it (into another folder here, to keep this one's checkpoint for what follows)
    const std::string said = r.err, from = "edited copy: cellform ", to = " (or start a new run)";
    const std::size_t a = said.find(from) + from.size(), b = said.find(to, a);
    REQUIRE(b != std::string::npos);
    std::vector<std::string> args;
    std::istringstream words(said.substr(a, b - a));  // (no quoting: the test's paths are plain)
    for (std::string w; words >> w;) args.push_back(w);
    args.insert(args.end(), {"--out", (t.path / "suggested").string(), "--quiet"});
    const CliResult s = cli(args);
    INFO(s.err);
    CHECK(s.code == 0);
    CHECK(nlohmann::json::parse(slurp(t.path / "suggested" / "run.json"))["parameters"]["cells"]["spring"] == 2.0);
  }
  const auto edited = t.write("edited.lua", std::string(kSmall) + "-- springier\n");
  r = cli({"resume", checkpoint, "--steps", "8", "--set", "cells.spring=2", "--script", edited.string(), "--quiet"});
  CHECK(r.code == 0);
  const std::string with_edit = slurp(out / "cells.ply");
  // the same script given with --script and a --set that changes a value is that script with the value
  // changed (the way to mend a value the run's own --set gave): the same cells as the edited copy
  fs::copy_file(out / "checkpoint-step5.cfck", out / "checkpoint.cfck", fs::copy_options::overwrite_existing);
  r = cli({"resume", checkpoint, "--steps", "8", "--set", "cells.spring=2", "--script", script.string(), "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK_THAT(r.err, !Contains("plain resume"));
  CHECK(slurp(out / "cells.ply") == with_edit);
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["parameters"]["cells"]["spring"] == 2);
}

TEST_CASE(
    "resume --script: the run's --sets the edited script lacks are dropped, its run.steps applies, and "
    "changed shapes are said",
    "[cli][checkpoint]") {
  TempDir t("cli-resume-script-carry");
  const std::string rest =
      "cells { time_step = 0.2, separation = 0.05 }\n"
      "disc { radius = 3 }\n"
      "petiole { at = {0, 0, 0} }\n";
  const auto first = t.write("first.lua",
                             "local P = params { age = 4 }\n"
                             "division { max_cells = 3000, rule = function(cell)\n"
                             "  if cell.step >= 25 then return 'x' end\n"
                             "  return cell.age > P.age end }\n"
                             "run { steps = 40 }\n"
                             "output { every = 10 }\n" +
                                 rest);
  const auto renamed = t.write("renamed.lua",
                               "local P = params { min_age = 4 }\n"
                               "division { max_cells = 3000, rule = function(cell) return cell.age > P.min_age end }\n"
                               "run { steps = 50 }\n" +
                                   rest);
  const fs::path out = t.path / "out";
  const std::string checkpoint = (out / "checkpoint.cfck").string();
  CliResult r =
      cli({"run", first.string(), "--out", out.string(), "--set", "age=5", "--checkpoint-every", "10", "--quiet"});
  REQUIRE(r.code == 2);
  const std::string at20 = slurp(out / "checkpoint.cfck");
  r = cli({"resume", checkpoint, "--script", renamed.string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("the run's --set age=5 is dropped: " + renamed.string() + " has no parameter for it"));
  CHECK_THAT(r.err, !Contains("warning"));  // the same disc and petiole
  auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["overrides"].empty());
  CHECK(run["steps"]["completed"] == 50);  // the edited script changes run.steps: that applies
  // one that leaves run.steps as it was keeps the run's own target, --steps included
  const fs::path steps = t.path / "steps";
  const std::string stepped = (steps / "checkpoint.cfck").string();
  REQUIRE(cli({"run", first.string(), "--out", steps.string(), "--steps", "45", "--checkpoint-every", "10", "--quiet"})
              .code == 2);
  const std::string same_steps = slurp(renamed);
  const auto kept =
      t.write("kept.lua", same_steps.substr(0, same_steps.find("run { steps = 50 }")) + "run { steps = 40 }\n" + rest);
  r = cli({"resume", stepped, "--script", kept.string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(steps / "run.json"))["steps"]["completed"] == 45);
  // a run.steps below the checkpoint's step is refused, as --steps would be
  const auto short_run =
      t.write("short.lua", same_steps.substr(0, same_steps.find("run { steps = 50 }")) + "run { steps = 15 }\n" + rest);
  r = cli({"resume", stepped, "--script", short_run.string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("short.lua:3: run.steps = 15 is below the checkpoint's step 45"));
  // no frames asked for any more, but those of the run up to its checkpoint stay its outputs
  CHECK(run["outputs"].size() == 6);  // cells.ply, cells.obj, run.json, frames 0, 10 and 20
  CHECK(fs::exists(out / "frames/cells_000020.ply"));
  // a petiole the edited script moves is not placed again, and the resume says so
  t.write("out/checkpoint.cfck", at20);
  const auto moved = t.write("moved.lua", slurp(renamed) + "petiole { at = {1, 0, 0} }\n");
  r = cli({"resume", checkpoint, "--script", moved.string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("warning: " + moved.string() + " changes the petioles due by step 20") &&
                        Contains("start a new run for them"));
  // only the petiole that changed is named, not the script's unchanged ones
  const std::string moved_text = slurp(moved);
  const auto lines = std::count(moved_text.begin(), moved_text.end(), '\n');
  std::string named = moved.string();
  named.insert(0, 1, '(');
  named += ':' + std::to_string(lines) + ')';
  INFO(r.err);
  CHECK_THAT(r.err, Contains(named));
}

TEST_CASE(
    "a failed run's run.json is written even when the error has bytes that are not UTF-8, and the hint "
    "keeps --out and --steps",
    "[cli][checkpoint]") {
  TempDir t("cli-failed-utf8");
  const auto script = t.write("utf.lua",
                              "cells { time_step = 0.2 }\n"
                              "division { max_cells = 3000, rule = function(cell)\n"
                              "  if cell.step >= 15 then error('bad \\255 byte') end\n"
                              "  return cell.age > 4 end }\n"
                              "run { steps = 40 }\n"
                              "disc { radius = 3 }\n");
  const fs::path out = t.path / "out dir";  // a space: the hint quotes the path
  // an earlier run's frames: the failed run, which has none, leaves no empty frames/ behind
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--steps", "10", "--set", "output.every=5", "--quiet"})
              .code == 0);
  REQUIRE(fs::exists(out / "frames/cells_000005.ply"));
  CliResult r = cli({"run", script.string(), "--out", out.string(), "--checkpoint-every", "10", "--quiet"});
  REQUIRE(r.code == 2);
  CHECK_THAT(r.err, !Contains("could not be written"));
  CHECK_THAT(r.err, Contains("cellform resume '" + (out / "checkpoint.cfck").string() + "' --script "));
  CHECK_FALSE(fs::exists(out / "frames"));
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "failed");
  CHECK_THAT(run["error"].get<std::string>(), Contains("utf.lua:3: bad"));
  // resumed into another folder, it fails before a checkpoint of its own: the hint names the folder
  const std::string checkpoint = (out / "checkpoint.cfck").string(), other = (t.path / "other").string();
  r = cli({"resume", checkpoint, "--out", other, "--steps", "30", "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err,
             Contains("cellform resume '" + checkpoint + "' --script ") && Contains(" --out " + other + " --steps 30"));
  CHECK_FALSE(fs::exists(other));
}

TEST_CASE(
    "a run that diverges leaves its last good step, a run.json that says so, and goes on with an edited "
    "script",
    "[cli][checkpoint]") {
  TempDir t("cli-diverged");
  const std::string rest =
      "division { trigger = 'age', age = 6, max_cells = 300 }\n"
      "run { steps = 20 }\n"
      "disc { radius = 3 }\n";
  const auto tight = t.write("tight.lua", "cells { time_step = 0.2, max_speed = 0.001 }\n" + rest);
  const auto loose = t.write("loose.lua", "cells { time_step = 0.2 }\n" + rest);
  const fs::path out = t.path / "out";
  const std::string checkpoint = (out / "checkpoint.cfck").string();
  CliResult r = cli({"run", tight.string(), "--out", out.string(), "--quiet"});
  REQUIRE(r.code == 1);
  CHECK_THAT(r.err, Contains("the simulation diverged") &&
                        Contains("cellform resume " + checkpoint + " --script " + tight.string()) &&
                        !Contains("carry over"));  // no --set: nothing to say of them
  {  // without --quiet, to a file or pipe (no progress bar to end), no blank line before the message
    const CliResult loud = cli({"run", tight.string(), "--out", (t.path / "loud").string()});
    CHECK(loud.code == 1);
    CHECK_THAT(loud.err, Contains("\ncellform: step ") && !Contains("\n\n"));
  }
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "failed");
  CHECK_THAT(run["error"].get<std::string>(), Contains("exceeds cells.max_speed = 0.001"));
  const std::uint64_t good = run["steps"]["completed"];
  CHECK(run["steps"]["failed"] == good + 1);
  const auto saved = cellform::core::read_chunk_file(slurp(out / "checkpoint.cfck"), "CKPT", 1, "test");
  CHECK(nlohmann::json::parse(saved.chunks.at("meta"))["step"] == good);
  r = cli({"resume", checkpoint, "--script", loose.string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["steps"]["completed"] == 20);
  // a value given by --set carries over to the resume: the hint says so, and --set gives another
  const fs::path out2 = t.path / "out2";
  r = cli({"run", loose.string(), "--out", out2.string(), "--quiet", "--set", "cells.max_speed=0.001"});
  REQUIRE(r.code == 1);
  CHECK_THAT(r.err, Contains("(the run's --set values carry over: cells.max_speed=0.001; with --script, --set "
                             "NAME=VALUE gives another)"));
  r = cli({"resume", (out2 / "checkpoint.cfck").string(), "--script", loose.string(), "--quiet", "--set",
           "cells.max_speed=100"});
  INFO(r.err);
  CHECK(r.code == 0);
}

TEST_CASE(
    "the clean-up of an emptied frames/ leaves a file of that name alone, and a divergence whose "
    "checkpoint cannot be written still says it diverged",
    "[cli][checkpoint]") {
  TempDir t("cli-frames-file");
  const auto script = t.write("small.lua", kSmall);
  const fs::path out = t.path / "out";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--steps", "10", "--set", "output.every=5", "--quiet"})
              .code == 0);
  fs::remove_all(out / "frames");
  t.write("out/frames", "the user's notes");
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--steps", "3", "--quiet"}).code == 0);
  CHECK(slurp(out / "frames") == "the user's notes");
  const auto tight = t.write("tight.lua", "cells { time_step = 0.2, max_speed = 0.001 }\ndisc { radius = 3 }\n");
  const fs::path fitted = t.path / "fitted", blocked = t.path / "blocked";  // (a longer name: a larger checkpoint)
  REQUIRE(cli({"run", tight.string(), "--out", fitted.string(), "--quiet"}).code == 1);
  CliResult r;
  {
    FileSizeLimit full(fs::file_size(fitted / "checkpoint.cfck") - 1);  // a full disk
    r = cli({"run", tight.string(), "--out", blocked.string(), "--quiet"});
  }
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("the simulation diverged") && Contains("the last good one, could not be written"));
  CHECK_FALSE(fs::exists(blocked / "run.json"));
}

TEST_CASE(
    "the first periodic checkpoint is written however soon it comes, so a run failing in its first minute "
    "can go on",
    "[cli][checkpoint]") {
  TempDir t("cli-first-checkpoint");
  const auto script = t.write("early.lua",
                              "cells { time_step = 0.2, separation = 0.05 }\n"
                              "division { max_cells = 3000, rule = function(cell)\n"
                              "  if cell.step >= 25 then return 'x' end\n"
                              "  return cell.age > 4 end }\n"
                              "run { steps = 40 }\n"
                              "output { checkpoint_every = 10 }\n"  // 60 s between checkpoints by default
                              "disc { radius = 3 }\n");
  const fs::path out = t.path / "out";
  const CliResult r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
  REQUIRE(r.code == 2);
  // said with its step, which is not the last checkpoint_every asked for (a walkthrough took it for step 150)
  CHECK_THAT(r.err, Contains("(the last checkpoint is " + (out / "checkpoint.cfck").string() + ", of step 10)"));
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["steps"]["completed"] == 10);  // the first; the one due at 20 came within 60 s of it
  CHECK(run["parameters"]["output"]["checkpoint_every"] == 10);
}

TEST_CASE("resume --script copies the checkpoint it resumed only when it first replaces it, under a free name",
          "[cli][checkpoint]") {
  TempDir t("cli-resume-script-copy");
  const std::string head =
      "cells { time_step = 0.2, separation = 0.05 }\n"
      "division { max_cells = 3000, rule = function(cell)\n"
      "  if cell.step >= ";
  const std::string tail =
      " then return 'x' end\n"
      "  return cell.age > 4 end }\n"
      "run { steps = 40 }\n"
      "disc { radius = 3 }\n";
  const auto at25 = t.write("at25.lua", head + "25" + tail), at23 = t.write("at23.lua", head + "23" + tail);
  const auto fine = t.write("fine.lua", head + "1000" + tail);
  const fs::path out = t.path / "out";
  const std::string checkpoint = (out / "checkpoint.cfck").string();
  REQUIRE(cli({"run", at25.string(), "--out", out.string(), "--checkpoint-every", "10", "--quiet"}).code == 2);
  const std::string at20 = slurp(out / "checkpoint.cfck");
  // a resume that fails before its first checkpoint replaces nothing, so it copies nothing
  CliResult r = cli({"resume", checkpoint, "--script", at23.string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_FALSE(fs::exists(out / "checkpoint-step20.cfck"));
  CHECK(slurp(out / "checkpoint.cfck") == at20);
  // a name taken by something else is skipped
  fs::create_directories(out / "checkpoint-step20.cfck");
  r = cli({"resume", checkpoint, "--script", fine.string(), "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK(slurp(out / "checkpoint-step20-2.cfck") == at20);
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["script"]["replaces"][0]["checkpoint"] ==
        "checkpoint-step20-2.cfck");
  // checkpoint metadata from before the list, or a damaged list
  auto saved = cellform::core::read_chunk_file(at20, "CKPT", 1, "test");
  auto meta = nlohmann::json::parse(saved.chunks.at("meta"));
  meta["replaced_scripts"] = nullptr;
  saved.chunks["meta"] = meta.dump();
  fs::create_directories(t.path / "none");
  const auto none = t.write("none/checkpoint.cfck", cellform::core::write_chunk_file("CKPT", 1, saved.chunks));
  CHECK(cli({"resume", none.string(), "--script", fine.string(), "--quiet"}).code == 0);
  meta["replaced_scripts"] = nlohmann::json::array({nlohmann::json{{"path", 5}}});
  saved.chunks["meta"] = meta.dump();
  fs::create_directories(t.path / "bad");
  const auto bad = t.write("bad/checkpoint.cfck", cellform::core::write_chunk_file("CKPT", 1, saved.chunks));
  r = cli({"resume", bad.string(), "--script", fine.string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("corrupt (metadata 'replaced_scripts')"));
}

TEST_CASE("a colonisation resume whose leaf changed names the change, not the files or the build",
          "[cli][checkpoint]") {
  TempDir t("cli-resume-leaf");
  const std::string tail =
      " }\ncolonisation { type = 'open', kill_distance = 1, birth_distance = 4, darts = 2000, growth = 'none',"
      " initial_length = 100 }\n";
  const auto leaf = t.write("leaf.lua", "leaf { shape = 'ovate', width = 0.6" + tail);
  const auto wider = t.write("wider.lua", "leaf { shape = 'ovate', width = 0.7" + tail);
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", leaf.string(), "--out", out.string(), "--steps", "20", "--quiet"}).code == 0);
  auto r = cli({"resume", out.string(), "--script", wider.string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("grew its veins in another source domain: changed: leaf.width = 0.7 (was 0.6)") &&
                        !Contains("files changed"));
  r = cli({"resume", out.string(), "--set", "leaf.width=0.7", "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("changed: --set leaf.width=0.7"));
  CHECK(cli({"resume", out.string(), "--steps", "25", "--quiet"}).code == 0);  // the checkpoint is as it was
}

TEST_CASE("an edited script without venation{} still has the checkpoint's vein cells bound its time step",
          "[cli][checkpoint]") {
  // (review) without venation{} the vein cells' weights leave the stability bound; a checkpoint's vein cells
  // still straighten, so they count: 0.5 is stable for the general cells at rest length 0.1, not for veins
  TempDir t("cli-vein-step");
  const std::string body =
      "run { steps = 40, seed = 1 }\n"
      "division { trigger = 'neighbours', min_neighbours = 6, max_cells = 200 }\n"
      "disc { radius = 0.4 }\npetiole { at = {0, -0.4, 0} }\n";
  const auto with =
      t.write("with.lua", body + "cells { rest_length = 0.1, time_step = 0.1 }\nvenation { threshold = 5 }\n");
  const auto without = t.write("without.lua", body + "cells { rest_length = 0.1, time_step = 0.5 }\n");
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", with.string(), "--out", out.string(), "--quiet"}).code == 0);
  REQUIRE(nlohmann::json::parse(slurp(out / "run.json"))["veins"]["vein_cells"].get<int>() > 0);
  const auto r = cli({"resume", out.string(), "--script", without.string(), "--steps", "50", "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("cells.time_step 0.5 is above the stable limit") && Contains("cells.vein_cohesion"));
  // a fresh run of that script has no vein cells: accepted
  CHECK(cli({"run", without.string(), "--out", (t.path / "p").string(), "--quiet", "--steps", "2"}).code == 0);
}

TEST_CASE("a resume whose script no longer loads suggests the corrected copy's command, quoted, with the limits",
          "[cli][checkpoint]") {
  TempDir t("cli-resume-hint");
  t.write("fan.txt", "0 0\n1 1\n0 2\n-1 1\n0 0\n");
  const auto script =
      t.write("s.lua", "leaf { file = 'fan.txt' }\ncolonisation { initial_length = 20, final_length = 24 }\n");
  const fs::path out = t.path / "o dir";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "2", "--lua-memory", "64"}).code ==
          0);
  fs::remove(t.path / "fan.txt");
  const auto r = cli({"resume", out.string(), "--lua-memory", "64"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("to go on with a corrected copy: cellform resume '" + (out / "checkpoint.cfck").string() +
                             "' --script EDITED.lua --lua-memory 64)"));
}
