// Tests of venation/vein_io.h: the SVG drawing's physical units.
#include "venation/vein_io.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "tests/venation/leaf_fixtures.h"

using namespace cellform;
using Catch::Matchers::Contains;
using core::Index;
using core::kNoIndex;
using core::Vec3;
namespace v = cellform::venation;
using namespace cellform::test;

namespace {

/// A folder of this test process's own: ctest runs the test cases as processes side by side, and two
/// of them sharing a fixed name would remove each other's files.
std::filesystem::path scratch_dir(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()));
}

std::string read_text(const std::filesystem::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

/// Every number captured by the first group of `pattern` in `text`.
std::vector<double> captured(const std::string& text, const std::string& pattern) {
  std::vector<double> out;
  const std::regex re(pattern);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back(std::stod((*it)[1].str()));
  return out;
}

}  // namespace

TEST_CASE("the SVG is drawn in millimetres at svg size", "[vein_io]") {
  // a 40 x 10 model-unit box: a rectangle outline, a vein along its middle and one branch
  v::Outline outline;
  outline.points = {{-20, 0}, {20, 0}, {20, 10}, {-20, 10}};
  v::VeinTree t;
  t.positions = {Vec3(0, 0, 0), Vec3(0, 5, 0), Vec3(10, 8, 0)};
  t.parent = {kNoIndex, 0, 1};
  t.radius = {0.5, 0.5, 0.01};
  const auto dir = scratch_dir("cellform_vein_io_test");
  std::filesystem::create_directories(dir);
  v::SvgParams sp;
  sp.size = 120;  // mm for the 40 units: 3 mm per unit
  v::write_svg(dir / "leaf.svg", t, outline, sp);
  const std::string svg = read_text(dir / "leaf.svg");
  std::filesystem::remove_all(dir);

  // the page: 120 x 30 mm of drawing plus 5 mm on each side, and one user unit is one millimetre; and 1.5 mm
  // more below, where the midvein's round end (3 mm wide at the outline's edge) reaches (audit: it ran off
  // the page through the margin). The outline's 0.2 mm line is inside the 120 mm (audit: it reached 0.1 mm
  // into the margin): 2.995 mm per unit
  const std::vector<double> w = captured(svg, "width=\"([0-9.]+)mm\""), h = captured(svg, "height=\"([0-9.]+)mm\"");
  REQUIRE(w.size() == 1);
  REQUIRE(h.size() == 1);
  CHECK(w[0] == Approx(130).margin(1e-9));
  CHECK(h[0] == Approx(10.5 * 2.995 + 10.2).margin(6e-4));  // (3 decimals in the file)
  CHECK(svg.find("viewBox=\"0 0 130.000 41.648\"") != std::string::npos);

  // the outline's corners land 119.8 mm apart, their line inside the 5 mm margin, y up
  const std::vector<double> xs = captured(svg, "[ML]([0-9.]+) [0-9.]+");
  REQUIRE(xs.size() >= 4);
  CHECK(*std::min_element(xs.begin(), xs.end()) == Approx(5.1));
  CHECK(*std::max_element(xs.begin(), xs.end()) == Approx(124.9));
  // the midvein, base (y = 0) below, drawn from its end nearer the page corner where the pen starts
  CHECK(svg.find("M65.000 20.075 L65.000 35.050") != std::string::npos);

  // strokes: 2 r mm per unit for veins, the minimum for the thin branch, then the outline's own width
  const std::vector<double> strokes = captured(svg, "stroke-width=\"([0-9.]+)\"");
  REQUIRE(strokes.size() == 3);
  CHECK(strokes[2] == Approx(sp.outline_stroke));
  // the outline: a line to cut, in a layer of its own colour and its fixed number
  CHECK(svg.find("<g id=\"outline\" inkscape:groupmode=\"layer\" inkscape:label=\"100 outline\" stroke=\"#0000a0\" "
                 "stroke-linejoin=\"round\" fill=\"none\">") != std::string::npos);
  CHECK(svg.find("fill=\"#") == std::string::npos);  // nothing filled but the marked sources, of which none here
  CHECK(strokes[0] == Approx(2 * 0.5 * 2.995));      // the midvein: 2.995 mm wide
  CHECK(strokes[1] == Approx(sp.min_stroke));        // 0.06 mm drawn at the minimum
  // no orders computed: one layer of veins, then the outline's
  CHECK_THAT(svg, Contains("inkscape:label=\"1 veins\"") && Contains("inkscape:label=\"100 outline\""));

  // a given scale (a print's, mm per model unit) replaces the size
  sp.scale = 2;
  const auto dir2 = scratch_dir("cellform_vein_io_test2");
  std::filesystem::create_directories(dir2);
  v::write_svg(dir2 / "leaf.svg", t, outline, sp);
  const std::string scaled = read_text(dir2 / "leaf.svg");
  std::filesystem::remove_all(dir2);
  CHECK(scaled.find("width=\"90.200mm\" height=\"31.200mm\"") != std::string::npos);  // 40 x 10.5 units at 2 mm
}

