// Tests of the cellform command line: exit codes, help, outputs, run.json, checkpoints and resume.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <thread>

#include "app/run_internal.h"
#include "core/chunk_file.h"
#include "core/errors.h"
#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {
const char* kSmall =
    "local P = params { size = 400 }\n"
    "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.5} }\n"
    "division { trigger = 'age', age = 6, min_age = 3, probability = 0.5, max_cells = P.size }\n"
    "run { steps = 30 }\n"
    "disc { radius = 3 }\n"
    "petiole { at = {0, 0, 0} }\n";
}

TEST_CASE("help, version and usage errors", "[cli]") {
  auto r = cli({"--help"});
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("usage: cellform"));
  r = cli({"run", "--help"});
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("--set NAME=VALUE"));
  r = cli({"--version"});
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("cellform 0."));
  CHECK(cli({}).code == 2);
  r = cli({"rnu", "x.lua"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("did you mean 'run'"));
  r = cli({"run", "x.lua", "--steps", "many"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--steps takes a whole number"));
  r = cli({"run", "x.lua", "--sed", "3"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("did you mean '--seed'"));
  r = cli({"run", "x.lua", "--lua-memory", "0"});  // the range given is the range checked
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--lua-memory takes a whole number from 1 to 65536, got '0'"));
  r = cli({"run"});
  CHECK(r.code == 2);
  r = cli({"params"});
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("rest_length"));
  for (const char* cmd : {"params", "--version"}) {
    r = cli({cmd, "--bogus"});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains(std::string("cellform ") + cmd + " takes no arguments, got '--bogus'"));
  }
  // a NaN reads the same whatever its sign bit
  CHECK(cellform::core::number_text(std::nan("")) == "NaN");
  CHECK(cellform::core::number_text(-std::nan("")) == "NaN");
}

TEST_CASE("input errors exit with 2 and one clear line", "[cli]") {
  TempDir t("cli-input");
  auto r = cli({"run", (t.path / "missing.lua").string(), "--out", (t.path / "o").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("missing.lua"));
  CHECK_THAT(r.err, Contains("does not exist"));
  const auto bad = t.write("bad.lua", "cells { spring = }\n");
  r = cli({"run", bad.string(), "--out", (t.path / "o").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("bad.lua:1:"));
  CHECK_FALSE(fs::exists(t.path / "o"));  // nothing written on an input error
  const auto empty = t.write("empty.lua", "cells {}\n");
  r = cli({"run", empty.string(), "--out", (t.path / "o").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("places no cells"));
  const auto ok = t.write("ok.lua", kSmall);
  r = cli({"run", ok.string(), "--set", "sise=3", "--out", (t.path / "o").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("did you mean 'size'"));
  // --seed and run.seed take the same whole numbers: up to 2^53, where Lua's numbers are all exact
  r = cli({"run", ok.string(), "--seed", "9007199254740993", "--out", (t.path / "o").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--seed takes a whole number from 0 to 9007199254740992"));
  r = cli({"run", ok.string(), "--set", "run.seed=1e16", "--out", (t.path / "o").string()});
  CHECK(r.code == 2);
  // a parameter of a function the script calls can be set; one of a function it does not call says so
  r = cli({"run", ok.string(), "--set", "disc.radius=2", "--quiet", "--steps", "2", "--out", (t.path / "o").string()});
  CHECK(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(t.path / "o" / "run.json"))["cells"]["initial"].get<int>() < 61);
  r = cli({"run", ok.string(), "--set", "print.size=50", "--out", (t.path / "o").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("the script does not call print{...}"));
  // a petiole placed away from the form is reported at its script line, also when it appears later
  const auto far = t.write("far.lua",
                           "venation {}\nrun { steps = 5 }\ndisc { radius = 3 }\npetiole { at = {0, -3, 0} }\n"
                           "petiole { at = {50, 0, 0}, step = 2 }\n");
  r = cli({"run", far.string(), "--out", (t.path / "far").string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("far.lua:5:"));
  CHECK_THAT(r.err, Contains("from the nearest cell"));
  // veins with no petiole before the first step: named at the venation line, and no output is left
  const auto none = t.write("none.lua", "disc { radius = 3 }\nvenation {}\nrun { steps = 5 }\n");
  r = cli({"run", none.string(), "--out", (t.path / "none").string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("none.lua:2: venation needs a petiole"));
  CHECK_FALSE(fs::exists(t.path / "none"));  // nothing written on an input error
}

TEST_CASE("bad shapes, obstacle meshes and obstacles around the cells exit with 2 and their script line", "[cli]") {
  TempDir t("cli-bad-forms");
  auto run = [&](const std::string& name, const std::string& script) {
    const auto path = t.write(name, script);
    return cli({"run", path.string(), "--out", (t.path / "out").string(), "--quiet", "--steps", "2"});
  };
  // shapes too large to build: the cell limit, never a silent empty shape, a library error or a garbled count
  for (const char* shape :
       {"disc { radius = 1e300 }", "disc { radius = math.maxinteger }", "disc { radius = 1e18 }",
        "disc { radius = 1, spacing = 1e-300 }", "rectangle { width = 2, height = 2, spacing = 1e-300 }",
        "sphere { radius = 1e18 }", "sphere { radius = 1, spacing = 1e-300 }",
        "line { from = {0, 0, 0}, to = {1, 0, 0}, spacing = 1e-300 }"}) {
    INFO(shape);
    const auto r = run("big.lua", "cell { at = {5, 5, 5} }\n" + std::string(shape) + "\n");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("big.lua:2:") && Contains("more than 50 million"));
    const auto need = r.err.find("would need");  // and no negative count
    CHECK((need != std::string::npos && r.err.find('-', need) == std::string::npos));
  }
  // an ASCII STL obstacle cut in the middle of a facet
  t.write("cut.stl", "solid t\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n");
  auto r = run("cut.lua", "disc { radius = 2 }\nmesh { file = 'cut.stl' }\n");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("cut.lua:2: mesh") && Contains("cut.stl") && Contains("line 5"));
  // obstacles that start around the cells: named at their line, before the first step
  r = run("ball.lua", "disc { radius = 2 }\nball { radius = 1e9 }\n");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("ball.lua:2: ball{...}: 19 of the 19 cells") && Contains("must start outside"));
  CHECK_FALSE(fs::exists(t.path / "out"));
  r = run("ground.lua", "venation {}\ndisc { radius = 2 }\npetiole { at = {0, 0, 0} }\nground { height = 1e9 }\n");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("ground.lua:4: ground{...}"));
  // sizes and positions stay within 1e9 model units, as every script position does
  r = run("huge.lua", "disc { radius = 2 }\nball { radius = 1e300 }\n");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("huge.lua:2:") && Contains("ball.radius"));
  t.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  r = run("scaled.lua", "disc { radius = 2 }\nmesh { file = 'tri.obj', scale = 1e12 }\n");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("scaled.lua:2: mesh") && Contains("1e+09"));
  // touching obstacles and a ground below the cells are fine
  r = run("fine.lua",
          "disc { radius = 2, centre = {0, 0, 0.5} }\nground {}\nball { centre = {0, 0, 1.5}, radius = 1 }\n"
          "box { min = {-1, -1, -3}, max = {1, 1, 0.5} }\n");
  CHECK(r.code == 0);
}

TEST_CASE("a run writes outputs and a run.json that reproduces it", "[cli]") {
  TempDir t("cli-run");
  const auto script = t.write("small.lua", kSmall);
  const fs::path out = t.path / "out";
  auto r = cli({"run", script.string(), "--out", out.string(), "--quiet", "--seed", "4", "--set", "size=300"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  for (const char* f : {"cells.ply", "cells.obj", "run.json", "checkpoint.cfck"}) CHECK(fs::exists(out / f));
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["seed"] == 4);
  CHECK(run["parameters"]["run"]["seed"] == 4);  // the seed used, not the script's
  CHECK(run["steps"]["completed"] == 30);
  CHECK(run["cells"]["final"].get<int>() <= 300);
  CHECK(run["cells"]["final"].get<int>() > run["cells"]["initial"].get<int>());
  CHECK(run["parameters"]["params"]["size"] == 300.0);
  CHECK(run["parameters"]["cells"]["spring"] == 1.0);
  CHECK(run["overrides"]["size"] == "300");
  CHECK(run["script"]["hash"].get<std::string>().rfind("fnv1a64:", 0) == 0);
  // no temporary files are left behind
  for (const auto& e : fs::directory_iterator(out))
    CHECK(e.path().filename().string().find("partial") == std::string::npos);

  SECTION("the same inputs and seed give identical outputs; a re-run replaces the old outputs") {
    const fs::path out2 = t.path / "out2";
    REQUIRE(cli({"run", script.string(), "--out", out2.string(), "--quiet", "--seed", "4", "--set", "size=300",
                 "--threads", "1"})
                .code == 0);
    CHECK(slurp(out / "cells.ply") == slurp(out2 / "cells.ply"));
    CHECK(slurp(out / "cells.obj") == slurp(out2 / "cells.obj"));
    REQUIRE(cli({"run", script.string(), "--out", out2.string(), "--quiet", "--seed", "5", "--set", "size=300"}).code ==
            0);
    CHECK(slurp(out / "cells.ply") != slurp(out2 / "cells.ply"));
  }
  SECTION("frames every N steps") {
    const fs::path out3 = t.path / "out3";
    REQUIRE(cli({"run", script.string(), "--out", out3.string(), "--quiet", "--set", "output.every=10"}).code == 0);
    for (const char* f : {"frames/cells_000010.ply", "frames/cells_000020.ply", "frames/cells_000030.ply"})
      CHECK(fs::exists(out3 / f));
    // a re-run without frames removes the old frames
    REQUIRE(cli({"run", script.string(), "--out", out3.string(), "--quiet"}).code == 0);
    CHECK_FALSE(fs::exists(out3 / "frames/cells_000010.ply"));
    // frames are asked for by output.every alone; output.ply = false drops only the final cells.ply
    REQUIRE(cli({"run", script.string(), "--out", out3.string(), "--quiet", "--set", "output.every=10", "--set",
                 "output.ply=false"})
                .code == 0);
    CHECK(fs::exists(out3 / "frames/cells_000010.ply"));
    CHECK_FALSE(fs::exists(out3 / "cells.ply"));
  }
}

TEST_CASE("resume continues to the bit-identical result", "[cli][checkpoint]") {
  TempDir t("cli-resume");
  const auto script = t.write("small.lua", kSmall);
  const fs::path whole = t.path / "whole", part = t.path / "part";
  REQUIRE(cli({"run", script.string(), "--out", whole.string(), "--quiet", "--steps", "40"}).code == 0);
  REQUIRE(cli({"run", script.string(), "--out", part.string(), "--quiet", "--steps", "17"}).code == 0);
  auto r = cli({"resume", (part / "checkpoint.cfck").string(), "--steps", "40", "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(slurp(whole / "cells.ply") == slurp(part / "cells.ply"));
  const auto resumed = nlohmann::json::parse(slurp(part / "run.json"));
  CHECK(resumed["command"] == "resume");
  // the run's counts, not this command's: cells at the start of the run, as the uninterrupted run says
  CHECK(resumed["cells"] == nlohmann::json::parse(slurp(whole / "run.json"))["cells"]);
}

TEST_CASE("resume writes beside its checkpoint and keeps the frames written before it", "[cli][checkpoint]") {
  TempDir t("cli-resume-frames");
  const auto script = t.write("small.lua", std::string(kSmall) + "output { every = 5 }\n");
  const fs::path first = t.path / "first", moved = t.path / "moved";
  REQUIRE(cli({"run", script.string(), "--out", first.string(), "--quiet", "--steps", "12"}).code == 0);
  // the run's folder is moved, and another run takes its old name
  fs::rename(first, moved);
  REQUIRE(cli({"run", script.string(), "--out", first.string(), "--quiet", "--steps", "3"}).code == 0);
  const std::string other = slurp(first / "cells.ply");
  auto r = cli({"resume", (moved / "checkpoint.cfck").string(), "--steps", "20", "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(slurp(first / "cells.ply") == other);  // the other run is untouched
  const auto run = nlohmann::json::parse(slurp(moved / "run.json"));
  CHECK(run["steps"]["completed"] == 20);
  // frames 5 and 10 came before the checkpoint (step 12), 15 and 20 after: all four are the run's
  for (const char* f :
       {"frames/cells_000005.ply", "frames/cells_000010.ply", "frames/cells_000015.ply", "frames/cells_000020.ply"}) {
    INFO(f);
    CHECK(fs::exists(moved / f));
    CHECK(std::find(run["outputs"].begin(), run["outputs"].end(), f) != run["outputs"].end());
  }
  // and they are the frames of one uninterrupted run
  const fs::path whole = t.path / "whole";
  REQUIRE(cli({"run", script.string(), "--out", whole.string(), "--quiet", "--steps", "20"}).code == 0);
  CHECK(slurp(whole / "frames/cells_000005.ply") == slurp(moved / "frames/cells_000005.ply"));
  CHECK(slurp(whole / "frames/cells_000020.ply") == slurp(moved / "frames/cells_000020.ply"));
  // a checkpoint newer than the folder's run.json (a resume that was killed after a periodic checkpoint)
  // still keeps the frames that run.json lists
  const std::string old_run = slurp(moved / "run.json");  // at step 20
  REQUIRE(cli({"resume", (moved / "checkpoint.cfck").string(), "--steps", "26", "--quiet"}).code == 0);
  std::ofstream(moved / "run.json") << old_run;  // as if the resume to 26 had died before its run.json
  r = cli({"resume", (moved / "checkpoint.cfck").string(), "--steps", "30", "--quiet"});
  REQUIRE(r.code == 0);
  for (const char* f : {"frames/cells_000005.ply", "frames/cells_000020.ply", "frames/cells_000030.ply"})
    CHECK(fs::exists(moved / f));
  // a checkpoint resumed in the folder of another run (other overrides) adopts none of that run's frames
  const fs::path other_run = t.path / "other";
  REQUIRE(cli({"run", script.string(), "--out", other_run.string(), "--quiet", "--steps", "20", "--set", "size=300"})
              .code == 0);
  const auto half = cli({"run", script.string(), "--out", (t.path / "half").string(), "--quiet", "--steps", "12"});
  REQUIRE(half.code == 0);
  fs::copy_file(t.path / "half" / "checkpoint.cfck", other_run / "checkpoint.cfck",
                fs::copy_options::overwrite_existing);
  r = cli({"resume", (other_run / "checkpoint.cfck").string(), "--steps", "20", "--quiet"});
  REQUIRE(r.code == 0);
  const auto adopted = nlohmann::json::parse(slurp(other_run / "run.json"))["outputs"];
  CHECK(std::find(adopted.begin(), adopted.end(), "frames/cells_000005.ply") == adopted.end());
  CHECK_FALSE(fs::exists(other_run / "frames/cells_000005.ply"));  // the other run's, removed with it
}

TEST_CASE("resuming a finished run reports its veins as the run did", "[cli][checkpoint]") {
  TempDir t("cli-resume-veins");
  const auto script = t.write("veins.lua", std::string(kSmall) + "venation { threshold = 5 }\n");
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "30"}).code == 0);
  const auto before = nlohmann::json::parse(slurp(out / "run.json"))["veins"];
  REQUIRE(before["vein_cells"].get<int>() > 0);
  const auto r = cli({"resume", (out / "checkpoint.cfck").string(), "--quiet"});  // at its target: no step
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto after = nlohmann::json::parse(slurp(out / "run.json"))["veins"];
  CHECK(after["vein_cells"] == before["vein_cells"]);
  CHECK(after["petiole_inflow"] == before["petiole_inflow"]);
}

TEST_CASE("corrupt, foreign and truncated checkpoints are refused clearly", "[cli][checkpoint]") {
  TempDir t("cli-corrupt");
  const auto script = t.write("small.lua", kSmall);
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "5"}).code == 0);
  std::string bytes = slurp(out / "checkpoint.cfck");
  const auto truncated = t.write("truncated.cfck", bytes.substr(0, bytes.size() / 2));
  auto r = cli({"resume", truncated.string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("corrupt"));
  bytes[bytes.size() / 2] ^= 0x55;
  r = cli({"resume", t.write("flipped.cfck", bytes).string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("checksum"));
  r = cli({"resume", script.string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("not a cellform file"));
  r = cli({"resume", (t.path / "nothing.cfck").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("does not exist"));
  // well-formed files whose content is not a run: an unknown mode, an empty colonisation state
  cellform::core::ChunkFile good = cellform::core::read_chunk_file(slurp(out / "checkpoint.cfck"), "CKPT", 1, "test");
  auto meta = nlohmann::json::parse(good.chunks.at("meta"));
  meta["mode"] = "zzz";
  auto forged = good.chunks;
  forged["meta"] = meta.dump();
  r = cli({"resume", t.write("mode.cfck", cellform::core::write_chunk_file("CKPT", 1, forged)).string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("unknown run mode 'zzz'"));
  meta["mode"] = "colonisation";
  forged["meta"] = meta.dump();
  forged["colonisation"] = "";
  r = cli({"resume", t.write("empty.cfck", cellform::core::write_chunk_file("CKPT", 1, forged)).string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("empty colonisation state"));
  // a negative step would wrap round to 2^64 - 1 and run as if almost done
  meta = nlohmann::json::parse(good.chunks.at("meta"));
  meta["step"] = -1;
  forged = good.chunks;
  forged["meta"] = meta.dump();
  r = cli({"resume", t.write("negative.cfck", cellform::core::write_chunk_file("CKPT", 1, forged)).string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("corrupt") && Contains("'step' is not a whole number >= 0"));
  meta["step"] = 5;
  meta["initial_cells"] = -3;
  forged["meta"] = meta.dump();
  r = cli({"resume", t.write("negative2.cfck", cellform::core::write_chunk_file("CKPT", 1, forged)).string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("'initial_cells' is not a whole number >= 0"));
}

TEST_CASE("a commit stopped between two runs' files leaves no run.json", "[cli]") {
  TempDir t("cli-commit");
  const fs::path dir = t.path / "out", staging = t.path / "staging";
  fs::create_directories(dir / "b.txt" / "inside");  // b.txt cannot be replaced: the move fails there
  std::ofstream(dir / "a.txt") << "old a";
  std::ofstream(dir / "run.json") << R"({"outputs": ["a.txt", "b.txt", "run.json"]})";
  fs::create_directories(staging);
  for (const char* n : {"run.json", "a.txt", "b.txt"}) std::ofstream(staging / n) << "new " << n;
  using cellform::app::commit_outputs;
  CHECK_THROWS_AS(commit_outputs(staging, dir, {"run.json", "a.txt", "b.txt"}), cellform::core::FileError);
  CHECK(slurp(dir / "a.txt") == "new a.txt");  // moved before the failure
  CHECK_FALSE(fs::exists(dir / "run.json"));   // the old one does not describe the mix
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
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("is not a directory"));
  CHECK(slurp(file) == "x");
}

TEST_CASE("Ctrl-C stops cleanly with outputs and a checkpoint that resumes identically", "[cli][signal]") {
  TempDir t("cli-signal");
  const auto script = t.write("long.lua",
                              "cells { time_step = 0.2, drag = {0.8, 0.8, 0.5} }\n"
                              "division { trigger = 'none' }\n"
                              "run { steps = 1000000 }\n"
                              "disc { radius = 40 }\n"
                              "petiole { at = {0, -40, 0} }\n"
                              "venation { threshold = 20 }\n"
                              "print { min_radius = 1 }\n");
  const fs::path out = t.path / "o";
  const std::string exe = std::string(CELLFORM_BINARY_DIR) + "/bin/cellform";
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    execl(exe.c_str(), exe.c_str(), "run", script.c_str(), "--out", out.c_str(), "--quiet", "--threads", "2",
          static_cast<char*>(nullptr));
    _exit(99);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  REQUIRE(fs::exists(out / "checkpoint.cfck"));
  REQUIRE(fs::exists(out / "cells.ply"));
  CHECK(fs::exists(out / "printable.stl"));  // the Ctrl-C came before printing: the solid is an output too
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "interrupted");
  CHECK(run["print"]["parts"].get<int>() >= 1);
  const std::uint64_t stopped = run["steps"]["completed"];
  REQUIRE(stopped > 0);
  // resuming to a few steps further equals an uninterrupted run to the same step
  const std::uint64_t target = stopped + 3;
  const fs::path whole = t.path / "whole";
  REQUIRE(cli({"run", script.string(), "--out", whole.string(), "--quiet", "--steps", std::to_string(target)}).code ==
          0);
  REQUIRE(cli({"resume", (out / "checkpoint.cfck").string(), "--steps", std::to_string(target), "--quiet"}).code == 0);
  CHECK(slurp(whole / "cells.ply") == slurp(out / "cells.ply"));
}

TEST_CASE("after a first Ctrl-C, a second during the print skips only the print", "[cli][signal]") {
  TempDir t("cli-signal-print");
  const auto script = t.write("long.lua",
                              "cells { time_step = 0.2, drag = {0.8, 0.8, 0.5} }\n"
                              "division { trigger = 'none' }\n"
                              "run { steps = 1000000 }\n"
                              "disc { radius = 30 }\n"
                              "print { veins = false, shell = true }\n");  // about 4 s: closing the shell
  const fs::path out = t.path / "o", log = t.path / "err.txt";
  const std::string exe = std::string(CELLFORM_BINARY_DIR) + "/bin/cellform";
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 2);
    execl(exe.c_str(), exe.c_str(), "run", script.c_str(), "--out", out.c_str(), static_cast<char*>(nullptr));
    _exit(99);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  kill(pid, SIGINT);  // stop the steps: the outputs, the print among them, follow
  bool printing = false;
  for (int i = 0; i < 300 && !printing; ++i) {  // up to 30 s for the print to start
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    printing = slurp(log).find("thickening") != std::string::npos;
  }
  REQUIRE(printing);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  kill(pid, SIGINT);  // the second: skips the print
  int status = 0;
  waitpid(pid, &status, 0);
  INFO(slurp(log));
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  CHECK(fs::exists(out / "cells.ply"));  // the other outputs and the checkpoint are kept
  CHECK(fs::exists(out / "checkpoint.cfck"));
  CHECK_FALSE(fs::exists(out / "printable.stl"));
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["print"]["error"] == "interrupted");
}

TEST_CASE("a Ctrl-C before the first step: the print still runs, or says why it cannot; exit 130", "[cli][signal]") {
  TempDir t("cli-early-interrupt");
  struct Reset {
    ~Reset() { cellform::app::g_interrupt = false; }
  } reset;
  // a sheet (linked by a few steps) to print as a shell: printed although the resumed run stops at once
  const auto shell = t.write("shell.lua", "disc { radius = 4 }\nprint { veins = false, shell = true, size = 30 }\n");
  auto r = cli({"run", shell.string(), "--out", (t.path / "shell").string(), "--quiet", "--steps", "5"});
  REQUIRE(r.code == 0);
  fs::remove(t.path / "shell" / "printable.stl");
  cellform::app::g_interrupt = true;
  r = cli({"resume", (t.path / "shell" / "checkpoint.cfck").string(), "--quiet", "--steps", "50"});
  INFO(r.err);
  CHECK(r.code == 130);
  CHECK(fs::exists(t.path / "shell" / "printable.stl"));
  CHECK(nlohmann::json::parse(slurp(t.path / "shell" / "run.json"))["status"] == "interrupted");
  // nothing printable yet: the reason is the interrupt, and the exit code says interrupted, not failed
  for (const char* script : {"disc { radius = 4 }\npetiole { at = {0, 0, 0} }\nvenation {}\nprint {}\n",
                             "leaf { shape = 'ellipse' }\ncolonisation { type = 'open', growth = 'none', "
                             "initial_length = 30, darts = 20000 }\nprint {}\n"}) {
    const auto file = t.write("veins.lua", script);
    cellform::app::g_interrupt = true;
    r = cli({"run", file.string(), "--out", (t.path / "veins").string(), "--quiet", "--steps", "50"});
    INFO(r.err);
    CHECK(r.code == 130);
    CHECK_THAT(r.err, Contains("interrupted before anything printable grew"));
    CHECK(nlohmann::json::parse(slurp(t.path / "veins" / "run.json"))["status"] == "interrupted");
  }
}

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
    for (const auto& name : run["outputs"]) CHECK(fs::is_regular_file(out / name.get<std::string>()));
    CHECK(run["outputs"].size() >= 3);
  }
}

TEST_CASE("cells and veins are bit-identical for 1 and 2 threads", "[cli][determinism]") {
  TempDir t("cli-threads");
  // about 5,800 cells, so the parallel paths (which start above 2,048 items) really run
  const auto script = t.write("big.lua",
                              "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.5} }\n"
                              "division { trigger = 'age', age = 8, min_age = 4, probability = 0.3,\n"
                              "           direction = 'auxin', max_cells = 8000 }\n"
                              "venation { threshold = 20 }\n"
                              "run { steps = 25 }\n"
                              "disc { radius = 40 }\n"
                              "petiole { at = {0, -40, 0} }\n"
                              "petiole { at = {0, 40, 0}, step = 10 }\n");
  const fs::path one = t.path / "one", two = t.path / "two";
  REQUIRE(cli({"run", script.string(), "--out", one.string(), "--quiet", "--threads", "1"}).code == 0);
  REQUIRE(cli({"run", script.string(), "--out", two.string(), "--quiet", "--threads", "2"}).code == 0);
  CHECK(slurp(one / "cells.ply") == slurp(two / "cells.ply"));
  CHECK(slurp(one / "veins.ply") == slurp(two / "veins.ply"));
  const auto run = nlohmann::json::parse(slurp(one / "run.json"));
  CHECK(run["veins"]["vein_cells"].get<int>() > 0);
  CHECK(run["veins"]["petiole_inflow"].get<double>() > 5000);
}

TEST_CASE("print{} writes a printable solid that cellform check accepts", "[cli][print]") {
  TempDir t("cli-print");
  const auto script = t.write("print.lua",
                              "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.3} }\n"
                              "division { trigger = 'age', age = 6, min_age = 3, probability = 0.5, max_cells = 600 }\n"
                              "venation { threshold = 15 }\n"
                              "run { steps = 80 }\n"
                              "disc { radius = 4 }\n"
                              "petiole { at = {0, -4, 0} }\n"
                              "print { formats = 'stl,obj,ply,scad' }\n");
  const fs::path out = t.path / "o";
  auto r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  for (const char* f : {"printable.stl", "printable.obj", "printable.ply", "printable.scad"})
    CHECK(fs::exists(out / f));
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["print"]["parts"] == 1);
  CHECK(run["print"]["volume_mm3"].get<double>() > 0);
  for (const char* f : {"printable.stl", "printable.obj", "printable.ply"}) {
    r = cli({"check", (out / f).string()});
    INFO(f << ": " << r.out << r.err);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Contains("printable"));
  }
  r = cli({"check", (out / "printable.stl").string(), "--json"});
  const auto checked = nlohmann::json::parse(r.out);
  CHECK(checked["printable"] == true);
  // veins are raised to print.min_radius = 0.4 mm: about 0.8 mm through, less a voxel or two (0.2 mm)
  const auto& wall = checked["wall_thickness_mm"];
  INFO(wall.dump());
  CHECK(wall["p01"].get<double>() > 0.6);
  CHECK(wall["min"].get<double>() > 0.1);  // single rays at the crotch of a junction can be short
  CHECK(wall["missed"].get<std::size_t>() * 20 < wall["samples"].get<std::size_t>());

  SECTION("a format named twice is written once, and the re-run replaces the earlier outputs") {
    // 'stl, stl' made the output commit fail half way, leaving new and old files mixed
    const std::string text = slurp(script);
    t.write("print.lua", text.substr(0, text.find("print {")) + "print { formats = 'stl, stl' }\n");
    r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(fs::exists(out / "printable.stl"));
    CHECK_FALSE(fs::exists(out / "printable.obj"));  // the earlier run's, not written again
    const auto outputs = nlohmann::json::parse(slurp(out / "run.json"))["outputs"];
    CHECK(std::count(outputs.begin(), outputs.end(), "printable.stl") == 1);
  }

  SECTION("print errors name the script's parameters") {
    r = cli({"run", script.string(), "--out", out.string(), "--quiet", "--set", "print.flat_base=500"});
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("print: print.flat_base (500 mm) must be less than the height"));
    r = cli({"run", script.string(), "--out", out.string(), "--quiet", "--set", "print.max_memory=1"});
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("a smaller print.size (or print.scale)") && Contains("raise print.max_memory") &&
                          Contains("above print.min_radius"));
    CHECK_FALSE(nlohmann::json::parse(slurp(out / "run.json"))["print"].contains("base_z_mm"));  // no cut asked
  }

  SECTION("a form that falls apart is an error when one piece is required") {
    const auto two = t.write("two.lua",
                             "cells { time_step = 0.2, drag = {0.8, 0.8, 0.3} }\n"
                             "division { trigger = 'none' }\n"
                             "venation { threshold = 6 }\n"
                             "run { steps = 40 }\n"
                             "line { from = {-30, 0, 0}, to = {-20, 0, 0} }\n"
                             "line { from = {20, 0, 0}, to = {30, 0, 0} }\n"
                             "petiole { at = {-30, 0, 0} }\n"
                             "petiole { at = {30, 0, 0} }\n"
                             "print { pieces = 'one' }\n");
    r = cli({"run", two.string(), "--out", (t.path / "two").string(), "--quiet"});
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("falls apart into 2 parts"));
    CHECK(fs::exists(t.path / "two" / "checkpoint.cfck"));  // nothing else is lost
    CHECK(fs::exists(t.path / "two" / "cells.ply"));
  }
}

