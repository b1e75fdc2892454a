// Tests of the script host's space-colonisation sections: leaf{}, colonisation{}, volume{}, surface{},
// growth tables and functions, and the outputs only such runs have.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "tests/app/script_test_util.h"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using cellform::test::load;
using cellform::test::load_error;

TEST_CASE("leaf{} and colonisation{} describe a space-colonisation run", "[script][colonisation]") {
  const auto cfg = load(
      "leaf { shape = 'ellipse', teeth = 8 }\n"
      "colonisation { type = 'closed', neighbourhood = 'urquhart', darts = 500, growth = 'none',\n"
      "               initial_length = 40 }\n");
  REQUIRE(cfg.colonisation);
  CHECK(cfg.colonisation->params.type == cellform::venation::VenationType::closed);
  CHECK(cfg.colonisation->params.neighbourhood == cellform::venation::Neighbourhood::urquhart);
  CHECK(cfg.colonisation->params.darts_per_area == Approx(500e-6));
  CHECK(cfg.colonisation->params.initial_scale == 40);
  CHECK(cfg.colonisation->params.final_scale == 40);  // no growth
  CHECK(cfg.colonisation->leaf.outline.points.size() > 16);
  CHECK_THAT(load_error("leaf {}\ndisc { radius = 2 }\n"), Contains("needs colonisation{...}"));
  CHECK_THAT(load_error("colonisation {}\ndisc { radius = 2 }\n"), Contains("cannot be combined"));
  CHECK_THAT(
      load_error("surface { cells = true, file = 'cube.obj' }\ncolonisation {}\ndisc { radius = 2 }\n"),
      Contains("surface{...} needs either file = \"shape.obj\" or cells = true (the grown cell sheet), not both"));
  CHECK_THAT(load_error("leaf { file = 'nothere.txt' }\ncolonisation {}\n"), Contains("nothere.txt"));
  // scale is for a mesh file's coordinates: beside the grown sheet or a box it did nothing, unsaid
  CHECK_THAT(load_error("disc { radius = 2 }\npetiole { at = {0, -2, 0} }\ncolonisation {}\n"
                        "surface { cells = true,\n scale = 2 }\n"),
             Contains(":4: surface.scale scales the coordinates of a mesh file (surface{file = ...}); the grown "
                      "cell sheet is in model units") &&
                 Contains("cells.rest_length"));
  CHECK_THAT(load_error("volume { box = { min = {0, 0, 0}, max = {10, 10, 10} }, scale = 3 }\ncolonisation {}\n"),
             Contains(":1: volume.scale scales the coordinates of a mesh file") && Contains("model units"));
  // scale = 1 changes nothing: accepted
  CHECK_NOTHROW(load("volume { box = { min = {0, 0, 0}, max = {10, 10, 10} }, scale = 1 }\ncolonisation {}\n"));
  CHECK_THAT(
      load_error("volume { ball = { centre = {0, 0, 0}, radius = 5 } }\ncolonisation {}\n", {{"volume.scale", "10"}}),
      Contains("--set volume.scale=10: volume.scale scales"));
  // a value given by --set that needs another section is named as given (it had no place, and a knob hint)
  CHECK_THAT(load_error("disc { radius = 2 }\n", {{"output.png", "true"}}),
             Contains("--set output.png=true: output{png = true} draws space-colonisation veins"));
  CHECK_THAT(load_error("colonisation { kill_distance = 0.2 }\n"), Contains("kill_distance"));
  CHECK_THAT(load_error("leaf { shape = 'ovat' }\ncolonisation {}\n"), Contains("did you mean \"ovate\""));
  // a blade narrower than a hundredth of its length said only that its outline crossed itself; 10,000
  // teeth took 9 s to check
  CHECK_THAT(load_error("leaf { width = 5e-324 }\ncolonisation {}\n"),
             Contains("leaf.width must be a number from 0.01 to 10"));
  CHECK_THAT(load_error("leaf { teeth = 10000 }\ncolonisation {}\n"),
             Contains("leaf.teeth must be a whole number from 0 to 2000"));
  // a petiole cell would be ignored by a leaf or volume run: said, with its line, instead
  CHECK_THAT(load_error("leaf {}\npetiole { at = {5, 5, 0} }\ncolonisation {}\n"),
             Contains(":2: petiole{...} places a petiole cell") && Contains("leaf{seeds = N}"));
  CHECK_THAT(
      load_error(
          "volume { box = { min = {0, 0, 0}, max = {10, 10, 10} } }\ncolonisation {}\npetiole { at = {1, 1, 1} }\n"),
      Contains(":3: petiole{...}"));
  // --set of a part the script's section does not give: said so, not "did you mean" the same name
  CHECK_THAT(load_error("volume { box = { min = {0, 0, 0}, max = {10, 10, 10} }, seeds = {{1, 1, 1}} }\n"
                        "colonisation {}\n",
                        {{"volume.ball.radius", "3"}}),
             Contains("--set volume.ball.radius=3: the script's volume{...} has no ball = {...}") &&
                 !Contains("did you mean"));
  CHECK_THAT(load_error("leaf {}\ncolonisation {}\ndivision { age = 3 }\n"),
             Contains(":3: division{...} sets up the cell system"));
  CHECK_THAT(load_error("cells { spring = 2 }\nleaf {}\ncolonisation {}\n"), Contains(":1: cells{...}"));
  // and by --set, which needs no call
  CHECK_THAT(load_error("leaf {}\ncolonisation {}\n", {{"cells.spring", "2"}}),
             StartsWith("--set cells.spring=2: cells{...} sets up the cell system"));
  CHECK_THAT(load_error("leaf {}\ncolonisation {}\n", {{"division.max_cells", "10"}}),
             StartsWith("--set division.max_cells=10: division{...} sets up the cell system"));
  // messages name the script's parameters, not the library's fields
  CHECK_THAT(load_error("leaf {}\ncolonisation { length_step = 0 }\n"),
             Contains(":2: colonisation.length_step") && !Contains("scale_step"));
  // a step below the rounding of the size never arrives: isogonic growth ran on to max_steps (a review)
  CHECK_THAT(load_error("leaf {}\ncolonisation { growth = 'isogonic', initial_length = 20, final_length = 40, "
                        "length_step = 1e-17 }\n"),
             Contains(":2: colonisation.length_step (1e-17) is too small to change the leaf's size (up to 40) in "
                      "double precision"));
  // the size's rounding is coarser past a power of two: a step that moves it below 2 stuck at 2 (a re-read)
  CHECK_THAT(load_error("leaf {}\ncolonisation { growth = 'isogonic', initial_length = 1.999999999999, "
                        "final_length = 2.000000000001, length_step = 1.5e-16 }\n"),
             Contains("is too small to change the leaf's size (up to 2"));
  CHECK_THAT(load_error("leaf {}\ncolonisation { growth = 'isogonic', initial_length = 20, final_length = 40, "
                        "length_step = 1e-6 }\n"),
             Contains(":2: colonisation.length_step (1e-06) is too small: growth from 20 to 40 would take more "
                      "than 10^7 steps"));
  CHECK_NOTHROW(
      load("leaf {}\ncolonisation { growth = 'isogonic', initial_length = 20, final_length = 40, "
           "length_step = 1e-5 }\n"));
  CHECK_THAT(load_error("leaf {}\ncolonisation { initial_length = 50, final_length = 20 }\n"),
             Contains("colonisation.final_length") && Contains("colonisation.initial_length"));
  CHECK_THAT(load_error("leaf { shape = 'ellipse', seeds = 3, seed_spread = 5 }\ncolonisation {}\n"),
             Contains("leaf.seeds: seed 1 of 3 lies outside the blade") && Contains("seed_spread = 5"));
  // seeds on one point never grow apart (a closed pattern stalled at once): refused
  CHECK_THAT(load_error("leaf { seeds = 3, seed_spread = 0 }\ncolonisation {}\n"),
             Contains(":1: leaf: leaf.seed_spread = 0 puts the 3 seeds on one point"));
  CHECK(load("leaf { seeds = 1, seed_spread = 0 }\ncolonisation {}\n").colonisation.has_value());
  CHECK_THAT(load_error("volume { ball = { radius = 10 }, seeds = {{0, 0, 5}, {0, 0, 5}} }\n"
                        "colonisation { type = 'closed' }\n"),
             Contains(":2: volume.seeds[2] {0, 0, 5} repeats volume.seeds[1]"));
  // an open pattern grows from the first and leaves the other alone: accepted
  CHECK(load("volume { ball = { radius = 10 }, seeds = {{0, 0, 5}, {0, 0, 5}} }\ncolonisation {}\n")
            .colonisation.has_value());
  // settings the run would ignore
  CHECK_THAT(load_error("leaf {}\ncolonisation { type = 'open', neighbourhood = 'urquhart' }\n"),
             Contains(":2: colonisation.neighbourhood"));
  CHECK_THAT(load_error("leaf {}\ncolonisation {}\noutput { every = 5 }\n"), Contains(":3: output.every"));
  CHECK_THAT(load_error("leaf {}\ncolonisation {}\nground {}\nattractor { position = {0, 0, 1} }\n"),
             Contains(":3: ground{...} acts on cells") && !Contains("nested"));
  // an obstacle for veins is a hollow in the volume: said so (a walkthrough found it only in the docs)
  CHECK_THAT(load_error("volume { box = {min = {0, 0, 0}, max = {9, 9, 9}} }\ncolonisation {}\nball { radius = 2 }\n"),
             Contains(":3: ball{...} acts on cells") && Contains("nested shells make a hollow"));
}