namespace {
/// "width: d" of each path of the SVG of a hand-made tree, in order (the veins', then the outline's):
/// 0 - 1 - 2 - 3 - 4 in a line, all 0.5 wide but the last segment; a branch 1 - 5 of the same width; an
/// anastomosis 4 - 5. Drawn at 1 mm per unit: x -> 6 + x, y -> 5 + (5 - y).
std::vector<std::string> hand_tree_paths(bool join_veins, std::pair<Index, Index> loop = {4, 5}) {
  v::Outline outline;
  outline.points = {{-1, -1}, {10, -1}, {10, 5}, {-1, 5}};
  v::VeinTree t;
  t.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(4, 0, 0), Vec3(1, 2, 0)};
  t.parent = {kNoIndex, 0, 1, 2, 3, 1};
  t.radius = {0.5, 0.5, 0.5, 0.5, 0.25, 0.5};
  t.anastomoses = {loop};
  const auto dir = scratch_dir("cellform_vein_io_paths");
  std::filesystem::create_directories(dir);
  v::SvgParams sp;
  sp.scale = 1;
  sp.margin = 4.9;  // and half the outline's 0.2 mm line: the points 5 mm in
  sp.join_veins = join_veins;
  v::write_svg(dir / "p.svg", t, outline, sp);
  const std::string svg = read_text(dir / "p.svg");
  std::filesystem::remove_all(dir);
  std::vector<std::string> paths;
  const std::regex re("<path stroke-width=\"([0-9.]+)\" d=\"([^\"]*)\"/>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator(); ++it)
    paths.push_back((*it)[1].str() + ": " + (*it)[2].str());
  return paths;
}
}  // namespace

TEST_CASE("the SVG draws a vein as one path between branch points and width changes", "[vein_io]") {
  // the trunk 0-1 ends at the branch point 1; 1-2-3 runs on; 3-4 is thinner; the branch 1-5; the
  // anastomosis 4-5 on its own. Nearest-next from the page's corner (0, 0): the branch from 5 (the
  // anastomosis's end there is as near, but a later stroke), the trunk back from 1, 1-2-3, 3-4, then the
  // anastomosis from 4; the outline last
  const std::vector<std::string> expected{"1.000: M7.000 8.000 L7.000 10.000",
                                          "1.000: M7.000 10.000 L6.000 10.000",
                                          "1.000: M7.000 10.000 L8.000 10.000 L9.000 10.000",
                                          "0.500: M9.000 10.000 L10.000 10.000",
                                          "0.500: M10.000 10.000 L7.000 8.000",  // the tip radius, 0.25
                                          "0.200: M5.000 11.000 L16.000 11.000 L16.000 5.000 L5.000 5.000 Z"};
  CHECK(hand_tree_paths(false) == expected);
}

TEST_CASE("a loop's closing segment is drawn at the width of the finer vein it joins", "[vein_io]") {
  // 2 - 5 joins two veins 1 mm wide (the finest vein, 3 - 4, is 0.5 mm): 1 mm, not the finest width
  const auto paths = hand_tree_paths(false, {2, 5});
  CHECK(std::count(paths.begin(), paths.end(), "1.000: M7.000 8.000 L8.000 10.000") +
            std::count(paths.begin(), paths.end(), "1.000: M8.000 10.000 L7.000 8.000") ==
        1);
  // the finer vein's node listed first or second: 4 - 5 and 5 - 4 both at the 0.5 mm of 3 - 4's tip
  for (const std::pair<Index, Index>& loop : {std::pair<Index, Index>{4, 5}, std::pair<Index, Index>{5, 4}}) {
    const auto drawn = hand_tree_paths(false, loop);
    CHECK(std::count(drawn.begin(), drawn.end(), "0.500: M10.000 10.000 L7.000 8.000") +
              std::count(drawn.begin(), drawn.end(), "0.500: M7.000 8.000 L10.000 10.000") ==
          1);
  }
}

