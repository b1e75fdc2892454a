// Tests of the cellform command line: exit codes, help, outputs, run.json and Ctrl-C (printing: cli_print_test.cpp;
// check: check_test.cpp).
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "app/run_internal.h"
#include "core/errors.h"
#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

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
  // an option cut short is the one it begins (--set is nearer by spelling)
  CHECK_THAT(cli({"run", "x.lua", "--ste", "3"}).err, Contains("did you mean '--steps'"));
  CHECK_THAT(cli({"run", "x.lua", "--checkpoint", "3"}).err, Contains("did you mean '--checkpoint-every'"));
  // cellform --help run is cellform run --help
  r = cli({"--help", "run"});
  CHECK(r.code == 0);
  CHECK(r.out == cli({"run", "--help"}).out);
  CHECK(cli({"help", "check"}).out == cli({"check", "--help"}).out);
  const auto unknown = cli({"help", "foo"});  // it gave the general help, exit 0
  CHECK(unknown.code == 2);
  CHECK_THAT(unknown.err, Contains("no help for 'foo'"));
  CHECK_THAT(cli({"help", "run", "--x"}).err, Contains("cellform help takes one COMMAND") && Contains("got '--x' too"));
  // --option=value is --option value (it was an unknown option '--steps=many')
  r = cli({"run", "x.lua", "--steps=many"});
  CHECK_THAT(r.err, Contains("--steps takes a whole number") && Contains("got 'many'"));
  r = cli({"run", "x.lua", "--quiet=yes"});  // a flag takes no value
  CHECK_THAT(r.err, Contains("--quiet takes no value, got '--quiet=yes'"));
  r = cli({"run", "x.lua", "--out=--steps"});  // after '=' a value, whatever it looks like (here: no x.lua)
  CHECK_THAT(r.err, !Contains("needs a value"));
  r = cli({"run", "x.lua", "--lua-memory", "0"});  // the range given is the range checked
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--lua-memory takes a whole number from 1 to 65536, got '0'"));
  // an option where a value belongs: the value was forgotten (it took "--quiet" as the script before)
  r = cli({"resume", "o/checkpoint.cfck", "--script", "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err,
             Contains("--script needs a value, got the option --quiet (a file or folder so named is ./--quiet)"));
  for (const char* option : {"--out", "--set", "--seed"}) {
    r = cli({"run", "x.lua", option, "-q"});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains(std::string(option) + " needs a value, got the option -q"));
  }
  r = cli({"run"});
  CHECK(r.code == 2);
  r = cli({"run", "x.lua", "--set", "scale=0.1", "--set", "scale=0.2"});  // the last wins, and it is said
  CHECK_THAT(r.err, Contains("--set scale is given twice; the last, 0.2, is used (not 0.1)"));
  // another option given twice with two values is refused: the last one won unsaid
  r = cli({"run", "x.lua", "--seed", "3", "--steps", "10", "--seed", "4"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--seed is given twice (3 and 4); give it once"));
  r = cli({"run", "x.lua", "--out", "a", "--out", "b"});
  CHECK_THAT(r.err, Contains("--out is given twice (a and b)"));
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
  CHECK_THAT(r.err, Contains("from the nearest cell, at {"));  // where a petiole could go instead
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
  // shapes far beyond division.max_cells are refused before they are built (a disc of radius 3000 was
  // 32 million cells, 2 GB and 13 s before the refusal); near the limit the exact count decides
  for (const char* shapes :
       {"disc { radius = 2 }\ndisc { radius = 3000 }", "disc { radius = 2 }\nsphere { radius = 1000 }",
        "disc { radius = 2 }\nrectangle { width = 3000, height = 3000 }",
        "disc { radius = 2 }\nline { from = {0, 0, 0}, to = {1e7, 0, 0} }"}) {
    INFO(shapes);
    const auto r = run("many.lua", std::string(shapes) + "\n");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("many.lua:2:") && Contains("the initial shapes would make about") &&
                          Contains("more than division.max_cells = 100000"));
  }
  {
    const auto r = run("limit.lua", "division { max_cells = 100 }\ndisc { radius = 5.6 }\n");  // about 115
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("limit.lua:2: disc: the initial shapes make 1") &&
                          Contains("cells, more than division.max_cells = 100, which also caps the cells placed "
                                   "(raise it, or place fewer)"));
  }
  {  // a shape whose cells would not fit in memory (32 million filled 22 GB of a 24 GB machine), before it is built
    const auto r =
        run("memory.lua", "run { max_memory = 100 }\ndivision { max_cells = 1000000 }\ndisc { radius = 300 }\n");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("memory.lua:3: disc: the initial shapes would make about 32") &&
                          Contains("cells, which take about 229 MB at the peak, more than run.max_memory = 100 MB"));
    // a max_cells the budget cannot hold is noted before the steps (the run may stop before it)
    const auto room = t.write("room.lua",
                              "run { max_memory = 100 }\ndivision { max_cells = 1000000 }\n"
                              "disc { radius = 3 }\n");
    const auto small = cli({"run", room.string(), "--out", (t.path / "room").string(), "--quiet", "--steps", "1"});
    CHECK(small.code == 0);
    CHECK_THAT(small.err, Contains("note: division.max_cells = 1000000 cells would take about 700 MB at the peak, "
                                   "more than run.max_memory = 100 MB"));
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
  // a mesh of degenerate triangles only is no wall: refused, as volume{file} and surface{file} refuse it
  t.write("flat.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n");
  r = run("flat.lua", "disc { radius = 2 }\nmesh { file = 'flat.obj' }\n");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("flat.lua:2: mesh: every triangle of flat.obj is degenerate"));
  // a disc laid on a floor mesh is on neither side of it: refused at the mesh's line (it fell through)
  t.write("floor.obj", "v -9 -9 0\nv 9 -9 0\nv 9 9 0\nv -9 9 0\nf 1 2 3 4\n");
  r = run("floor.lua", "disc { radius = 2 }\nmesh { file = 'floor.obj' }\n");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("floor.lua:2: mesh{...}: 19 of the 19 cells lie on its surface"));
  CHECK(run("above.lua", "disc { radius = 2, centre = {0, 0, 0.1} }\nmesh { file = 'floor.obj' }\n").code == 0);
  // a pipe or a device as the mesh: refused, not read for ever (its fingerprint was taken before load_mesh looked)
  REQUIRE(::mkfifo((t.path / "fifo.stl").c_str(), 0600) == 0);
  fs::create_symlink("/dev/zero", t.path / "zero.obj");
  for (const char* file : {"fifo.stl", "zero.obj"}) {
    r = run("pipe.lua", "disc { radius = 2 }\nmesh { file = '" + std::string(file) + "' }\n");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("pipe.lua:2: mesh") && Contains(file) && Contains("is not a regular file"));
  }
  // touching obstacles and a ground below the cells are fine
  r = run("fine.lua",
          "disc { radius = 2, centre = {0, 0, 0.5} }\nground {}\nball { centre = {0, 0, 1.5}, radius = 1 }\n"
          "box { min = {-1, -1, -3}, max = {1, 1, 0.5} }\n");
  CHECK(r.code == 0);
}

