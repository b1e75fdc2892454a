// Tests of what a space-colonisation run says at its end (app/run_colonisation.cpp).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/run_internal.h"
#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {
// a closed box 20 x 20 x `thick` (model units), its top at z = thick
std::string slab(double thick) {
  const std::string t = std::to_string(thick);
  return "v -10 -10 0\nv 10 -10 0\nv 10 10 0\nv -10 10 0\nv -10 -10 " + t + "\nv 10 -10 " + t + "\nv 10 10 " + t +
         "\nv -10 10 " + t +
         "\nf 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 "
         "8\n";
}
}  // namespace

TEST_CASE("veins that stall behind a thin wall of a surface say why, and how to go on", "[cli][colonisation]") {
  TempDir t("cli-thin-wall");
  t.write("thin.obj", slab(2));
  t.write("thick.obj", slab(8));
  const std::string rule =
      "colonisation { type = 'open', kill_distance = 1, birth_distance = 3, darts = 20000 }\nrun { seed = 1 }\n";
  // 2 segments thick: a source on the floor pulls the ceiling's node straight down, and its step lands back
  const auto thin = t.write("thin.lua", "surface { file = 'thin.obj', seeds = {{0, 0, 2}} }\n" + rule);
  auto r = cli({"run", thin.string(), "--out", (t.path / "a").string(), "--quiet"});
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(slurp(t.path / "a" / "run.json"));
  CHECK(j["status"] == "stalled");
  // no cell grows: run.json leaves out the parameters of cells and division, which --set refuses (audit)
  CHECK(!j["parameters"].contains("cells"));
  CHECK(!j["parameters"].contains("division"));
  CHECK(j["parameters"].contains("colonisation"));
  const std::size_t left = j["veins"]["sources_left"];
  CHECK(left > 0);
  CHECK_THAT(r.err, Contains("note: " + std::to_string(left) +
                             (left == 1 ? " auxin source is left" : " auxin sources are left")) &&
                        Contains("thinner than about 3 vein segments") && Contains("surface{scale = ...}"));
  // 8 thick: the veins go round the rim, and nothing is said
  const auto thick = t.write("thick.lua", "surface { file = 'thick.obj', seeds = {{0, 0, 8}} }\n" + rule);
  r = cli({"run", thick.string(), "--out", (t.path / "b").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(t.path / "b" / "run.json"))["status"] == "complete");
  CHECK_THAT(r.err, !Contains(" auxin source"));
}

