// Tests of the cellform command line for space-colonisation runs (app/run_colonisation.cpp): outputs,
// 3-D domains, resume, step and node limits.
#include <signal.h>

#include <array>
#include <catch2/catch.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "app/progress.h"
#include "app/run_internal.h"
#include "core/chunk_file.h"
#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("a colonisation that never places a source says so", "[cli][colonisation]") {
  TempDir t("cli-nosource");
  // so few darts that none lands: the run ends with only the seed node, and a warning says why
  const auto sparse =
      t.write("sparse.lua", "leaf {}\ncolonisation { darts = 1e-6, initial_length = 20, final_length = 24 }\n");
  auto r = cli({"run", sparse.string(), "--out", (t.path / "o").string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("no auxin source was placed"));
  CHECK_THAT(r.err, Contains("colonisation.darts"));
  // a box smaller than the birth distance round its seed: every dart falls within it, which more darts or
  // steps would not change
  const auto small =
      t.write("small.lua", "volume { box = { min = {0, 0, 0}, max = {3, 3, 3} } }\ncolonisation { darts = 20000 }\n");
  r = cli({"run", small.string(), "--out", (t.path / "s").string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("darts fell within the birth distances: lower colonisation.birth_distance") &&
                        !Contains("more steps") && !Contains("raise colonisation.darts"));
  // marginal growth throws its darts at the start, b_s apart: with b_s = 60 over a blade 40 long, none made a
  // source in it (it said that no dart was thrown, to raise the darts)
  const auto wide = t.write("wide.lua",
                            "leaf {}\ncolonisation { birth_distance = 60, darts = 20000, initial_length "
                            "= 30, final_length = 40 }\n");
  r = cli({"run", wide.string(), "--out", (t.path / "w").string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("darts thrown over the grown blade's box at the start (marginal growth) made a source "
                             "in the blade: lower colonisation.birth_distance (it is 60)") &&
                        !Contains("raise colonisation.darts"));
  // a run that does place sources gives no such warning (marginal growth reveals sources only while the
  // blade grows, here two steps: rho x 10^6 = 20000 puts about 12 darts into the 24 x 12 box)
  const auto dense =
      t.write("dense.lua", "leaf {}\ncolonisation { darts = 20000, initial_length = 20, final_length = 24 }\n");
  r = cli({"run", dense.string(), "--out", (t.path / "d").string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK(r.err.find("no auxin source") == std::string::npos);
  CHECK(r.err.find("no vein grew") == std::string::npos);
  // sources placed, but all within the kill distance when they came: said, naming both distances
  const auto reached = t.write("reached.lua",
                               "leaf { shape = 'ovate' }\ncolonisation { type = 'closed', growth = 'none', "
                               "initial_length = 60, darts = 2000, kill_distance = 1000 }\n");
  r = cli({"run", reached.string(), "--out", (t.path / "k").string(), "--quiet"});
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("auxin sources were placed, but no vein grew") &&
                        Contains("colonisation.kill_distance (1000)") && Contains("vein_birth_distance, 10,"));
  CHECK(nlohmann::json::parse(slurp(t.path / "k" / "run.json"))["status"] == "complete");
  // a parameter only the steps can find wrong is named with the line of colonisation{...}
  const auto flood = t.write("flood.lua",
                             "leaf { shape = 'ellipse' }\n"
                             "colonisation { type = 'open', growth = 'isogonic', darts = 1e12 }\n");
  r = cli({"run", flood.string(), "--out", (t.path / "f").string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("flood.lua:2: colonisation.darts: "));
  CHECK_FALSE(fs::exists(t.path / "f"));  // nothing written: no empty folder left
}

TEST_CASE("3-D space colonisation: veins in a volume and on a grown cell sheet", "[cli][colonisation]") {
  TempDir t("cli-col3d");
  SECTION("a ball, closed veins, printed as one piece") {
    const auto script =
        t.write("ball.lua",
                "volume { ball = { centre = {0, 0, 6}, radius = 6 } }\n"
                "colonisation { type = 'closed', kill_distance = 1.5, birth_distance = 3, darts = 3000 }\n"
                "print { pieces = 'one', size = 40 }\n");
    const fs::path out = t.path / "ball";
    auto r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto run = nlohmann::json::parse(slurp(out / "run.json"));
    CHECK(run["domain"] == "ball");
    CHECK((run["status"] == "complete" || run["status"] == "stalled"));
    CHECK(run["veins"]["loops"].get<int>() > 0);
    CHECK(run["print"]["parts"] == 1);
    CHECK(!fs::exists(out / "veins.svg"));  // no plane to draw a 3-D pattern in
    CHECK(fs::file_size(out / "veins.ply") > 0);
    r = cli({"check", (out / "printable.stl").string(), "--json"});
    CHECK(nlohmann::json::parse(r.out)["printable"] == true);
    // same result with more threads
    REQUIRE(cli({"run", script.string(), "--out", (t.path / "ball2").string(), "--quiet", "--threads", "2"}).code == 0);
    CHECK(slurp(out / "veins.ply") == slurp(t.path / "ball2" / "veins.ply"));
  }
  SECTION("surface{cells = true}: the cells grow first, the veins grow on their sheet") {
    const auto script =
        t.write("sheet.lua",
                "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.3} }\n"
                "division { trigger = 'age', age = 6, min_age = 3, probability = 0.5, max_cells = 400 }\n"
                "run { steps = 60 }\n"
                "disc { radius = 4 }\n"
                "petiole { at = {0, -4, 0} }\n"
                "surface { cells = true }\n"
                "colonisation { kill_distance = 1, birth_distance = 2, darts = 20000 }\n"
                "print { shell = true, size = 30 }\n");
    const fs::path out = t.path / "sheet";
    auto r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto run = nlohmann::json::parse(slurp(out / "run.json"));
    CHECK(run["domain"] == "surface");
    CHECK(run["parameters"]["division"]["max_cells"] == 400);  // the sheet's, which a colonisation alone leaves out
    CHECK(run["cells"]["final"].get<int>() > run["cells"]["initial"].get<int>());
    CHECK(run["timings"]["sheet_s"].get<double>() > 0);  // the cells' time, besides the veins' simulation_s
    CHECK(run["veins"]["nodes"].get<int>() > 10);
    CHECK(run["print"]["shell_triangles"].get<int>() > 0);
    CHECK(fs::file_size(out / "cells.ply") > 0);
    CHECK(fs::file_size(out / "printable.stl") > 0);
    // the checkpoint keeps the grown sheet: resuming does not grow the cells again
    const std::string cells = slurp(out / "cells.ply"), veins = slurp(out / "veins.ply");
    r = cli({"resume", (out / "checkpoint.cfck").string()});
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, !Contains("growing the cell sheet") && Contains("resuming veins"));
    CHECK(slurp(out / "cells.ply") == cells);
    CHECK(slurp(out / "veins.ply") == veins);
  }
  SECTION("a print that fails makes the status 'print failed', not 'complete'") {
    const auto two =
        t.write("two.lua",
                "volume { box = { min = {0, 0, 0}, max = {40, 10, 10} }, seeds = {{1, 5, 5}, {39, 5, 5}} }\n"
                "colonisation { type = 'open', kill_distance = 1, birth_distance = 30, darts = 1e-9 }\n"
                "print { pieces = 'one', size = 40 }\n");
    const auto r = cli({"run", two.string(), "--out", (t.path / "two").string(), "--quiet"});
    INFO(r.err);
    CHECK(r.code == 1);
    const auto run = nlohmann::json::parse(slurp(t.path / "two" / "run.json"));
    CHECK(run["status"] == "print failed");
    // (nothing grew to print: other print.* values would not help, so no hint that they would)
    CHECK_THAT(r.err, Contains("veins done, but the print failed") &&
                          !Contains("to print again with other print.* values: cellform resume "));
    // a checkpoint that cannot be written is not a failed print
    const auto plain = t.write("plain.lua",
                               "volume { box = { min = {0, 0, 0}, max = {10, 10, 10} } }\n"
                               "colonisation { type = 'open', kill_distance = 1, birth_distance = 3, darts = 3000 }\n");
    REQUIRE(cli({"run", plain.string(), "--out", (t.path / "fitted").string(), "--quiet"}).code == 0);
    CliResult b;
    {
      FileSizeLimit full(fs::file_size(t.path / "fitted" / "checkpoint.cfck") - 1);  // a full disk
      b = cli({"run", plain.string(), "--out", (t.path / "blocked").string(), "--quiet"});
    }
    CHECK(b.code == 1);
    CHECK_THAT(b.err, Contains("checkpoint.cfck"));
    CHECK_THAT(b.err, !Contains("print failed"));
    CHECK(nlohmann::json::parse(slurp(t.path / "blocked" / "run.json"))["status"] != "print failed");
  }
  SECTION("bad domains are input errors") {
    const auto bad = t.write("bad.lua",
                             "volume { box = { min = {0, 0, 0}, max = {5, 5, 5} }, seeds = {{9, 9, 9}} }\n"
                             "colonisation {}\n");
    const auto r = cli({"run", bad.string(), "--out", (t.path / "bad").string(), "--quiet"});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("bad.lua:1:") && Contains("volume.seeds[1]"));
  }
  SECTION("a sheet with no seed and no petiole is refused before the cells grow") {
    // it was said only after the whole growth (here a million steps)
    const auto bare = t.write("bare.lua",
                              "run { steps = 1000000 }\n"
                              "disc { radius = 4 }\n"
                              "surface { cells = true }\n"
                              "colonisation {}\n");
    const auto r = cli({"run", bare.string(), "--out", (t.path / "bare").string()});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("surface{cells = true} needs seeds") && !Contains("growing the cell sheet"));
    // its only petiole due after the sheet's last step: the same, at the petiole's line
    const auto late = t.write("late.lua",
                              "run { steps = 1000000 }\n"
                              "disc { radius = 4 }\n"
                              "petiole { at = {0, -4, 0}, step = 2000000 }\n"
                              "surface { cells = true }\n"
                              "colonisation {}\n");
    const auto l = cli({"run", late.string(), "--out", (t.path / "late").string()});
    CHECK(l.code == 2);
    CHECK_THAT(l.err, Contains("late.lua:3: surface{cells = true} starts its veins at the petiole cells, but the first "
                               "petiole is due at step 2000000, after the sheet's last step (1000000)") &&
                          !Contains("growing the cell sheet"));
    CHECK_FALSE(fs::exists(t.path / "late"));
  }
}

TEST_CASE("space colonisation resumes to the bit-identical veins, in a leaf and in a volume", "[cli][checkpoint]") {
  TempDir t("cli-col-resume");
  const std::string leaf =
      "run { seed = 3 }\n"
      "leaf { shape = 'ovate', width = 0.6 }\n"
      "colonisation { type = 'closed', kill_distance = 1, birth_distance = 3, growth = 'marginal',\n"
      "  initial_length = 15, final_length = 50, length_step = 1, darts = 3000 }\n";
  const std::string volume =
      "run { seed = 4 }\n"
      "volume { ball = { centre = {0, 0, 6}, radius = 6 } }\n"
      "colonisation { type = 'open', kill_distance = 1, birth_distance = 2.5, darts = 3000 }\n";
  for (const auto& [name, source] : {std::pair{"leaf", leaf}, std::pair{"ball", volume}}) {
    INFO(name);
    const auto script = t.write(std::string(name) + ".lua", source);
    const fs::path whole = t.path / (std::string(name) + "-whole"), part = t.path / (std::string(name) + "-part");
    auto r = cli({"run", script.string(), "--out", whole.string(), "--quiet"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto full = nlohmann::json::parse(slurp(whole / "run.json"));
    const int steps = full["steps"]["completed"].get<int>();
    REQUIRE(steps > 20);
    CHECK(fs::exists(whole / "checkpoint.cfck"));
    CHECK(full["checkpoint"] == "checkpoint.cfck");
    // stopped part way (as Ctrl-C would), with checkpoints every 4 steps on the way
    r = cli({"run", script.string(), "--out", part.string(), "--quiet", "--steps", "13", "--checkpoint-every", "4"});
    REQUIRE(r.code == 0);
    CHECK(nlohmann::json::parse(slurp(part / "run.json"))["steps"]["completed"] == 13);
    CHECK(slurp(whole / "veins.ply") != slurp(part / "veins.ply"));
    r = cli({"resume", (part / "checkpoint.cfck").string(), "--steps", "100000", "--quiet", "--threads", "2"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(slurp(whole / "veins.ply") == slurp(part / "veins.ply"));
    CHECK(slurp(whole / "veins.obj") == slurp(part / "veins.obj"));
    const auto resumed = nlohmann::json::parse(slurp(part / "run.json"));
    CHECK(resumed["command"] == "resume");
    CHECK(resumed["steps"]["first"] == 13);
    CHECK(resumed["steps"]["completed"] == steps);
    // resuming the finished run changes nothing
    r = cli({"resume", (whole / "checkpoint.cfck").string(), "--quiet"});
    REQUIRE(r.code == 0);
    CHECK(nlohmann::json::parse(slurp(whole / "run.json"))["steps"]["completed"] == steps);
  }
  // refused: a damaged checkpoint, and parameters other than those it was grown with
  const fs::path out = t.path / "ball-part";
  std::string bytes = slurp(out / "checkpoint.cfck");
  bytes[bytes.size() / 2] ^= 0x55;
  auto r = cli({"resume", t.write("flipped.cfck", bytes).string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("checksum"));
  // (the widths, computed at the end, may change: not named)
  r = cli({"resume", (out / "checkpoint.cfck").string(), "--set", "colonisation.kill_distance=2", "--set",
           "colonisation.node_flow=0.5", "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("continues with the parameters it was saved with, and this resume "
                             "changes them: --set colonisation.kill_distance=2. Only the thread count, ") &&
                        Contains("; start a new run for other values") && !Contains("--set colonisation.node_flow"));
  // a path that reads like the message itself is quoted whole (the message was once cut from the loader's text)
  const fs::path odd = t.path / "x was saved with: only q";
  fs::create_directories(odd);
  fs::copy_file(out / "checkpoint.cfck", odd / "checkpoint.cfck");
  r = cli({"resume", (odd / "checkpoint.cfck").string(), "--set", "colonisation.kill_distance=2", "--quiet"});
  CHECK_THAT(r.err, Contains("checkpoint '" + (odd / "checkpoint.cfck").string() +
                             "' continues with the parameters it was saved with, and this resume changes them: "));
  // an edited script that changes one: named with its old and new value
  const auto edited = t.write("edited.lua", std::regex_replace(volume, std::regex("darts = 3000"), "darts = 2000"));
  r = cli({"resume", (out / "checkpoint.cfck").string(), "--script", edited.string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("this resume changes them: colonisation.darts = 2000.0 (was 3000.0). Only"));
  // the run's own script with a --set a plain resume takes (a colonisation checkpoint keeps no cell
  // values): a plain resume, not an edit with a copy of the checkpoint
  r = cli({"resume", (out / "checkpoint.cfck").string(), "--script", (t.path / "ball.lua").string(), "--set",
           "colonisation.max_nodes=1000000", "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("plain resume"));
  CHECK_FALSE(nlohmann::json::parse(slurp(out / "run.json"))["script"].contains("replaces"));
  for (const auto& e : fs::directory_iterator(out))
    CHECK(e.path().filename().string().rfind("checkpoint-step", 0) != 0);
}

TEST_CASE("a space-colonisation run writes the vein files output{} asks for", "[cli][colonisation]") {
  TempDir t("cli-colout");
  const auto script = t.write("few.lua",
                              "leaf { shape = 'ellipse' }\n"
                              "colonisation { type = 'open', growth = 'none', initial_length = 30, darts = 20000 }\n"
                              "output { ply = false, obj = false, png = true, png_size = 16, svg_size = 50 }\n");
  const fs::path out = t.path / "out";
  const auto r = cli({"run", script.string(), "--out", out.string(), "--steps", "4", "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  // run.steps counts cell steps: it has no meaning here, and is neither recorded nor accepted
  CHECK_FALSE(nlohmann::json::parse(slurp(out / "run.json"))["parameters"]["run"].contains("steps"));
  const auto steps = cli({"run", script.string(), "--out", out.string(), "--set", "run.steps=3"});
  CHECK(steps.code == 2);
  CHECK_THAT(steps.err,
             Contains("--set run.steps=3: run.steps counts the steps of cells") && Contains("colonisation.max_steps"));
  // the leaf is longer than wide (y up): 50 mm high plus the 5 mm margins
  CHECK_THAT(slurp(out / "veins.svg"), Contains("height=\"60.000mm\""));
  CHECK(fs::exists(out / "veins.png"));  // the smallest size allowed still draws
  CHECK_FALSE(fs::exists(out / "veins.ply"));
  CHECK_FALSE(fs::exists(out / "veins.obj"));
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  for (const auto& name : run["outputs"]) CHECK(fs::exists(out / name.get<std::string>()));
  const auto empty = cli({"run", script.string(), "--out", ""});
  CHECK(empty.code == 2);
  CHECK_THAT(empty.err, Contains("--out needs a folder name"));
  for (const char* root : {"/", "//", "/./"}) {
    const auto at_root = cli({"run", script.string(), "--out", root});
    CHECK(at_root.code == 2);
    CHECK_THAT(at_root.err, Contains("is the root of the file system"));
  }
}

TEST_CASE("with print{}, veins.svg is drawn at the print's scale, so a cut outline fits the printed veins",
          "[cli][colonisation]") {
  TempDir t("cli-col-svg-print");
  const auto script = t.write("leaf.lua",
                              "leaf { shape = 'ellipse' }\n"
                              "colonisation { type = 'open', growth = 'none', initial_length = 30, darts = 20000 }\n"
                              "print { size = 70 }\n");
  const fs::path out = t.path / "out";
  const auto r = cli({"run", script.string(), "--out", out.string(), "--steps", "30", "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  const double scale = run["print"]["scale_mm_per_unit"];
  const auto check = nlohmann::json::parse(cli({"check", (out / "printable.stl").string(), "--json"}).out);
  const double printed_width = check["bbox_max_mm"][0].get<double>() - check["bbox_min_mm"][0].get<double>();
  // the drawing's width (less its 5 mm margins) is the leaf's at the print's scale: the printed veins' width
  // less their radii, and at most the outline's width
  const std::string svg = slurp(out / "veins.svg");
  const std::size_t at = svg.find("width=\"") + 7;
  const double drawn = std::stod(svg.substr(at, svg.find("mm\"", at) - at)) - 10;
  CHECK(drawn >= printed_width - 2 * 0.4 * 2);             // veins inside the outline, radii at least min_radius
  CHECK(drawn == Approx(30 * 0.5 * scale).epsilon(0.35));  // about the ellipse's width at that scale
  CHECK(scale > 0);
  // printed again with a value that fails: the folder stays as it was (its print went, as did the checkpoint)
  const std::array<const char*, 4> kept = {"printable.stl", "run.json", "checkpoint.cfck", "veins.svg"};
  std::vector<std::string> before;
  for (const char* f : kept) before.push_back(slurp(out / f));
  const auto again = cli({"resume", out.string(), "--quiet", "--set", "print.voxel_size=0.001"});
  CHECK(again.code == 1);
  CHECK_THAT(again.err, Contains("nothing in " + out.string() + "/ changed"));
  for (std::size_t k = 0; k < kept.size(); ++k) CHECK(slurp(out / kept[k]) == before[k]);
}

TEST_CASE("a colonisation checkpoint whose run set cells.* (once ignored, now refused) still resumes",
          "[cli][checkpoint]") {
  TempDir t("cli-col-old-sets");
  const auto script = t.write("leaf.lua", "leaf {}\ncolonisation { initial_length = 20, final_length = 24 }\n");
  const fs::path out = t.path / "o";
  REQUIRE(cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "3"}).code == 0);
  // forged as an earlier cellform wrote it for a run given --set cells.spring=2
  cellform::core::ChunkFile saved = cellform::core::read_chunk_file(slurp(out / "checkpoint.cfck"), "CKPT", 1, "t");
  auto meta = nlohmann::json::parse(saved.chunks.at("meta"));
  meta["overrides"]["cells.spring"] = "2";
  saved.chunks["meta"] = meta.dump();
  fs::create_directories(t.path / "older");
  t.write("older/checkpoint.cfck", cellform::core::write_chunk_file("CKPT", 1, saved.chunks));
  const auto r = cli({"resume", (t.path / "older" / "checkpoint.cfck").string(), "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  // a new run given it is refused
  CHECK(cli({"run", script.string(), "--out", (t.path / "n").string(), "--set", "cells.spring=2"}).code == 2);
}

TEST_CASE("a colonisation run stopped by max_nodes says so, and resumes under the larger limit it suggests",
          "[cli][colonisation]") {
  TempDir t("cli-maxnodes");
  const auto script = t.write("cap.lua",
                              "leaf { shape = 'ellipse' }\n"
                              "colonisation { type = 'open', growth = 'none', initial_length = 200, darts = 2000,"
                              " max_nodes = 40 }\n");
  const fs::path out = t.path / "out";
  const auto r = cli({"run", script.string(), "--out", out.string()});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.out, Contains("stopped at colonisation.max_nodes"));
  {  // the closing line gives the veins' extent, as veins.obj holds them (a flat leaf: no height)
    std::istringstream obj(slurp(out / "veins.obj"));
    std::vector<cellform::core::Vec3> points;
    for (std::string line; std::getline(obj, line);)
      if (line.rfind("v ", 0) == 0) {
        std::istringstream v(line.substr(2));
        double x = 0, y = 0, z = 0;
        v >> x >> y >> z;
        points.emplace_back(x, y, z);
      }
    REQUIRE(points.size() > 40);
    const std::string extent = cellform::app::extent_text(points);
    CHECK_THAT(extent, Contains(" x 0.0 model units") || Contains(" x 0 model units"));
    CHECK_THAT(r.out, Contains(" loops" + extent + "; outputs in "));
  }
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "stopped at max_nodes");
  const auto nodes = run["veins"]["nodes"].get<std::size_t>();
  CHECK(nodes >= 40);
  // twice what the step reached (it may pass the limit): the resume has room to step on
  CHECK_THAT(r.out, Contains("--set colonisation.max_nodes=" + std::to_string(2 * nodes) + "\n"));
  const auto more =
      cli({"resume", (out / "checkpoint.cfck").string(), "--set", "colonisation.max_nodes=80", "--quiet"});
  INFO(more.err);
  REQUIRE(more.code == 0);
  const auto run2 = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run2["veins"]["nodes"].get<std::size_t>() > nodes);
  CHECK(run2["veins"]["nodes"].get<std::size_t>() >= 80);
}

TEST_CASE("a colonisation run stopped by max_steps resumes under a larger max_steps, by --set or an edited script",
          "[cli][colonisation][checkpoint]") {
  TempDir t("cli-maxsteps");
  const std::string source =
      "run { seed = 2 }\n"
      "leaf { shape = 'ellipse' }\n"
      "colonisation { type = 'open', growth = 'none', initial_length = 60, darts = 2000, max_steps = 8 }\n";
  const auto script = t.write("steps.lua", source);
  const fs::path out = t.path / "out", whole = t.path / "whole";
  auto r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  auto run = nlohmann::json::parse(slurp(out / "run.json"));
  REQUIRE(run["steps"]["completed"] == 8);
  CHECK(run["status"] == "stopped at max_steps");
  // the same run to 20 steps in one go
  r = cli({"run", script.string(), "--out", whole.string(), "--quiet", "--set", "colonisation.max_steps=20"});
  REQUIRE(r.code == 0);
  r = cli({"resume", (out / "checkpoint.cfck").string(), "--set", "colonisation.max_steps=20", "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["steps"]["first"] == 8);
  CHECK(run["steps"]["completed"] == 20);
  CHECK(run["steps"]["limit"] == 20);
  CHECK(run["parameters"]["colonisation"]["max_steps"] == 20);  // run.json agrees with itself
  CHECK(slurp(out / "veins.ply") == slurp(whole / "veins.ply"));
  // below the checkpoint's step: refused, as --steps would be
  r = cli({"resume", (out / "checkpoint.cfck").string(), "--set", "colonisation.max_steps=5", "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("colonisation.max_steps = 5 is below the checkpoint's step 20"));
  // an edited script that raises its max_steps goes on to it (a run whose --set gave max_steps keeps that)
  const fs::path edit = t.path / "edit";
  REQUIRE(cli({"run", script.string(), "--out", edit.string(), "--quiet"}).code == 0);
  std::string edited_source = source;
  edited_source.replace(edited_source.find("max_steps = 8"), 13, "max_steps = 20");
  const auto edited = t.write("edited.lua", edited_source);
  r = cli({"resume", (edit / "checkpoint.cfck").string(), "--script", edited.string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(edit / "run.json"))["steps"]["completed"] == 20);
  CHECK(slurp(edit / "veins.ply") == slurp(whole / "veins.ply"));
  // --steps on a fresh run: run.json's max_steps is the limit used
  r = cli({"run", script.string(), "--out", (t.path / "s").string(), "--quiet", "--steps", "5"});
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(t.path / "s" / "run.json"))["parameters"]["colonisation"]["max_steps"] == 5);
}

TEST_CASE("an outline file in any unit is one leaf length from petiole to tip", "[cli][colonisation]") {
  TempDir t("cli-outline-unit");
  // a kite with its tip 1 from the petiole, and the same drawn 128 times larger (scaling back is exact)
  const std::string kite = "0 0\n0.5 0.5\n0 1\n-0.5 0.5\n0 0\n";
  const std::string big = "0 0\n64 64\n0 128\n-64 64\n0 0\n";
  t.write("kite.txt", kite);
  t.write("big.txt", big);
  const std::string rest =
      "colonisation { type = 'open', initial_length = 20, final_length = 30, length_step = 1 }\n"
      "run { seed = 4 }\n";
  const auto a = t.write("a.lua", "leaf { file = 'kite.txt' }\n" + rest);
  const auto b = t.write("b.lua", "leaf { file = 'big.txt' }\n" + rest);
  REQUIRE(cli({"run", a.string(), "--out", (t.path / "a").string(), "--quiet"}).code == 0);
  REQUIRE(cli({"run", b.string(), "--out", (t.path / "b").string(), "--quiet"}).code == 0);
  const auto ja = nlohmann::json::parse(slurp(t.path / "a" / "run.json"));
  CHECK(ja["veins"]["nodes"].get<int>() > 20);
  CHECK(slurp(t.path / "a" / "veins.ply") == slurp(t.path / "b" / "veins.ply"));  // the same leaf, 30 long
  // one drawn hanging below its petiole is measured by half its farthest vertex, so nudging a vertex
  // just above y = 0 changes nothing (it once scaled the leaf by a thousand)
  t.write("hang.txt", "0 0\n0.5 -0.5\n0 -1\n-0.5 -0.5\n0 0\n");
  t.write("nudged.txt", "0 0\n0.5 0.001\n0.5 -0.5\n0 -1\n-0.5 -0.5\n0 0\n");
  std::vector<double> born;
  for (const char* f : {"hang", "nudged"}) {
    const auto sc = t.write(std::string(f) + ".lua", "leaf { file = '" + std::string(f) + ".txt' }\n" + rest);
    const fs::path o = t.path / f;
    REQUIRE(cli({"run", sc.string(), "--out", o.string(), "--quiet"}).code == 0);
    born.push_back(nlohmann::json::parse(slurp(o / "run.json"))["veins"]["sources_born"].get<double>());
  }
  CHECK(born[1] < 2 * born[0] + 10);
  // a file whose every vertex is the petiole is refused
  t.write("dot.txt", "0 0\n0 0\n0 0\n0 0\n");
  const auto c = t.write("c.lua", "leaf { file = 'dot.txt' }\n" + rest);
  const auto r = cli({"run", c.string(), "--out", (t.path / "c").string(), "--quiet"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("c.lua:1: leaf: "));
  // an outline drawn away from (0, 0): the file is named
  t.write("away.txt", "1 1\n1.3 1.3\n1 2\n0.7 1.3\n1 1\n");
  const auto d = t.write("d.lua", "leaf { file = 'away.txt' }\n" + rest);
  const auto away = cli({"run", d.string(), "--out", (t.path / "d").string(), "--quiet"});
  CHECK(away.code == 2);
  CHECK_THAT(away.err, Contains("d.lua:1: leaf: ") && Contains("(0, 0) of away.txt") && Contains("outside"));
}

TEST_CASE("Ctrl-C while surface{cells = true}'s sheet grows leaves a checkpoint that finishes it identically",
          "[cli][colonisation][signal]") {
  TempDir t("cli-sheet-int");
  const auto script = t.write("sheet.lua",
                              "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.3} }\n"
                              "division { trigger = 'age', age = 6, min_age = 3, probability = 0.5, max_cells = 400 }\n"
                              "run { steps = 100000000 }\n"
                              "disc { radius = 4 }\n"
                              "petiole { at = {0, -4, 0} }\n"
                              "surface { cells = true }\n"
                              "colonisation { kill_distance = 1, birth_distance = 2, darts = 20000 }\n");
  const fs::path out = t.path / "o";
  const pid_t pid = spawn_cellform({"run", script.string(), "--out", out.string(), "--quiet"});
  REQUIRE(pid > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  kill(pid, SIGINT);
  CHECK(wait_exit(pid) == 130);
  REQUIRE(fs::exists(out / "checkpoint.cfck"));
  CHECK(fs::exists(out / "cells.ply"));  // the sheet so far
  CHECK_FALSE(fs::exists(out / "veins.ply"));
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["status"] == "interrupted");
  CHECK(run["phase"] == "cells");
  const std::uint64_t stopped = run["cells"]["steps"];
  REQUIRE(stopped > 0);
  CHECK(run["timings"].at("sheet_s").get<double>() > 0);  // the sheet's steps took the second
  CHECK(run["timings"].at("checkpoints_s").get<double>() >= 0);
  fs::copy_file(out / "checkpoint.cfck", t.path / "sheet.cfck");
  // resuming grows the rest of the sheet, then the veins: the same as one uninterrupted run
  const std::string target = std::to_string(stopped + 20);
  const fs::path whole = t.path / "whole";
  auto r = cli({"run", script.string(), "--out", whole.string(), "--quiet", "--steps", target});
  REQUIRE(r.code == 0);
  r = cli({"resume", (out / "checkpoint.cfck").string(), "--steps", target});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err,
             Contains("resuming the cell sheet from step " + std::to_string(stopped)) && Contains("growing veins"));
  CHECK(slurp(whole / "cells.ply") == slurp(out / "cells.ply"));
  CHECK(slurp(whole / "veins.ply") == slurp(out / "veins.ply"));
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["veins"]["nodes"].get<int>() > 10);
  CHECK(nlohmann::json::parse(slurp(out / "run.json"))["cells"]["initial"] ==
        nlohmann::json::parse(slurp(whole / "run.json"))["cells"]["initial"]);
  // the sheet checkpoint keeps the values it grew with: a resume by a cellform whose defaults changed
  // grows the rest with them (forged here as a saved cells.separation of 0.1)
  cellform::core::ChunkFile saved = cellform::core::read_chunk_file(slurp(t.path / "sheet.cfck"), "CKPT", 1, "test");
  auto meta = nlohmann::json::parse(saved.chunks.at("meta"));
  REQUIRE(meta["mode"] == "sheet");
  REQUIRE(meta["physics"]["cells"]["separation"] == 0.05);
  REQUIRE(meta["initial_cells"].get<int>() > 0);
  meta["physics"]["cells"]["separation"] = 0.1;
  saved.chunks["meta"] = meta.dump();
  fs::create_directories(t.path / "older");
  t.write("older/checkpoint.cfck", cellform::core::write_chunk_file("CKPT", 1, saved.chunks));
  r = cli({"resume", (t.path / "older" / "checkpoint.cfck").string(), "--steps", target, "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(t.path / "older" / "run.json"))["parameters"]["cells"]["separation"] == 0.1);
  // the sheet's parameters cannot change on the way: the sheet would not be the run's
  r = cli({"resume", (t.path / "sheet.cfck").string(), "--steps", target, "--set", "cells.separation=0.1"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--set cells.separation=0.1") && Contains("continues with the parameters it was saved"));
}