TEST_CASE("run.json names the script by its full path when it was given relative to the folder run from", "[cli]") {
  TempDir t("cli-relative");
  t.write("small.lua", kSmall);
  const fs::path before = fs::current_path();
  fs::current_path(t.path);
  const auto r = cli({"run", "small.lua", "--out", "o", "--quiet", "--steps", "3"});
  fs::current_path(before);
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto run = nlohmann::json::parse(slurp(t.path / "o" / "run.json"));
  CHECK(fs::equivalent(run["script"]["path"].get<std::string>(), t.path / "small.lua"));
  CHECK(fs::path(run["script"]["path"].get<std::string>()).is_absolute());
}

TEST_CASE("a step limit given twice (by --steps and by a --set of another value) is refused", "[cli]") {
  // --steps would win unsaid, and run.json's overrides would show the --set as in force; a later plain resume
  // keeps the checkpoint's limit, not the --set's
  TempDir t("cli-two-limits");
  const auto cells = t.write("cells.lua", kSmall), veins = t.write("veins.lua", kSmallVeins);
  const std::string out = (t.path / "o").string(), vout = (t.path / "v").string();
  auto refused = [](const CliResult& r, const std::string& set) {
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("--steps 4 and --set " + set + " both give the step limit; give one of them"));
    CHECK(r.err.find('\n') == r.err.size() - 1);  // one line
  };
  for (const char* v : {"6", "+6", " 6", "6e0"})  // read as every --set of a number is
    refused(cli({"run", cells.string(), "--out", out, "--steps", "4", "--set", std::string("run.steps=") + v}),
            std::string("run.steps=") + v);
  refused(cli({"run", veins.string(), "--out", vout, "--steps", "4", "--set", "colonisation.max_steps=6"}),
          "colonisation.max_steps=6");
  CHECK_FALSE(fs::exists(out));
  // the same value twice is one limit; a cell run's colonisation.max_steps is refused for what it is
  REQUIRE(cli({"run", cells.string(), "--out", out, "--steps", "4", "--set", "run.steps= 4.0", "-q"}).code == 0);
  REQUIRE(cli({"run", veins.string(), "--out", vout, "--steps", "4", "--set", "colonisation.max_steps=4", "-q"}).code ==
          0);
  const auto other = cli({"run", cells.string(), "--out", out, "--steps", "4", "--set", "colonisation.max_steps=6"});
  CHECK_THAT(other.err, !Contains("both give the step limit") && Contains("colonisation"));
  // resumes: a colonisation's limit, and a cell run's run.steps under --script (a plain resume refuses it itself)
  refused(cli({"resume", vout, "--steps", "4", "--set", "colonisation.max_steps=6"}), "colonisation.max_steps=6");
  refused(cli({"resume", out, "--script", cells.string(), "--steps", "4", "--set", "run.steps=6"}), "run.steps=6");
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
  CHECK(run["threads"] == 0);                    // as asked: all cores, which were
  CHECK(run["threads_used"] == std::max(1u, std::thread::hardware_concurrency()));
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
    // (given as --option=value)
    REQUIRE(
        cli({"run", script.string(), "--out=" + out2.string(), "--quiet", "--seed=4", "--set=size=300", "--threads=1"})
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
    // the first frame is of the cells as placed, with their surface; writing frames changes nothing else
    const fs::path out4 = t.path / "out4";
    REQUIRE(cli({"run", script.string(), "--out", out4.string(), "--quiet", "--seed", "4", "--set", "size=300", "--set",
                 "output.every=10"})
                .code == 0);
    CHECK(slurp(out4 / "cells.ply") == slurp(out / "cells.ply"));
    const std::string first = slurp(out4 / "frames/cells_000000.ply");
    const std::size_t faces = first.find("element face ");
    REQUIRE(faces != std::string::npos);
    CHECK(std::stoul(first.substr(faces + 13)) > 0);
    CHECK(first.find("element vertex " + std::to_string(run["cells"]["initial"].get<int>()) + "\n") !=
          std::string::npos);
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
  const pid_t pid = spawn_cellform({"run", script.string(), "--out", out.string(), "--quiet", "--threads", "2"});
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  kill(pid, SIGINT);
  int signal = 0;
  CHECK(wait_exit(pid, &signal) == 130);
  CHECK(signal == SIGINT);  // ends by SIGINT after its outputs, so a shell loop of runs stops too
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

TEST_CASE("a closed terminal (SIGHUP) stops like Ctrl-C; a closed stderr pipe does not stop the run", "[cli][signal]") {
  TempDir t("cli-hup");
  const auto script =
      t.write("long.lua", "division { trigger = 'none' }\nrun { steps = 1000000 }\ndisc { radius = 20 }\n");
  const fs::path out = t.path / "o";
  pid_t pid = spawn_cellform({"run", script.string(), "--out", out.string(), "--quiet"});
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  kill(pid, SIGHUP);
  kill(pid, SIGHUP);  // a hang-up can come twice: still one orderly stop
  CHECK(wait_exit(pid) == 130);
  CHECK(fs::exists(out / "checkpoint.cfck"));
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["status"] == "interrupted");
  // progress lines into a pipe nobody reads any more (cellform run ... 2>&1 | head -c 10)
  int fds[2];
  REQUIRE(pipe(fds) == 0);
  close(fds[0]);
  const fs::path piped = t.path / "p";
  pid = spawn_cellform({"run", script.string(), "--out", piped.string(), "--steps", "50"}, fds[1]);
  REQUIRE(pid > 0);
  close(fds[1]);
  CHECK(wait_exit(pid) == 0);  // not killed by SIGPIPE (that would be 141)
  CHECK(fs::exists(piped / "cells.ply"));
  CHECK(fs::exists(piped / "run.json"));
}

