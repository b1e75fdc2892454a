// Tests of app/run_start.cpp: what resume --script says about an edited script's placed things, and the
// checkpoint's metadata of text that is not UTF-8.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "app/run_internal.h"
#include "tests/app/test_util.h"

using namespace cellform;
using Catch::Matchers::Contains;

namespace {
forms::PetioleSpec petiole(double x, int line) {
  return {core::Vec3(x, 0, 0), true, 0, "e.lua:" + std::to_string(line) + ": "};
}
}  // namespace

TEST_CASE("resume --script names the petioles it changes, not those it only reorders", "[cli][checkpoint]") {
  app::Start s;
  s.resume = true;
  s.step = 10;
  app::SceneConfig before, now;
  before.scene.petioles = {petiole(0, 3), petiole(5, 4)};
  now.scene.petioles = {petiole(5, 3), petiole(0, 4)};  // the same two, lines swapped
  CHECK(app::unplaced_changes(s, before, now).empty());
  now.scene.petioles = {petiole(0, 3), petiole(6, 4)};  // the second moved
  CHECK_THAT(app::unplaced_changes(s, before, now),
             Contains("petioles due by step 10 (e.lua:4; 1 of the run's no longer there (moved or removed))") &&
                 !Contains("e.lua:3"));
  now.scene.petioles = {petiole(0, 3), petiole(5, 4), petiole(9, 7)};  // one added
  CHECK_THAT(app::unplaced_changes(s, before, now), Contains("(e.lua:7)"));
  now.scene.petioles = {petiole(0, 3), petiole(5, 4), {core::Vec3(9, 0, 0), true, 20, "e.lua:8: "}};
  CHECK(app::unplaced_changes(s, before, now).empty());  // due after the checkpoint: placed as the run goes on
}

namespace fs = std::filesystem;
using namespace cellform::test;

TEST_CASE("text that is not UTF-8: a script's name is recorded replaced; a value is refused", "[cli]") {
  TempDir t("cli-utf8");
  const auto script = t.write(
      "n\xff\xfe"
      "ame.lua",
      kSmall);
  const fs::path out = t.path / "out";
  auto r = cli({"run", script.string(), "--out", out.string(), "--quiet", "--steps", "3"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(run["script"]["path"].get<std::string>().find("n\xef\xbf\xbd\xef\xbf\xbd"
                                                      "ame.lua") != std::string::npos);
  // the checkpoint is written and resumes
  r = cli({"resume", (out / "checkpoint.cfck").string(), "--steps", "5", "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  // a script in a folder whose name is not UTF-8 reads its files beside it, on resume too (the checkpoint
  // keeps the path's bytes)
  fs::create_directories(t.path / "f\xe9");
  t.write("f\xe9/segment.txt", "-0.125 0\n0.125 0\n0.125 1\n-0.125 1\n-0.125 0\n");
  const auto leaf = t.write("f\xe9/grass.lua",
                            "leaf { file = 'segment.txt' }\ncolonisation { initial_length = 20, final_length = 30 }\n");
  const fs::path grass = t.path / "grass";
  r = cli({"run", leaf.string(), "--out", grass.string(), "--quiet", "--steps", "3"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  r = cli({"resume", (grass / "checkpoint.cfck").string(), "--steps", "6", "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  // a value is run.json's and the checkpoint's to record as given: refused before the run
  r = cli({"run", script.string(), "--out", out.string(), "--set", "size=\xff"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--set size=\\xff: not UTF-8 text"));
  const auto knob = t.write("knob.lua", "local P = params { name = 'caf\xe9' }\ndisc { radius = 2 }\n");
  r = cli({"run", knob.string(), "--out", (t.path / "k").string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("knob.lua:1: params{...}: the knob name's default is not UTF-8 text"));
}

TEST_CASE("a script's default output folder is out/<its name>, never out/ itself or the working folder", "[cli]") {
  TempDir t("run-start-name");
  for (const auto& [name, folder] : {std::pair{"leaf.lua", "out/leaf"}, std::pair{"...lua", "out/script"},
                                     std::pair{"..lua", "out/script"}, std::pair{".lua", "out/.lua"}}) {
    INFO(name);
    app::RunOptions o;
    o.script = t.write(name, "disc { radius = 2 }\n");
    CHECK(app::start_from(o).out_dir == std::filesystem::path(folder));
  }
}

TEST_CASE("the commands cellform suggests can be pasted back into a shell", "[cli]") {
  CHECK(app::shell_word("/tmp/out/leaf/checkpoint.cfck") == "/tmp/out/leaf/checkpoint.cfck");
  CHECK(app::shell_word("/tmp/o é sp2/checkpoint.cfck") == "'/tmp/o é sp2/checkpoint.cfck'");
  CHECK(app::shell_word("it's") == "'it'\\''s'");
}

TEST_CASE("a large veins.svg is said to be large, with the way to fewer paths", "[cli]") {
  using cellform::app::kLargeSvgBytes;
  using cellform::app::large_svg_note;
  CHECK(large_svg_note(kLargeSvgBytes - 1, false).empty());
  CHECK(large_svg_note(static_cast<std::uintmax_t>(-1), false).empty());  // size unknown: nothing said
  const std::string note = large_svg_note(110'400'000, false);
  CHECK(note ==
        "cellform: note: veins.svg is 110 MB: drawing and laser-cutter programs may take minutes to open "
        "it; output{svg_paths = \"veins\"} draws about half as many paths\n");
  CHECK(large_svg_note(kLargeSvgBytes, true).find("svg_paths") == std::string::npos);  // drawn so already
}