TEST_CASE("a 3-D domain thousands of segments across, as a mesh drawn in mm gives, is noted at the start",
          "[cli][colonisation]") {
  TempDir t("cli-large-domain");
  t.write("plate.obj", "v 0 0 0\nv 2000 0 0\nv 2000 2000 0\nv 0 2000 0\nf 1 2 3\nf 1 3 4\n");
  const std::string rule = "colonisation { birth_distance = 3, kill_distance = 1, darts = 1e-5, max_steps = 2 }\n";
  const auto mm = t.write("mm.lua", "surface { file = 'plate.obj', seeds = {{1000, 1000, 0}} }\n" + rule);
  auto r = cli({"run", mm.string(), "--out", (t.path / "a").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, Contains("note: the surface spans 2000 vein segments (model units) at its longest") &&
                        Contains("wants surface{scale = ...}"));
  // scaled to 100 segments: nothing is said
  const auto scaled =
      t.write("scaled.lua", "surface { file = 'plate.obj', scale = 0.05, seeds = {{50, 50, 0}} }\n" + rule);
  r = cli({"run", scaled.string(), "--out", (t.path / "b").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err, !Contains("at its longest"));
  // a box is given in segments: said, without the mesh's remedy
  const auto box = t.write("box.lua", "volume { box = { min = {0, 0, 0}, max = {1500, 10, 10} } }\n" + rule);
  r = cli({"run", box.string(), "--out", (t.path / "c").string(), "--quiet"});
  REQUIRE(r.code == 0);
  CHECK_THAT(r.err,
             Contains("note: the volume spans 1500 vein segments (model units) at its longest") && !Contains("scale"));
}

TEST_CASE("a colonisation quick try with --steps ends before any vein: the print is skipped, and says why",
          "[cli][colonisation]") {
  TempDir t("cli-col-short-try");
  // darts land on the marginal leaf only once it has grown: none in the first 3 steps
  const auto script = t.write("leaf.lua",
                              "leaf { shape = 'ellipse' }\ncolonisation { type = 'open', kill_distance = 1, "
                              "birth_distance = 1, growth = 'marginal', initial_length = 0.5, final_length = 40, "
                              "length_step = 0.2, darts = 200, max_steps = 400 }\nprint { formats = 'stl' }\n");
  auto r = cli({"run", script.string(), "--out", (t.path / "a").string(), "--steps", "3", "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("print: skipped: nothing to print yet at step 3 (no vein has grown; the run was cut "
                             "short at step 3 of the script's 400)"));
  auto j = nlohmann::json::parse(slurp(t.path / "a" / "run.json"));
  CHECK(j["status"] == "stopped at max_steps");
  CHECK(j["print"].contains("skipped"));
  CHECK(!fs::exists(t.path / "a" / "printable.stl"));
  // the whole script with nothing grown still fails, as it asked for a print
  r = cli({"run", script.string(), "--out", (t.path / "b").string(), "--steps", "3", "--set",
           "colonisation.max_steps=3", "--quiet"});
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("nothing to print: no vein grew") && !Contains("skipped"));
  // a quick try long enough to grow veins prints them
  r = cli({"run", script.string(), "--out", (t.path / "c").string(), "--steps", "60", "--quiet"});
  CHECK(r.code == 0);
  CHECK(fs::exists(t.path / "c" / "printable.stl"));
}

TEST_CASE("a quick try on a grown sheet ends before any vein: the print of veins and sheet is skipped",
          "[cli][colonisation]") {
  // examples/ribbed_shell.lua --steps 3: the sheet alone was printed, and its flat base did not fit the flat sheet
  // of so short a try, which failed the run (exit 1)
  TempDir t("cli-col-sheet-try");
  const std::string sheet =
      "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.3} }\n"
      "division { trigger = 'age', age = 6, min_age = 3, probability = 0.5, max_cells = 400 }\n"
      "run { steps = 60 }\ndisc { radius = 4 }\npetiole { at = {0, -4, 0} }\nsurface { cells = true }\n"
      "colonisation { kill_distance = 1, birth_distance = 2, darts = 20000 }\n";
  const auto script = t.write("sheet.lua", sheet + "print { shell = true, size = 30, flat_base = 2 }\n");
  const auto r = cli({"run", script.string(), "--out", (t.path / "a").string(), "--steps", "1", "--quiet"});
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("print: skipped: nothing to print yet at step 1") && !Contains("flat_base"));
  const auto j = nlohmann::json::parse(slurp(t.path / "a" / "run.json"));
  CHECK(j["print"].contains("skipped"));
  CHECK(!fs::exists(t.path / "a" / "printable.stl"));
  // a print of the sheet alone (print.veins = false) has no veins to wait for: made as in a full run
  const auto alone = t.write("sheet_only.lua", sheet + "print { shell = true, size = 30, veins = false }\n");
  const auto q = cli({"run", alone.string(), "--out", (t.path / "b").string(), "--steps", "1", "--quiet"});
  INFO(q.err);
  CHECK(q.code == 0);
  CHECK(nlohmann::json::parse(slurp(t.path / "b" / "run.json"))["print"]["segments"] == 0);
  CHECK(fs::exists(t.path / "b" / "printable.stl"));
}

TEST_CASE("colonisation.node_flow widens the veins towards the base: each inner node adds its flow (Section 3.5)",
          "[cli][colonisation]") {
  TempDir t("cli-node-flow");
  struct Node {
    double flow, radius;
    int parent = -1, children = 0;
  };
  auto grow = [&](const std::string& node_flow) {
    const auto script = t.write("leaf" + node_flow + ".lua",
                                "leaf { shape = 'ellipse' }\nrun { seed = 2 }\ncolonisation { type = 'open', "
                                "growth = 'none', initial_length = 60, kill_distance = 1, birth_distance = 2, darts = "
                                "2000, murray_exponent = 2, node_flow = " +
                                    node_flow + " }\n");
    const fs::path out = t.path / ("o" + node_flow);
    const auto r = cli({"run", script.string(), "--out", out.string(), "--quiet"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    std::vector<Node> nodes;  // from veins.obj: "v x y z" then "#a flow radius order"; "l tip ... base"
    std::istringstream in(slurp(out / "veins.obj"));
    for (std::string line; std::getline(in, line);) {
      std::istringstream ls(line);
      std::string tag;
      ls >> tag;
      if (tag == "#a") {
        REQUIRE(!nodes.empty());
        ls >> nodes.back().flow >> nodes.back().radius;
      } else if (tag == "v") {
        nodes.push_back({});
      } else if (tag == "l") {  // a run of nodes, each the parent of the one before
        int child = 0, parent = 0;
        for (ls >> child; ls >> parent; child = parent) {
          nodes[static_cast<std::size_t>(child - 1)].parent = parent - 1;
          ++nodes[static_cast<std::size_t>(parent - 1)].children;
        }
      }
    }
    REQUIRE(nodes.size() > 100);
    return nodes;
  };
  const auto pure = grow("0"), wide = grow("0.25");
  REQUIRE(pure.size() == wide.size());  // widths come after growth: the same tree
  std::vector<double> sum(wide.size(), 0.0);
  for (const Node& v : wide)
    if (v.parent >= 0) sum[static_cast<std::size_t>(v.parent)] += v.flow;
  const double tip = wide[0].radius / std::sqrt(wide[0].flow);  // radius = tip_radius * flow^(1/2)
  std::size_t inner = 0, tips = 0;
  for (std::size_t i = 0; i < wide.size(); ++i) {
    const Node& v = wide[i];
    CHECK(v.radius == Approx(tip * std::sqrt(v.flow)).epsilon(1e-5));  // the files keep 32-bit floats
    CHECK(pure[i].children == v.children);
    if (v.children == 0) {
      ++tips;
      CHECK(v.flow == 1);
      CHECK(pure[i].flow == 1);
    } else {
      ++inner;
      CHECK(v.flow == Approx(sum[i] + 0.25).epsilon(1e-5));  // r^2 = sum of the children's r^2, plus the node's
      CHECK(v.flow > pure[i].flow);
    }
  }
  // the base: every tip's flow and a quarter for every inner node; Murray's law alone gives the tips
  const auto root = static_cast<std::size_t>(
      std::find_if(wide.begin(), wide.end(), [](const Node& v) { return v.parent < 0; }) - wide.begin());
  CHECK(pure[root].flow == static_cast<double>(tips));
  CHECK(wide[root].flow == Approx(static_cast<double>(tips) + 0.25 * static_cast<double>(inner)).epsilon(1e-5));
  CHECK(wide[root].radius == Approx(pure[root].radius * std::sqrt(wide[root].flow / pure[root].flow)).epsilon(1e-5));
  CHECK(wide[root].radius > 1.4 * pure[root].radius);
}

TEST_CASE("a stalled leaf says where its sources are left: outside the grown blade, or out of every vein's reach",
          "[cli][colonisation]") {
  TempDir t("cli-leaf-stall");
  // marginal growth of a lobed blade: below a lobe the young blade covers what the grown one leaves open
  const auto script = t.write("lobed.lua",
                              "leaf { shape = 'lobed' }\nrun { seed = 1 }\ncolonisation { type = 'open', growth = "
                              "'marginal', initial_length = 5, final_length = 60, length_step = 1, darts = 300, "
                              "kill_distance = 1, birth_distance = 1 }\n");
  const auto r = cli({"run", script.string(), "--out", (t.path / "a").string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(slurp(t.path / "a" / "run.json"));
  REQUIRE(j["status"] == "stalled");
  const std::size_t left = j["veins"]["sources_left"];
  // the note's two counts add up to run.json's
  const std::string lead =
      "note: " + std::to_string(left) + (left == 1 ? " auxin source is left: " : " auxin sources are left: ");
  REQUIRE_THAT(r.err, Contains(lead));
  std::istringstream rest(r.err.substr(r.err.find(lead) + lead.size()));
  std::size_t outside = 0, inside = 0;
  std::string words;
  rest >> outside;
  std::getline(rest, words, ')');
  CHECK_THAT(words, Contains("outside the grown blade") && Contains("below a lobe or tooth") && Contains("isogonic"));
  rest.ignore(2);
  rest >> inside;
  std::getline(rest, words);
  CHECK_THAT(words, Contains(inside == 1 ? "inside it, where no vein can step towards it (" : "towards them ("));
  CHECK(outside > 0);
  CHECK(outside + inside == left);
}

TEST_CASE("a stalled volume says its veins do not cross a gap between its parts", "[cli][colonisation]") {
  TempDir t("cli-volume-stall");
  // two closed boxes 10 wide, 5 apart, seeded in the first: the sources in the second wait for ever
  std::string obj;
  for (const double x0 : {0.0, 15.0}) {
    for (int i = 0; i < 8; ++i)
      obj += "v " + std::to_string(x0 + (i & 1 ? 10 : 0)) + (i & 2 ? " 10" : " 0") + (i & 4 ? " 10\n" : " 0\n");
    const int b = x0 == 0 ? 0 : 8;
    for (const auto& q : {std::array{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}})
      obj += "f " + std::to_string(b + q[0]) + " " + std::to_string(b + q[1]) + " " + std::to_string(b + q[2]) + " " +
             std::to_string(b + q[3]) + "\n";
  }
  t.write("two.obj", obj);
  const auto script = t.write("two.lua",
                              "volume { file = 'two.obj', seeds = {{5, 5, 0}} }\n"
                              "colonisation { type = 'open', kill_distance = 1, birth_distance = 2.5, "
                              "darts = 20000 }\n");
  const auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(slurp(t.path / "o" / "run.json"));
  REQUIRE(j["status"] == "stalled");
  const std::size_t left = j["veins"]["sources_left"];
  CHECK(left > 10);
  CHECK_THAT(r.err, Contains("note: " + std::to_string(left) +
                             " auxin sources are left. A vein node that would step "
                             "out of the volume is moved back") &&
                        Contains("seed each part (volume{seeds = ...})"));
}

TEST_CASE("veins.svg is at the print's scale even when the print fails, and run.json gives its scale and size",
          "[cli][colonisation]") {
  TempDir t("cli-col-svg-failed-print");
  const auto script = t.write("leaf.lua",
                              "leaf { shape = 'ellipse' }\n"
                              "colonisation { type = 'open', growth = 'none', initial_length = 30, darts = 20000 }\n"
                              "print { size = 70 }\n");
  const auto good = cli({"run", script.string(), "--out", (t.path / "good").string(), "--steps", "30", "--quiet"});
  REQUIRE(good.code == 0);
  // an export audit: a print refused for memory drew the leaf 200 mm long instead, and nothing said so
  const auto bad = cli({"run", script.string(), "--out", (t.path / "bad").string(), "--steps", "30", "--quiet", "--set",
                        "print.voxel_size=0.001", "--set", "print.max_memory=1"});
  INFO(bad.err);
  REQUIRE(bad.code == 1);
  const auto g = nlohmann::json::parse(slurp(t.path / "good" / "run.json"));
  const auto b = nlohmann::json::parse(slurp(t.path / "bad" / "run.json"));
  CHECK(b["status"] == "print failed");
  CHECK(g["svg"]["scale_mm_per_unit"] == g["print"]["scale_mm_per_unit"]);
  CHECK(b["svg"] == g["svg"]);
  CHECK(slurp(t.path / "bad" / "veins.svg") == slurp(t.path / "good" / "veins.svg"));
  const std::string svg = slurp(t.path / "good" / "veins.svg");
  const std::size_t at = svg.find("width=\"") + 7;
  CHECK(std::stod(svg.substr(at, svg.find("mm\"", at) - at)) ==
        Approx(g["svg"]["width_mm"].get<double>()).margin(5e-4));  // (3 decimals)
  // without print{} the drawing is 200 mm on its longer side, margins aside
  const auto plain = t.write("plain.lua",
                             "leaf { shape = 'ellipse' }\n"
                             "colonisation { type = 'open', growth = 'none', initial_length = 30, darts = 20000 }\n");
  REQUIRE(cli({"run", plain.string(), "--out", (t.path / "plain").string(), "--steps", "30", "--quiet"}).code == 0);
  const auto p = nlohmann::json::parse(slurp(t.path / "plain" / "run.json"));
  CHECK(std::max(p["svg"]["width_mm"].get<double>(), p["svg"]["height_mm"].get<double>()) == Approx(210));
}

TEST_CASE("a colonisation print gives each loop's closing segment the finer vein's radius at both ends",
          "[colonisation][print]") {
  // a tree 0 -> 1 -> 2 and 0 -> 3 (radii 3, 2, 1 and 0.5), with a loop closed between 2 and 3
  cellform::venation::VeinTree t;
  t.positions = {cellform::core::Vec3(0, 0, 0), cellform::core::Vec3(0, 1, 0), cellform::core::Vec3(0, 2, 0),
                 cellform::core::Vec3(1, 1, 0)};
  t.parent = {cellform::core::kNoIndex, 0, 1, 0};
  t.birth_step = {0, 1, 2, 1};
  t.radius = {3, 2, 1, 0.5};
  t.order = {1, 1, 1, 2};
  t.anastomoses = {{2, 3}};
  const auto s = cellform::app::vein_segments(t);
  REQUIRE(s.size() == 4);
  for (std::size_t k = 0; k < 3; ++k) {  // tree edges: each end the radius of its node, but a side branch's
    const auto [p, c] = t.edges()[k];    // (3, of order 2 off an order-1 vein): its own at both, not flared
    CHECK(s[k].a == t.positions[p]);
    CHECK(s[k].b == t.positions[c]);
    CHECK(s[k].ra == (c == 3 ? 0.5 : t.radius[p]));
    CHECK(s[k].rb == t.radius[c]);
  }
  CHECK(s[3].a == t.positions[2]);  // the closing segment: 0.5 at both ends, not 1 at one of them
  CHECK(s[3].b == t.positions[3]);
  CHECK(s[3].ra == 0.5);
  CHECK(s[3].rb == 0.5);
}