TEST_CASE("cellform check reports broken and unreadable meshes", "[cli][check]") {
  TempDir t("cli-check");
  // a tetrahedron with one face missing: a hole
  const auto open = t.write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n");
  auto r = cli({"check", open.string()});
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Contains("NOT printable"));
  CHECK_THAT(r.out, Contains("boundary edges 3"));
  const auto closed = t.write("closed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n");
  r = cli({"check", closed.string()});
  INFO(r.out);
  CHECK(r.code == 0);
  const auto garbage = t.write("garbage.stl", "this is not a mesh");
  r = cli({"check", garbage.string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("garbage.stl"));
  CHECK(cli({"check"}).code == 2);
  CHECK(cli({"check", (t.path / "none.stl").string()}).code == 2);
}

TEST_CASE("a checkpoint resumes from any working directory (script, files beside it and outputs stay put)",
          "[cli][checkpoint]") {
  TempDir t("cli-cwd");
  t.write("fan.txt", "0 0\n1 1\n0 2\n-1 1\n0 0\n");  // an outline file, named relative to the script
  t.write("fan.lua",
          "leaf { file = 'fan.txt' }\n"
          "colonisation { type = 'open', growth = 'none', initial_length = 30, darts = 20000 }\n");
  const fs::path before = fs::current_path();
  fs::current_path(t.path);
  const auto first = cli({"run", "fan.lua", "--steps", "3", "--quiet"});  // relative script, default out/fan
  fs::current_path("/");
  const auto resumed = cli({"resume", (t.path / "out/fan/checkpoint.cfck").string(), "--steps", "6", "--quiet"});
  fs::current_path(before);
  INFO(first.err);
  REQUIRE(first.code == 0);
  INFO(resumed.err);
  REQUIRE(resumed.code == 0);
  const auto run = nlohmann::json::parse(slurp(t.path / "out/fan/run.json"));
  CHECK(run["command"] == "resume");
  CHECK(run["steps"]["completed"] == 6);
  CHECK_FALSE(fs::exists("/out/fan"));
}