TEST_CASE("volume{} and surface{} give space colonisation a 3-D domain", "[script][colonisation]") {
  namespace v = cellform::venation;
  auto cfg = load(
      "volume { box = { min = {-4, -4, 0}, max = {4, 4, 10} } }\n"
      "colonisation { type = 'closed', darts = 300 }\n");
  REQUIRE(cfg.colonisation);
  const v::Domain& d = cfg.colonisation->domain;
  CHECK(d.kind == v::DomainKind::box);
  CHECK(d.box_max == cellform::core::Vec3(4, 4, 10));
  REQUIRE(d.initial_nodes.size() == 1);
  CHECK(d.initial_nodes[0] == cellform::core::Vec3(0, 0, 0));     // the centre of the floor
  CHECK(cfg.colonisation->params.growth == v::GrowthMode::none);  // the 3-D default
  CHECK(cfg.colonisation->params.initial_scale == 1);
  CHECK(cfg.resolved["colonisation"]["growth"] == "none");
  CHECK(cfg.resolved["volume"]["seeds"].size() == 1);

  cfg = load("volume { ball = { centre = {0, 0, 5}, radius = 5 }, seeds = {0, 0, 2} }\ncolonisation {}\n");
  CHECK(cfg.colonisation->domain.kind == v::DomainKind::ball);
  CHECK(cfg.colonisation->domain.initial_nodes.at(0) == cellform::core::Vec3(0, 0, 2));
  cfg = load(
      "disc { radius = 3 }\npetiole { at = {0, -3, 0} }\nsurface { cells = true }\n"
      "colonisation { growth = 'none' }\nprint { shell = true }\n");
  CHECK(cfg.colonisation->on_cells);
  CHECK(cfg.colonisation->domain.kind == v::DomainKind::surface);
  CHECK(!cfg.initial_cells.empty());

  // a closed octahedron as a volume file, and with one face missing
  const auto dir = std::filesystem::temp_directory_path() / ("cellform-domain-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string verts = "v 2 0 0\nv -2 0 0\nv 0 2 0\nv 0 -2 0\nv 0 0 2\nv 0 0 -2\n";
  const std::string faces = "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\n";
  std::ofstream(dir / "closed.obj") << verts << faces << "f 1 4 6\n";
  std::ofstream(dir / "open.obj") << verts << faces;
  const std::string closed = (dir / "closed.obj").string(), open = (dir / "open.obj").string();
  cfg = load("volume { file = '" + closed + "', scale = 2, seeds = {{0, 0, -3}} }\ncolonisation {}\n");
  CHECK(cfg.colonisation->domain.kind == v::DomainKind::volume);
  CHECK(cfg.colonisation->domain.mesh.vertices[0].x() == 4);  // scaled
  CHECK_THAT(load_error("volume { file = '" + open + "', seeds = {{0, 0, 0}} }\ncolonisation {}\n"),
             Contains("test/leaf.lua:1:") && Contains("volume.file") && Contains("not closed"));
  CHECK_NOTHROW(load("surface { file = '" + open + "', seeds = {{2, 0, 0}} }\ncolonisation {}\n"));
  CHECK_THAT(load_error("surface { file = '" + open + "', seeds = {{0, 0, 0}} }\ncolonisation {}\n"),
             Contains("surface.seeds[1]") && Contains("not on the surface") &&
                 Contains("model units): it is 1.1547") &&  // 2 / sqrt(3) to every face's plane: how far, and where
                 Contains("the nearest point of the surface is {0.666667, 0.666667, 0.666667}"));
  // within a vein segment of it, a seed is moved onto the surface, with a note (a point on a round shape typed
  // where the mesh has facets), and run.json records where it was placed
  cfg = load("surface { file = '" + open + "', seeds = {{0.4, 0.4, 0.4}} }\ncolonisation {}\n");
  const cellform::core::Vec3 on = cfg.colonisation->domain.initial_nodes.at(0);
  CHECK(on.x() == Approx(2.0 / 3));
  CHECK(on.z() == Approx(2.0 / 3));
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:1: surface.seeds[1] {0.4, 0.4, 0.4} is 0.46188 model units off the "
                                    "surface: moved onto it, to {0.666667, 0.666667, 0.666667}"));
  CHECK(cfg.resolved["surface"]["seeds"][0][0] == on.x());
  CHECK_THAT(load_error("volume { file = '" + closed + "' }\ncolonisation {}\n"), Contains("needs seeds"));
  // domains are bounded like every script position (1e9 model units)
  CHECK_THAT(load_error("surface { file = '" + open + "', scale = 1e300, seeds = {{2, 0, 0}} }\ncolonisation {}\n"),
             Contains("test/leaf.lua:1: surface.file: with scale = 1e+300") && Contains("lies beyond 1e+09"));
  CHECK_THAT(load_error("volume { ball = { radius = 1e300 } }\ncolonisation {}\n"),
             Contains("volume.ball.radius must be a number from 0 (exclusive) to 1e+09"));
  // an outline file is used as drawn: the built-in outlines' values are refused beside it, and not recorded
  std::ofstream(dir / "fan.txt") << "0 0\n1 1\n0 2\n-1 1\n0 0\n";
  const std::string fan = (dir / "fan.txt").string();
  cfg = load("leaf { file = '" + fan + "' }\ncolonisation {}\n");
  CHECK(cfg.resolved["leaf"]["file"] == fan);
  for (const char* k : {"shape", "width", "teeth", "tooth_depth", "lobes", "lobe_depth"})
    CHECK_FALSE(cfg.resolved["leaf"].contains(k));
  CHECK(cfg.notes.empty());
  cfg = load("leaf { file = '" + fan + "', teeth = 20 }\ncolonisation {}\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:1: leaf.teeth has no effect beside leaf.file"));
  cfg = load("leaf { file = '" + fan + "' }\ncolonisation {}\n", {{"leaf.shape", "cordate"}});
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("--set leaf.shape=cordate: leaf.shape has no effect beside leaf.file"));
  CHECK_FALSE(cfg.resolved["leaf"].contains("shape"));
  // the same fan drawn pointing down: its length is half its farthest vertex's distance, and that is said
  std::ofstream(dir / "down.txt") << "0 0\n1 -1\n0 -2\n-1 -1\n0 0\n";
  cfg = load("leaf { file = '" + (dir / "down.txt").string() + "' }\ncolonisation {}\n");
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:1: leaf.file's outline does not point along +y") &&
                               Contains("its highest y is 0, its farthest vertex (0, -2)") &&
                               Contains("reaches twice as far as colonisation.initial_length and final_length say"));
  double lowest = 0;
  for (const auto& q : cfg.colonisation->leaf.outline.points) lowest = std::min(lowest, q.y());
  CHECK(lowest == -2.0);  // scaled by 1 / (2 / 2): twice the length
  std::filesystem::remove_all(dir);
  // so are the lobes of an outline without lobes, and a tooth depth without teeth
  cfg = load("leaf { shape = 'ovate', lobes = 2,\n lobe_depth = 0.9, tooth_depth = 0.1 }\ncolonisation {}\n");
  REQUIRE(cfg.notes.size() == 3);
  CHECK_THAT(cfg.notes[0], Contains("test/leaf.lua:1: leaf.lobes has no effect with shape = \"ovate\""));
  CHECK_THAT(cfg.notes[1], Contains("leaf.lobe_depth has no effect with shape = \"ovate\""));
  CHECK_THAT(cfg.notes[2], Contains("leaf.tooth_depth has no effect without teeth"));
  CHECK_FALSE(cfg.resolved["leaf"].contains("lobe_depth"));
  CHECK(
      load("leaf { shape = 'palmate', lobes = 3, lobe_depth = 0.5, teeth = 9, tooth_depth = 0.01 }\ncolonisation {}\n")
          .notes.empty());
  cfg = load("leaf { shape = 'lobed', lobes = 3 }\ncolonisation {}\n", {{"leaf.shape", "cordate"}});
  REQUIRE(cfg.notes.size() == 1);
  CHECK_THAT(cfg.notes[0], Contains("leaf.lobes has no effect with shape = \"cordate\""));

  CHECK_THAT(load_error("volume { box = { min = {0, 0, 0}, max = {1, 1, 1} }, seeds = {{0, 0, 2}} }\n"
                        "colonisation {}\n"),
             Contains("volume.seeds[1]") && Contains("not inside"));
  CHECK_THAT(load_error("volume { box = { min = {0, 0, 0}, max = {1, 1, 1} } }\n"
                        "colonisation { type = 'closed', neighbourhood = 'urquhart' }\n"),
             Contains("test/leaf.lua:2:") && Contains("colonisation.neighbourhood") && Contains("exact"));
  CHECK_THAT(load_error("volume { box = { min = {0, 0, 0}, max = {1, 1, 1} } }\n"
                        "colonisation { growth = 'marginal' }\n"),
             Contains("colonisation.growth") && Contains("does not grow"));
  CHECK_THAT(load_error("volume {}\ncolonisation {}\n"), Contains("exactly one of box"));
  CHECK_THAT(load_error("volume { box = { min = {0, 0, 0} } }\ncolonisation {}\n"), Contains("needs 'max'"));
  CHECK_THAT(load_error("volume { box = { min = {0, 0, 0}, max = {1, 1, 1} }, seeds = {{0, 0}} }\n"),
             Contains("volume.seeds") && Contains("entry 1"));
  CHECK_THAT(load_error("volume { ball = { radius = 2 } }\nleaf {}\ncolonisation {}\n"),
             Contains("test/leaf.lua:2:") && Contains("already grow in volume{...} (at test/leaf.lua:1);"));
  CHECK_THAT(load_error("volume { ball = { radius = 2 } }\n"), Contains("needs colonisation{...}"));
  CHECK_THAT(load_error("surface {}\ncolonisation {}\n"), Contains("either file"));
  CHECK_THAT(load_error("surface { cells = true }\ncolonisation {}\n"), Contains("place them with a shape"));
  CHECK_THAT(load_error("volume { ball = { radius = 2 } }\ncolonisation {}\ndisc { radius = 2 }\n"),
             Contains("cannot be combined"));
  CHECK_THAT(load_error("volume { ball = { radius = 2 } }\ncolonisation {}\nprint { shell = true }\n"),
             Contains("print{shell = true}"));
}