TEST_CASE("joined, the SVG draws each vein as one path at its length-weighted mean width", "[vein_io]") {
  // the first child of 1, 2, goes on (equal widths): the branch from 5 (nearest the page's corner), the
  // whole main vein from 0 at (1 + 1 + 1 + 0.5) / 4 mm, the anastomosis from 4, the outline
  const std::vector<std::string> expected{
      "1.000: M7.000 8.000 L7.000 10.000",
      "0.875: M6.000 10.000 L7.000 10.000 L8.000 10.000 L9.000 10.000 L10.000 10.000",
      "0.500: M10.000 10.000 L7.000 8.000", "0.200: M5.000 11.000 L16.000 11.000 L16.000 5.000 L5.000 5.000 Z"};
  CHECK(hand_tree_paths(true) == expected);
}

TEST_CASE("the SVG has a layer per vein order, each path in the layer of its segments' order", "[vein_io]") {
  const bool join = GENERATE(false, true);  // paths between branch points, or a path per vein
  auto [t, rep] = v::colonise(ellipse_leaf(30, 20), params(v::VenationType::closed, 1));
  v::compute_widths(t, {});
  REQUIRE(!t.anastomoses.empty());
  const std::uint32_t top = *std::max_element(t.order.begin(), t.order.end());
  REQUIRE(top >= 3);
  const auto dir = scratch_dir("cellform_vein_io_layers");
  std::filesystem::create_directories(dir);
  v::SvgParams sp;
  sp.scale = 10;
  sp.join_veins = join;
  v::write_svg(dir / "leaf.svg", t, ellipse_leaf(30, 20).outline, sp);
  const std::string svg = read_text(dir / "leaf.svg");
  std::filesystem::remove_all(dir);

  // the node at each drawn point (3 decimals of mm at 10 mm per unit: distinct for these nodes)
  const auto [lo, hi] = v::drawing_bounds(t, ellipse_leaf(30, 20).outline);
  std::map<std::string, Index> node_at;
  for (Index i = 0; i < t.size(); ++i) {
    char key[64];
    std::snprintf(key, sizeof key, "%.3f %.3f", (t.positions[i].x() - lo.x()) * 10 + 5.1,  // margin, half line
                  (hi.y() - t.positions[i].y()) * 10 + 5.1);
    REQUIRE(node_at.emplace(key, i).second);
  }
  // every segment once, in the layer of its order: a tree edge's child node's, an anastomosis's higher end
  std::map<std::pair<Index, Index>, std::uint32_t> want;
  for (Index i = 0; i < t.size(); ++i)
    if (t.parent[i] != kNoIndex) want[{std::min(i, t.parent[i]), std::max(i, t.parent[i])}] = t.order[i];
  for (const auto& [a, b] : t.anastomoses) want[{std::min(a, b), std::max(a, b)}] = std::max(t.order[a], t.order[b]);
  std::map<std::pair<Index, Index>, std::uint32_t> drawn;
  std::vector<std::string> labels, colours;
  const std::regex layer_re(
      "<g id=\"([a-z0-9-]+)\" inkscape:groupmode=\"layer\" inkscape:label=\"([^\"]*)\"( stroke=\"(#[0-9a-f]+)\")?");
  const std::regex path_re("<path stroke-width=\"[0-9.]+\" d=\"([^\"]*)\"/>"), point_re("[ML]([0-9.]+ [0-9.]+)");
  std::uint32_t layer_order = 0;
  bool in_outline = false;
  std::size_t duplicates = 0, unknown = 0, misplaced = 0, paths = 0, broken = 0;
  std::istringstream lines(svg);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_search(line, m, layer_re)) {
      labels.push_back(m[2].str());
      colours.push_back(m[4].str());
      const std::string id = m[1].str();
      layer_order = id.rfind("veins-order-", 0) == 0 ? static_cast<std::uint32_t>(std::stoul(id.substr(12))) : 0;
      in_outline = id == "outline";
      continue;
    }
    if (in_outline || !std::regex_search(line, m, path_re)) continue;
    const std::string d = m[1].str();
    std::vector<Index> nodes;
    for (auto it = std::sregex_iterator(d.begin(), d.end(), point_re); it != std::sregex_iterator(); ++it) {
      const auto at = node_at.find((*it)[1].str());
      REQUIRE(at != node_at.end());
      nodes.push_back(at->second);
    }
    ++paths;
    // a vein's path runs from parent to child (either way round) but for an anastomosis, a path of two nodes
    if (nodes.size() > 2) {
      const bool down = t.parent[nodes[1]] == nodes[0];
      for (std::size_t k = 0; k + 1 < nodes.size(); ++k)
        broken += down ? t.parent[nodes[k + 1]] != nodes[k] : t.parent[nodes[k]] != nodes[k + 1];
    }
    for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
      const std::pair<Index, Index> e{std::min(nodes[k], nodes[k + 1]), std::max(nodes[k], nodes[k + 1])};
      const auto it = want.find(e);
      unknown += it == want.end();
      misplaced += it != want.end() && it->second != layer_order;
      duplicates += !drawn.emplace(e, layer_order).second;
    }
  }
  CHECK(unknown == 0);
  CHECK(misplaced == 0);
  CHECK(duplicates == 0);
  CHECK(drawn.size() == want.size());
  CHECK(broken == 0);
  // a path per vein ends at a tip (the widest child goes on in its parent's order): one per tip and
  // anastomosis; between branch points there are more
  std::vector<int> children(t.size(), 0);
  for (Index i = 0; i < t.size(); ++i)
    if (t.parent[i] != kNoIndex) ++children[t.parent[i]];
  const auto tips = static_cast<std::size_t>(std::count(children.begin(), children.end(), 0));
  if (join)
    CHECK(paths == tips + t.anastomoses.size());
  else
    CHECK(paths > tips + t.anastomoses.size());
  // layers 1 .. top by order (every order from 1 to the highest has a vein), then the outline as layer 100
  std::vector<std::string> expected;
  for (std::uint32_t o = 1; o <= top; ++o)
    expected.push_back(std::to_string(o) + " veins of order " + std::to_string(o));
  expected.push_back("100 outline");
  CHECK(labels == expected);
  // each layer its own colour (up to twelve orders), the outline's too: software that separates a
  // drawing's operations by colour keeps the layers apart
  REQUIRE(top <= 12);
  std::vector<std::string> distinct = colours;
  std::sort(distinct.begin(), distinct.end());
  CHECK(std::unique(distinct.begin(), distinct.end()) == distinct.end());
}