TEST_CASE("a run's --checkpoint-every is kept by its checkpoints, so a resumed run goes on with it", "[cli]") {
  TempDir t("cli-ckevery");
  const auto script = t.write("few.lua",
                              "leaf { shape = 'ellipse' }\n"
                              "colonisation { type = 'open', growth = 'none', initial_length = 200, darts = 2000 }\n");
  auto every = [](const fs::path& checkpoint) {
    const cellform::core::ChunkFile f = cellform::core::read_chunk_file(slurp(checkpoint), "CKPT", 1, "checkpoint");
    return nlohmann::json::parse(f.at("meta", "checkpoint")).at("checkpoint_every");
  };
  const fs::path a = t.path / "a", b = t.path / "b";
  REQUIRE(
      cli({"run", script.string(), "--out", a.string(), "--steps", "6", "--checkpoint-every", "2", "--quiet"}).code ==
      0);
  CHECK(every(a / "checkpoint.cfck") == 2);
  REQUIRE(cli({"resume", (a / "checkpoint.cfck").string(), "--steps", "9", "--quiet"}).code == 0);
  CHECK(every(a / "checkpoint.cfck") == 2);
  REQUIRE(
      cli({"resume", (a / "checkpoint.cfck").string(), "--steps", "12", "--checkpoint-every", "5", "--quiet"}).code ==
      0);
  CHECK(every(a / "checkpoint.cfck") == 5);
  REQUIRE(cli({"run", script.string(), "--out", b.string(), "--steps", "3", "--quiet"}).code == 0);
  CHECK(every(b / "checkpoint.cfck").is_null());  // the script's output.checkpoint_every applies
}

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
  CHECK_THAT(first.err, !Contains("checkpoint"));  // the stale file is not this run's
  const CliResult second = cli({"run", script.string(), "--out", out.string(), "--checkpoint-every", "4", "--quiet"});
  CHECK(second.code == 2);
  CHECK_THAT(second.err, Contains("(the last checkpoint is " + (out / "checkpoint.cfck").string() + ")"));
  // that checkpoint (step 8) resumes into the same error, and says it is the one resumed
  const fs::path kept = t.path / "step8.cfck";
  fs::copy_file(out / "checkpoint.cfck", kept);
  const CliResult resumed = cli({"resume", kept.string(), "--out", (t.path / "again").string(), "--quiet"});
  CHECK(resumed.code == 2);
  CHECK_THAT(resumed.err, Contains("(the last checkpoint is " + kept.string() + ", the one resumed)"));
}