TEST_CASE("colonisation{growth = 'nonuniform'} takes growth tables or functions of y0 (Appendix A)",
          "[script][colonisation]") {
  const std::string head = "leaf { shape = 'ellipse' }\ncolonisation { growth = 'nonuniform', initial_length = 20,\n";
  auto cfg = load(head +
                  "  growth_x = {{0, 1.05}, {0.5, 1.1}, {1, 1.0}},\n"
                  "  growth_y = function(y0) return 1 + 0.02 * y0 end, growth_steps = 30 }\n");
  REQUIRE(cfg.colonisation);
  const auto& p = cfg.colonisation->params;
  CHECK(p.growth == cellform::venation::GrowthMode::nonuniform);
  CHECK(p.growth_steps == 30);
  CHECK(p.final_scale == 20);  // the size follows from the rates, not from final_length
  // heights in leaf lengths become model units of the initial leaf (x 20)
  REQUIRE(p.growth_x.y == std::vector<double>{0, 10, 20});
  CHECK(p.growth_x(5) == Approx(1.075));
  CHECK(p.growth_x(-3) == Approx(1.05));  // constant beyond the ends
  // the function is sampled at 257 heights from -0.5 to 1.5 leaf lengths, linear in between
  REQUIRE(p.growth_y.y.size() == 257);
  CHECK(p.growth_y.y.front() == Approx(-10));
  CHECK(p.growth_y.y.back() == Approx(30));
  CHECK(p.growth_y(7.3) == Approx(1 + 0.02 * 7.3 / 20));
  CHECK(cfg.resolved["colonisation"]["growth_x"].size() == 3);

  const std::string y_ok = "  growth_y = {{0, 1.01}}, growth_steps = 5 }\n";
  CHECK_THAT(load_error(head + "  growth_x = {{0, 1.1}, {0, 1.2}},\n" + y_ok),
             Contains("test/leaf.lua:2: colonisation.growth_x[2]") && Contains("increase strictly"));
  CHECK_THAT(load_error(head + "  growth_x = {{0, 1.1}, {1, 0}},\n" + y_ok),
             Contains("colonisation.growth_x[2]") && Contains("> 0"));
  CHECK_THAT(load_error(head + "  growth_x = {{0, 1.1}, {1, 0/0}},\n" + y_ok), Contains("colonisation.growth_x[2]"));
  CHECK_THAT(load_error(head + "  growth_x = {{0, 1.1}, {1}},\n" + y_ok), Contains("pair {y0, rate}"));
  CHECK_THAT(load_error(head + "  growth_x = {},\n" + y_ok), Contains("at least one {y0, rate}"));
  CHECK_THAT(load_error(head + "  growth_x = 3,\n" + y_ok), Contains("a table or a function"));
  CHECK_THAT(load_error(head + "  growth_x = function(y) return y - 0.5 end,\n" + y_ok),
             Contains("colonisation.growth_x(") && Contains("> 0") && Contains("REG_x > 0"));
  // a function's bad value is named at the function's line, as its wrong type is (it said the section's)
  CHECK_THAT(load_error("local function rate(y)\n  return 0/0\nend\n" + head + "  growth_y = rate,\n" +
                        "  growth_x = {{0, 1.01}}, growth_steps = 5 }\n"),
             Contains("test/leaf.lua:1: colonisation.growth_y(-0.5)") && Contains("REG_y > 0"));
  CHECK_THAT(load_error(head + "  growth_x = function(y) return 'fast' end,\n" + y_ok),
             Contains("must return a number"));
  CHECK_THAT(load_error(head + "  growth_x = function(y) error('no rate here') end,\n" + y_ok),
             Contains("no rate here") && Contains("colonisation.growth_x failed at y0 = -0.5"));
  // audit: any other error value, or a yield, said only "error object is not a string" or no line
  CHECK_THAT(load_error(head + "  growth_x = function(y) error(42) end,\n" + y_ok),
             Contains("growth_x failed at y0 = -0.5: test/leaf.lua:3: 42"));
  CHECK_THAT(load_error(head + "  growth_x = function(y) error({}) end,\n" + y_ok),
             Contains("test/leaf.lua:3: error() was raised with a table value"));
  CHECK_THAT(load_error(head + "  growth_x = function(y) coroutine.yield() end,\n" + y_ok),
             Contains("test/leaf.lua:3: attempt to yield from outside a coroutine"));
  // a growth function is called as the script loads, but it is no place to describe the scene
  for (const char* call : {"output { png = true }", "params { zz = 1 }", "cell { at = {0, 0, 0} }"})
    CHECK_THAT(load_error(head + "  growth_x = function(y) " + call + " return 1.1 end,\n" + y_ok),
               Contains("can only be called at the top level of the script, not inside the function "
                        "colonisation.growth_x"));
  CHECK_THAT(load_error(head + "  growth_y = {{0, 1.01}}, growth_steps = 5 }\n"), Contains("needs growth_x"));
  CHECK_THAT(load_error(head + "  growth_x = {{0, 1.01}}, growth_y = {{0, 1.01}} }\n"), Contains("growth_steps >= 1"));
  CHECK_THAT(load_error("colonisation { growth = 'marginal', growth_x = {{0, 1.1}} }\n"),
             Contains("growth_x applies only to growth = \"nonuniform\""));
  CHECK_THAT(load_error("colonisation { growth = 'none', growth_steps = 4 }\n"), Contains("growth_steps applies only"));
  // growth not given: the message says what that means, for a leaf and for a volume
  CHECK_THAT(
      load_error("volume { ball = { radius = 5 } }\ncolonisation { growth_steps = 5 }\n"),
      Contains("growth_steps applies only") && Contains("growth is not given") && !Contains("growth is \"marginal\""));
  // the leaf's size in a volume: refused, as growth is
  CHECK_THAT(load_error("volume { ball = { radius = 5 } }\ncolonisation { final_length = 400 }\n"),
             Contains("colonisation.final_length sizes a growing leaf blade; a volume{...} or surface{...} keeps"));
  CHECK_THAT(load_error(head + "  growth_x = {{0, 1.01}}, growth_y = {{0, 1.01}}, growth_steps = 5 }\n",
                        {{"colonisation.growth_x", "2"}}),
             Contains("cannot be set from the command line"));
}