TEST_CASE("Ctrl-C while a script is read stops it there", "[cli][signal]") {
  TempDir t("cli-int-load");
  const auto script = t.write("loop.lua", "while true do end\n");
  const fs::path out = t.path / "o", log = t.path / "err.txt";
  const pid_t pid = spawn_cellform_logged(
      {"run", script.string(), "--out", out.string(), "--quiet", "--lua-instructions", "18446744073709551615"}, log);
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  kill(pid, SIGINT);
  CHECK(wait_exit(pid) == 130);
  CHECK_FALSE(fs::exists(out));
  // said as what happens: no steps, no outputs to wait for
  CHECK_THAT(slurp(log), Contains("stopping the script being read") && !Contains("the steps stop"));
  // a hang-up too (it said "the steps stop ... a checkpoint is written", then that nothing was written)
  const fs::path log2 = t.path / "err2.txt";
  const pid_t hup = spawn_cellform_logged(
      {"run", script.string(), "--out", out.string(), "--quiet", "--lua-instructions", "18446744073709551615"}, log2);
  REQUIRE(hup > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  kill(hup, SIGHUP);
  CHECK(wait_exit(hup) == 130);
  CHECK_FALSE(fs::exists(out));
  CHECK_THAT(slurp(log2), Contains("hang-up: stopping the script being read") && !Contains("the steps stop"));
}

TEST_CASE("after a first Ctrl-C, a second during the print skips only the print", "[cli][signal]") {
  TempDir t("cli-signal-print");
  const auto script = t.write("long.lua", slow_print_script("1000000"));
  const fs::path out = t.path / "o", log = t.path / "err.txt";
  const pid_t pid = spawn_cellform_logged({"run", script.string(), "--out", out.string()}, log);
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  kill(pid, SIGINT);                              // stop the steps: the outputs, the print among them, follow
  REQUIRE(wait_for_text(log, "thickening", 30));  // the print has started
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  kill_from_another_process(pid, SIGINT);  // the second: skips the print
  const int code = wait_exit(pid);
  INFO(slurp(log));
  CHECK(code == 130);
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

namespace {
/// The time `s` seconds after the epoch of CheckpointClock's clock (its tests give the times).
cellform::app::CheckpointClock::Clock::time_point at(double s) {
  using Clock = cellform::app::CheckpointClock::Clock;
  return Clock::time_point{} + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}
}  // namespace

TEST_CASE("periodic checkpoints come every N steps, but not within output.checkpoint_seconds of the last", "[cli]") {
  using cellform::app::CheckpointClock;
  const CheckpointClock::Clock::time_point t0{};
  CheckpointClock exact(4, 0, 0, t0);
  CHECK_FALSE(exact.due(1, at(1)));
  CHECK(exact.due(4, at(2)));
  CHECK(exact.due(8, at(3)));
  CHECK_FALSE(exact.due(9, at(1e6)));  // no minutes bound: none between
  CheckpointClock never(0, 0, 10, t0);
  CHECK_FALSE(never.due(0, at(0)));
  CHECK_FALSE(never.due(1000, at(1e6)));  // checkpoint_every = 0: only at the end, whatever the time
  CheckpointClock slow(2, 30, 0, t0);     // the first is written (a run failing early keeps it), then none within 30 s
  CHECK(slow.due(2, at(0)));
  CHECK_FALSE(slow.due(4, at(10)));
  CHECK_FALSE(slow.due(6, at(29.9)));
  CHECK(slow.due(8, at(30)));
}

TEST_CASE("a checkpoint is also due output.checkpoint_minutes after the last one, at any step", "[cli]") {
  // a rule failing at step 999 of a run checkpointed every 1,000 steps lost every step before it
  using cellform::app::CheckpointClock;
  const CheckpointClock::Clock::time_point t0{};
  CheckpointClock c(1000, 60, 10, t0);
  CHECK_FALSE(c.due(1, at(10)));
  CHECK_FALSE(c.due(7, at(599)));
  CHECK(c.due(8, at(600)));  // ten minutes after the start
  CHECK_FALSE(c.due(9, at(601)));
  CHECK_FALSE(c.due(1000, at(620)));  // the step's own, within checkpoint_seconds of the last: skipped
  CHECK(c.due(2000, at(700)));
  CHECK_FALSE(c.due(2001, at(1299)));
  CHECK(c.due(2002, at(1300)));                // ten minutes after the last
  CheckpointClock sparse(1000, 3600, 10, t0);  // none within an hour of the last, whatever the minutes say
  CHECK_FALSE(sparse.due(5, at(600)));
  CHECK(sparse.due(6, at(3600)));
  // the veins grown on a sheet go on from the sheet's last checkpoint (nine minutes of sheet, then one of veins)
  CheckpointClock sheet(1000, 60, 10, t0);
  CHECK(sheet.due(1000, at(60)));
  CHECK(sheet.last() == at(60));
  CheckpointClock veins(1000, 60, 10, sheet.last());
  CHECK_FALSE(veins.due(1, at(659)));
  CHECK(veins.due(2, at(660)));
}

TEST_CASE("control bytes from a damaged file reach the terminal escaped", "[cli]") {
  TempDir t("cli-escape");
  const auto stl = t.write("bad.stl", "solid x\nfacet \x1b[2J normal 0 0 1\n");
  const fs::path log = t.path / "err.txt";
  const pid_t pid = spawn_cellform_logged({"check", stl.string()}, log);
  REQUIRE(pid > 0);
  CHECK(exit_within(pid, 20) == 2);
  const std::string said = slurp(log);
  CHECK_THAT(said, Contains("bad.stl") && Contains("facet \\x1b[2J normal"));
  CHECK(said.find('\x1b') == std::string::npos);
}

TEST_CASE("option values just past their ranges are refused", "[cli]") {
  auto r = cli({"run", "x.lua", "--threads", "257"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--threads takes a whole number from 0 to 256, got '257'"));
  r = cli({"check", "x.stl", "--min-wall", "0"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--min-wall must be a thickness > 0"));
  r = cli({"run", "x.lua", "--set", "=5"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--set takes NAME=VALUE, got '=5'"));
}