TEST_CASE("resume refuses to go back in steps or to change the seed, leaving the checkpoint as it was",
          "[cli][checkpoint]") {
  TempDir t("cli-resume-back");
  const auto cells = t.write("small.lua", kSmall);
  const auto veins = t.write("few.lua",
                             "leaf { shape = 'ellipse' }\n"
                             "colonisation { type = 'open', growth = 'none', initial_length = 200, darts = 2000 }\n");
  for (const auto& script : {cells, veins}) {
    INFO(script.filename().string());
    const fs::path out = t.path / script.stem();
    REQUIRE(cli({"run", script.string(), "--out", out.string(), "--steps", "6", "--quiet"}).code == 0);
    const fs::path ck = out / "checkpoint.cfck";
    const std::string before = slurp(ck);
    const CliResult back = cli({"resume", ck.string(), "--steps", "4", "--quiet"});
    CHECK(back.code == 2);
    CHECK_THAT(back.err, Contains("is at step 6; --steps 4 would go back"));
    const CliResult seed = cli({"resume", ck.string(), "--seed", "99", "--quiet"});
    CHECK(seed.code == 2);
    CHECK_THAT(seed.err, Contains("--seed 99: a resumed run keeps the seed of"));
    CHECK(slurp(ck) == before);
    CHECK(cli({"resume", ck.string(), "--steps", "6", "--quiet"}).code == 0);  // the same step: outputs again
  }
  // a cell run's physics stay as saved; what it writes may change
  const fs::path ck = t.path / "small" / "checkpoint.cfck";
  for (const char* set : {"cells.spring=2", "size=100", "run.seed=5"}) {
    const CliResult physics = cli({"resume", ck.string(), "--set", set, "--quiet", "--steps", "8"});
    CHECK(physics.code == 2);
    CHECK_THAT(physics.err, Contains(std::string("--set ") + set) && Contains("only output.* and print.* may change"));
  }
  CHECK(cli({"resume", ck.string(), "--set", "output.obj=false", "--quiet", "--steps", "8"}).code == 0);
}