TEST_CASE("output{png = true} needs a space-colonisation run", "[script][png]") {
  auto cfg = load("colonisation {}\noutput { png = true, png_size = 300 }\n");
  CHECK(cfg.output.png);
  CHECK(cfg.output.png_size == 300);
  CHECK_THAT(load_error("disc { radius = 2 }\noutput { png = true }\n"), Contains("it needs colonisation{...}"));
  CHECK_THAT(load_error("colonisation {}\noutput { png_size = 4 }\n"), Contains("output.png_size"));
}

TEST_CASE("output.every (frames of a cell run) is refused in a space-colonisation run, naming where it is set",
          "[script][colonisation]") {
  CHECK_THAT(load_error("colonisation {}\noutput { every = 5 }\n"), Contains(":2: output.every writes frames"));
  // from the command line: the --set is named (the script's output{} line, or none, was)
  CHECK_THAT(load_error("colonisation {}\noutput { ply = true }\n", {{"output.every", "5"}}),
             Contains("--set output.every=5: output.every writes frames"));
  CHECK_THAT(load_error("colonisation {}\n", {{"output.every", "5"}}),
             Contains("--set output.every=5: output.every writes frames"));
  // also when the run grows a cell sheet first: its message says so (the parameter table too)
  CHECK_THAT(load_error("disc { radius = 2 }\npetiole {}\nsurface { cells = true }\ncolonisation {}\n"
                        "output { every = 5 }\n"),
             Contains(":5: output.every writes frames of a cell run") && Contains("surface{cells = true}"));
}