TEST_CASE("the SVG's finest orders share the last layer colour, never the midvein's", "[vein_io]") {
  // a chain of 15 nodes whose segments have orders 1 to 14
  v::VeinTree t;
  for (Index i = 0; i < 15; ++i) {
    t.positions.push_back(Vec3(i, (i % 2) * 0.5, 0));
    t.parent.push_back(i == 0 ? kNoIndex : i - 1);
    t.radius.push_back(0.1);
    t.order.push_back(i == 0 ? 1 : i);
  }
  v::Outline outline;
  outline.points = {{-1, -1}, {15, -1}, {15, 2}, {-1, 2}};
  const auto dir = scratch_dir("cellform_vein_io_colours");
  std::filesystem::create_directories(dir);
  v::write_svg(dir / "leaf.svg", t, outline);
  const std::string svg = read_text(dir / "leaf.svg");
  std::filesystem::remove_all(dir);
  std::map<std::uint32_t, std::string> colour;
  const std::regex layer_re("<g id=\"veins-order-([0-9]+)\"[^>]* stroke=\"(#[0-9a-f]+)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), layer_re); it != std::sregex_iterator(); ++it)
    colour[static_cast<std::uint32_t>(std::stoul((*it)[1].str()))] = (*it)[2].str();
  REQUIRE(colour.size() == 14);
  const std::set<std::string> first_eleven = [&] {
    std::set<std::string> s;
    for (std::uint32_t o = 1; o <= 11; ++o) s.insert(colour[o]);
    return s;
  }();
  CHECK(first_eleven.size() == 11);
  for (std::uint32_t o = 12; o <= 14; ++o) {
    INFO("order " << o);
    CHECK(colour[o] == colour[12]);
    CHECK(first_eleven.count(colour[o]) == 0);
  }
}

TEST_CASE("SVG, PLY and OBJ output", "[colonisation]") {
  auto [t, rep] = v::colonise(ellipse_leaf(30, 20), params(v::VenationType::closed, 1));
  v::compute_widths(t, {});
  const auto dir = scratch_dir("cellform_colonisation_test");
  std::filesystem::create_directories(dir);
  v::write_svg(dir / "leaf.svg", t, ellipse_leaf(30, 20).outline);
  v::write_vein_ply(dir / "veins.ply", t);
  v::write_vein_obj(dir / "veins.obj", t);
  std::ifstream svg(dir / "leaf.svg");
  std::stringstream s;
  s << svg.rdbuf();
  const std::string text = s.str();
  CHECK_THAT(text, Contains("<svg") && Contains("</svg>"));
  const auto edges = t.edges();
  // every edge is drawn once: one "L" per segment in the veins' layers (paths join segments into
  // polylines); the outline's layer comes after them
  const std::size_t group = text.find("<g "), group_end = text.find("<g id=\"outline\"");
  REQUIRE(group != std::string::npos);
  REQUIRE(group_end != std::string::npos);
  std::size_t ls = 0;
  for (std::size_t at = text.find(" L", group); at < group_end; at = text.find(" L", at + 2)) ++ls;
  CHECK(ls == edges.size());
  std::stringstream all;
  all << std::ifstream(dir / "veins.ply", std::ios::binary).rdbuf();
  const std::string ply = all.str();
  CHECK(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0) == 0);  // as the cell runs' veins.ply
  CHECK_THAT(ply, Contains("element vertex " + std::to_string(t.size())) &&
                      Contains("property double x\nproperty double y\nproperty double z\nproperty float flow\n"
                               "property float radius\nproperty int order\n") &&
                      Contains("element edge " + std::to_string(edges.size())));
  // the body: 36 bytes per node (x y z as doubles, flow radius order), then 8 per edge, child -> parent first
  const std::size_t body = ply.find("end_header\n") + 11;
  REQUIRE(ply.size() == body + 36 * t.size() + 8 * edges.size());
  auto f32 = [&](std::size_t at) {
    float v;
    std::memcpy(&v, ply.data() + at, 4);
    return v;
  };
  auto i32 = [&](std::size_t at) {
    std::int32_t v;
    std::memcpy(&v, ply.data() + at, 4);
    return v;
  };
  const Index last = static_cast<Index>(t.size() - 1);
  double x = 0;
  std::memcpy(&x, ply.data() + body + 36 * last, 8);
  CHECK(x == t.positions[last].x());  // exact, a double (a float snapped coordinates far from the origin)
  CHECK(f32(body + 36 * last + 24) == static_cast<float>(t.flow[last]));
  CHECK(f32(body + 36 * last + 28) == static_cast<float>(t.radius[last]));
  CHECK(i32(body + 36 * last + 32) == static_cast<std::int32_t>(t.order[last]));
  const std::size_t first_edge = body + 36 * t.size();
  REQUIRE(t.parent[1] != kNoIndex);
  CHECK(i32(first_edge) == 1);  // node 0 is the seed: the first edge is node 1's, to its parent
  CHECK(i32(first_edge + 4) == static_cast<std::int32_t>(t.parent[1]));
  std::ifstream obj(dir / "veins.obj");
  std::string line;
  std::size_t v_lines = 0, l_lines = 0, a_lines = 0;
  std::multiset<std::pair<Index, Index>> segments;  // of the polylines, undirected, 0-based
  while (std::getline(obj, line)) {
    v_lines += line.rfind("v ", 0) == 0;
    a_lines += line.rfind("#a ", 0) == 0;
    if (line.rfind("l ", 0) != 0) continue;
    ++l_lines;
    std::istringstream in(line.substr(2));
    std::vector<Index> vs;
    for (Index v; in >> v;) vs.push_back(v - 1);
    for (std::size_t i = 0; i + 1 < vs.size(); ++i)
      segments.insert({std::min(vs[i], vs[i + 1]), std::max(vs[i], vs[i + 1])});
  }
  CHECK(v_lines == t.size());
  CHECK(a_lines == t.size());
  CHECK(l_lines < edges.size());  // a polyline per branch, not per segment
  std::multiset<std::pair<Index, Index>> want;
  for (const auto& [a, b] : edges) want.insert({std::min<Index>(a, b), std::max<Index>(a, b)});
  CHECK(segments == want);
  std::filesystem::remove_all(dir);
}