TEST_CASE("periodic checkpoints come every N steps, but not within output.checkpoint_seconds of the last", "[cli]") {
  using cellform::app::CheckpointClock;
  CheckpointClock exact(4, 0);
  CHECK_FALSE(exact.due(1));
  CHECK(exact.due(4));
  CHECK(exact.due(8));
  CHECK_FALSE(exact.due(9));
  CheckpointClock never(0, 0);
  CHECK_FALSE(never.due(0));
  CHECK_FALSE(never.due(1000));
  CheckpointClock slow(2, 30);  // nothing is due within 30 s of the start
  CHECK_FALSE(slow.due(2));
  CHECK_FALSE(slow.due(4));
  CheckpointClock timed(2, 0.001);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  CHECK_FALSE(timed.due(3));
  CHECK(timed.due(4));
}

TEST_CASE("a run removes the staging folders and checkpoint drafts of killed runs, and only those", "[cli]") {
  TempDir t("cli-stale");
  const auto script = t.write("small.lua", kSmall);
  const fs::path out = t.path / "out";
  fs::create_directories(out / ".partial-999999999");  // no such process (beyond any pid_max)
  std::ofstream(out / ".partial-999999999" / "veins.ply") << "half";
  const fs::path live = out / (".partial-" + std::to_string(::getppid()));  // a process that is running
  fs::create_directories(live);
  fs::create_directories(out / ".partial-notes");                               // not a run's
  std::ofstream(out / "checkpoint.cfck.tmp-999999999") << "half a checkpoint";  // a killed run's
  const fs::path live_tmp = out / ("checkpoint.cfck.tmp-" + std::to_string(::getppid()));
  std::ofstream(live_tmp) << "being written";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--steps", "3", "--quiet"}).code == 0);
  CHECK_FALSE(fs::exists(out / ".partial-999999999"));
  CHECK_FALSE(fs::exists(out / "checkpoint.cfck.tmp-999999999"));
  CHECK(fs::exists(live));
  CHECK(fs::exists(live_tmp));
  CHECK(fs::exists(out / ".partial-notes"));
  CHECK(fs::exists(out / "cells.ply"));
}