TEST_CASE("leaf.fine_teeth sums a second wave of teeth into the margin (doubly serrate)", "[script][colonisation]") {
  // Runions 2005, Section 3.2: margins by "summing triangular waveforms of different amplitudes and
  // frequencies"; a script could give only one (a paper-fidelity audit)
  auto turns = [](const std::string& script) {  // the margin's changes between turning left and right
    const auto cfg = load(script);
    const auto& pts = cfg.colonisation->leaf.outline.points;
    int changes = 0, last = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const auto& a = pts[i];
      const auto& b = pts[(i + 1) % pts.size()];
      const auto& c = pts[(i + 2) % pts.size()];
      const double cross = (b.x() - a.x()) * (c.y() - b.y()) - (b.y() - a.y()) * (c.x() - b.x());
      const int sign = cross > 1e-12 ? 1 : cross < -1e-12 ? -1 : 0;
      if (sign != 0 && last != 0 && sign != last) ++changes;
      if (sign != 0) last = sign;
    }
    return changes;
  };
  const int smooth = turns("leaf { shape = 'ellipse' }\ncolonisation {}\n");
  const int serrate = turns("leaf { shape = 'ellipse', teeth = 20 }\ncolonisation {}\n");
  const int doubly = turns("leaf { shape = 'ellipse', teeth = 20, fine_teeth = 100 }\ncolonisation {}\n");
  INFO("turn changes: smooth " << smooth << ", 20 teeth " << serrate << ", and 100 fine " << doubly);
  CHECK(smooth == 0);
  CHECK(serrate >= 2 * 20 - 4);  // each tooth turns the margin at least twice (they fade near the petiole)
  CHECK(doubly > 3 * serrate);   // five times as many teeth on the teeth
  const auto cfg = load(
      "leaf { shape = 'ellipse', teeth = 20, fine_teeth = 100, fine_tooth_depth = 0.004 }\n"
      "colonisation {}\n");
  CHECK(cfg.resolved["leaf"]["fine_teeth"] == 100);
  CHECK(cfg.resolved["leaf"]["fine_tooth_depth"] == 0.004);
  // a depth without its teeth is noted, as tooth_depth is
  const auto noted = load("leaf { shape = 'ellipse', fine_tooth_depth = 0.01 }\ncolonisation {}\n");
  REQUIRE(noted.notes.size() == 1);
  CHECK_THAT(noted.notes[0], Contains("leaf.fine_tooth_depth has no effect without fine teeth"));
}

TEST_CASE("leaf.seed_points places the seed vein nodes by hand", "[script][colonisation]") {
  // Runions 2005: "positions of the initial points are specified by the user"; a script could only spread
  // them evenly along the base (a paper-fidelity audit)
  const auto cfg = load(
      "leaf { shape = 'ellipse', seed_points = {{-0.1, 0.05}, {0.1, 0.05}, {0, 0.5}} }\n"
      "colonisation {}\n");
  const auto& nodes = cfg.colonisation->leaf.initial_nodes;
  REQUIRE(nodes.size() == 3);
  CHECK(nodes[0] == cellform::venation::Vec2(-0.1, 0.05));
  CHECK(nodes[2] == cellform::venation::Vec2(0, 0.5));
  CHECK(cfg.resolved["leaf"]["seed_points"] == nlohmann::json::parse("[[-0.1, 0.05], [0.1, 0.05], [0, 0.5]]"));
  CHECK_FALSE(cfg.resolved["leaf"].contains("seeds"));
  CHECK(load("leaf { seed_points = {0, 0.2} }\ncolonisation {}\n").colonisation->leaf.initial_nodes.size() == 1);
  CHECK_THAT(load_error("leaf { shape = 'ellipse', seed_points = {{0, 0.05}, {0.9, 0.5}} }\ncolonisation {}\n"),
             Contains("test/leaf.lua:1") && Contains("leaf.seed_points[2] lies outside the blade"));
  // a closed pattern's seeds on one point never grow apart: refused, in the script's names, with leaf{}'s line;
  // in an open one the second is left alone, harmlessly
  CHECK_THAT(load_error("\nleaf { seed_points = {{0, 0.5}, {0, 0.5}} }\ncolonisation { type = 'closed' }\n"),
             Contains("test/leaf.lua:2: leaf.seed_points[2] repeats leaf.seed_points[1]"));
  CHECK(
      load("leaf { seed_points = {{0, 0.5}, {0, 0.5}} }\ncolonisation {}\n").colonisation->leaf.initial_nodes.size() ==
      2);
  CHECK_THAT(load_error("leaf { seeds = 3, seed_points = {{0, 0.05}} }\ncolonisation {}\n"),
             Contains("leaf.seed_points places the seed vein nodes by hand: leave out leaf.seeds"));
  CHECK_THAT(
      load_error("leaf { seed_points = {{0, 0.05, 0}} }\ncolonisation {}\n"),
      Contains("leaf.seed_points must be a list of points {{x, y}, ...} in leaf lengths; entry 1 is not {x, y}"));
}