TEST_CASE("print with no vein grown, or no sheet to thicken, says so instead of printing a ball", "[cli][print]") {
  TempDir t("cli-noprint");
  const auto none = t.write("none.lua",
                            "run { steps = 10 }\ndisc { radius = 3 }\npetiole { at = {0, -3, 0} }\n"
                            "venation { threshold = 1e9 }\nprint {}\n");
  auto r = cli({"run", none.string(), "--out", (t.path / "a").string(), "--quiet"});
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("nothing to print yet (no vein has grown"));
  CHECK_FALSE(fs::exists(t.path / "a" / "printable.stl"));
  CHECK(fs::exists(t.path / "a" / "cells.ply"));  // the other outputs are kept
  const auto line = t.write("line.lua",
                            "run { steps = 5 }\nline { from = {0, 0, 0}, to = {5, 0, 0} }\n"
                            "print { veins = false, shell = true }\n");
  r = cli({"run", line.string(), "--out", (t.path / "b").string(), "--quiet"});
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("no sheet of triangles") && !Contains("use shell = true"));
}

TEST_CASE("a run of no steps writes the surface and prints the sheet the shapes placed", "[cli]") {
  TempDir t("cli-no-steps");
  const auto script = t.write("s0.lua",
                              "run { steps = 0 }\ndisc { radius = 3 }\n"
                              "print { veins = false, shell = true, size = 30 }\n");
  const auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  // the links the first step would make: a disc of 37 cells on a unit lattice has 54 triangles
  const std::string obj = slurp(t.path / "o" / "cells.obj");
  std::size_t faces = 0;
  for (std::size_t at = obj.find("\nf "); at != std::string::npos; at = obj.find("\nf ", at + 1)) ++faces;
  CHECK(faces == 54);
  const auto check = cli({"check", (t.path / "o" / "printable.stl").string(), "--json"});
  CHECK(nlohmann::json::parse(check.out)["printable"] == true);
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

TEST_CASE("a resume steps with the values its run was saved with, though a default changed since",
          "[cli][checkpoint]") {
  TempDir t("cli-physics");
  const auto script =
      t.write("n.lua", "division { trigger = 'neighbours' }\ndisc { radius = 3 }\nrun { steps = 10 }\n");
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "4"}).code == 0);
  cellform::core::ChunkFile saved = cellform::core::read_chunk_file(slurp(out / "checkpoint.cfck"), "CKPT", 1, "test");
  auto meta = nlohmann::json::parse(saved.chunks.at("meta"));
  REQUIRE(meta["physics"]["division"]["radius"] == 1.25);  // recorded, though the script does not set it
  // as if saved when the default was 1.5
  meta["physics"]["division"]["radius"] = 1.5;
  auto forged = saved.chunks;
  forged["meta"] = meta.dump();
  const fs::path older = t.path / "older" / "checkpoint.cfck";
  fs::create_directories(older.parent_path());
  t.write("older/checkpoint.cfck", cellform::core::write_chunk_file("CKPT", 1, forged));
  auto r = cli({"resume", older.string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto run = nlohmann::json::parse(slurp(older.parent_path() / "run.json"));
  CHECK(run["parameters"]["division"]["radius"] == 1.5);
  const auto again = nlohmann::json::parse(
      cellform::core::read_chunk_file(slurp(older), "CKPT", 1, "test").chunks.at("meta"))["physics"];
  CHECK(again["division"]["radius"] == 1.5);
  CHECK(again["division"]["trigger"] == "neighbours");
  // a checkpoint that records no values (an older cellform) resumes with today's, and says so
  meta.erase("physics");
  forged["meta"] = meta.dump();
  fs::create_directories(t.path / "oldest");
  const auto oldest = t.write("oldest/checkpoint.cfck", cellform::core::write_chunk_file("CKPT", 1, forged));
  r = cli({"resume", oldest.string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("does not record its run's parameter values"));
  // a changed value the script refuses now (division.radius beside a division.rule) is said, not fatal;
  // a value this cellform does not know is left alone
  const auto ruled = t.write("r.lua",
                             "division { rule = function(c) return c.age > 4 end, max_cells = 200 }\n"
                             "disc { radius = 3 }\nrun { steps = 10 }\n");
  REQUIRE(cli({"run", ruled.string(), "--out", (t.path / "r").string(), "--quiet", "--steps", "4"}).code == 0);
  saved = cellform::core::read_chunk_file(slurp(t.path / "r" / "checkpoint.cfck"), "CKPT", 1, "test");
  meta = nlohmann::json::parse(saved.chunks.at("meta"));
  meta["physics"]["division"]["radius"] = 1.5;
  meta["physics"]["cells"]["no_such_weight"] = 2;
  forged = saved.chunks;
  forged["meta"] = meta.dump();
  fs::create_directories(t.path / "ruled");
  const auto ruled_ck = t.write("ruled/checkpoint.cfck", cellform::core::write_chunk_file("CKPT", 1, forged));
  r = cli({"resume", ruled_ck.string(), "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("warning: the run was saved with division.radius = 1.5 (now 1.25)") &&
                        !Contains("no_such_weight"));
}

TEST_CASE("math.random in a rule gives the same cells for the same seed, after a resume too", "[cli][checkpoint]") {
  TempDir t("cli-math-random");
  const auto script =
      t.write("rnd.lua",
              "run { steps = 30, seed = 5 }\ncells { time_step = 0.15, planar = 0.6, separation = 0.05 }\n"
              "division { rule = function(c) return c.age > 3 and math.random() < 0.2 end, "
              "max_cells = 300 }\ndisc { radius = 3 }\n");
  auto run_to = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args{"run", script.string(), "--out", (t.path / name).string(), "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    REQUIRE(cli(args).code == 0);
    return slurp(t.path / name / "cells.ply");
  };
  const std::string a = run_to("a", {}), b = run_to("b", {"--threads", "2"});
  CHECK(a == b);  // Lua 5.4 seeds math.random randomly: it was different on every run
  run_to("c", {"--steps", "12"});
  REQUIRE(cli({"resume", (t.path / "c" / "checkpoint.cfck").string(), "--steps", "30", "--quiet"}).code == 0);
  CHECK(slurp(t.path / "c" / "cells.ply") == a);
  CHECK(run_to("d", {"--seed", "6"}) != a);  // and the seed matters
}
