// Every example script runs on small settings, so examples cannot rot.
#include <catch2/catch.hpp>
#include <cstring>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>

#include "export/vein_png.h"
#include "tests/app/test_util.h"

using namespace cellform::test;
using namespace cellform;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("every example runs on small settings", "[examples]") {
  std::vector<fs::path> scripts;
  for (const auto& e : fs::directory_iterator(fs::path(CELLFORM_SOURCE_DIR) / "examples"))
    if (e.path().extension() == ".lua") scripts.push_back(e.path());
  std::sort(scripts.begin(), scripts.end());
  REQUIRE(scripts.size() >= 4);
  TempDir t("examples");
  for (const fs::path& s : scripts) {
    DYNAMIC_SECTION(s.filename().string()) {
      const fs::path out = t.path / s.stem();
      // cells capped, where there are cells (a space-colonisation run refuses settings of cells it has not)
      const std::string text = slurp(s);
      const bool no_cells =
          text.find("colonisation") != std::string::npos && text.find("cells = true") == std::string::npos;
      std::vector<std::string> args{"run", s.string(), "--out", out.string(), "--quiet", "--steps", "60"};
      if (!no_cells) args.insert(args.end(), {"--set", "division.max_cells=1500"});
      // a printed shell is voxelised at 0.2 mm whatever the cell count: print it 40 mm across
      if (text.find("shell = true") != std::string::npos) args.insert(args.end(), {"--set", "print.size=40"});
      const auto r = cli(args);
      INFO(r.err);
      REQUIRE(r.code == 0);
      const auto run = nlohmann::json::parse(slurp(out / "run.json"));
      if (run.value("mode", "") == "colonisation") {  // space colonisation: veins in a leaf, volume or surface
        CHECK(run["steps"]["completed"].get<int>() <= 60);
        CHECK(run["veins"]["nodes"].get<int>() > 10);
        CHECK(fs::file_size(out / "veins.ply") > 0);
        if (run["domain"] == "leaf") {
          CHECK(fs::file_size(out / "veins.svg") > 0);
        } else {  // a 3-D structural example prints as one watertight piece
          REQUIRE(run.contains("print"));
          CHECK(run["print"]["parts"] == 1);
          const auto check = cli({"check", (out / "printable.stl").string(), "--json"});
          CHECK(nlohmann::json::parse(check.out)["printable"] == true);
        }
      } else {
        CHECK(run["steps"]["completed"] == 60);
        if (run.contains("print")) CHECK(!run["print"].contains("skipped"));  // 60 steps grow enough to print
        CHECK(run["cells"]["final"].get<int>() >= run["cells"]["initial"].get<int>());
        CHECK(fs::file_size(out / "cells.ply") > 0);
      }
    }
  }
}

TEST_CASE("the first script of docs/scripting.md grows a leaf, as copied", "[examples]") {
  // the block a new user copies first: it must grow well beyond its disc with the documented defaults
  const std::string doc = slurp(fs::path(CELLFORM_SOURCE_DIR) / "docs" / "scripting.md");
  const auto start = doc.find("```lua\n");
  REQUIRE(start != std::string::npos);
  const auto end = doc.find("```", start + 7);
  REQUIRE(end != std::string::npos);
  TempDir t("doc-example");
  const fs::path script = t.write("doc.lua", doc.substr(start + 7, end - start - 7));
  const auto r = cli({"run", script.string(), "--out", (t.path / "o").string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto run = nlohmann::json::parse(slurp(t.path / "o" / "run.json"));
  INFO(run["cells"].dump());
  // 62 cells at the start; with division.radius = 1.5 the sheet stalled at 99
  CHECK(run["cells"]["final"].get<int>() > 5 * run["cells"]["initial"].get<int>());
  // its petiole drains a venation{...}: veins grow (without it the petiole was only a fixed cell)
  CHECK(run["veins"]["vein_cells"].get<int>() > 0);
  CHECK_THAT(r.err, !Contains("petiole"));
}

namespace {

/// One Table 1 row of Runions et al. 2005 as a preset in examples/colonisation/ uses it.
struct Preset {
  const char* file;
  const char* test_scale;  // --set scale=... for a quick run
  const char* extra;       // another --set, or ""
  bool closed;
  double kill_distance, birth_distance, initial_length, darts;  // Table 1: d_k, b_s, L_i, rho x 10^6
  double final_length, length_step;                             // Table 1: L_f, Delta L (0: no such growth)
  const char* growth;
  double murray_exponent;
  double vein_birth_distance = 0;  // b_v where a preset departs from Table 1's b_v = b_s (0: it does not)
};

/// The vein graph of veins.ply: node count, edges, and the independent cycles (edges - nodes + parts).
struct Graph {
  std::size_t nodes = 0, edges = 0, parts = 0, cycles = 0;
};

Graph read_vein_graph(const fs::path& ply) {
  const std::string bytes = slurp(ply);
  std::istringstream in(bytes);
  std::string line;
  Graph g;
  std::size_t vertex_bytes = 0;  // binary little-endian: 8 bytes per double, 4 per float or int property
  bool in_vertex = false;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream ls(line);
    std::string a, b;
    std::size_t n = 0;
    ls >> a >> b >> n;
    if (a == "format") REQUIRE(b == "binary_little_endian");
    if (a == "element") in_vertex = b == "vertex";
    if (a == "element" && b == "vertex") g.nodes = n;
    if (a == "element" && b == "edge") g.edges = n;
    if (a == "property" && in_vertex) vertex_bytes += b == "double" ? 8 : 4;
  }
  std::size_t at = static_cast<std::size_t>(in.tellg()) + g.nodes * vertex_bytes;
  REQUIRE(bytes.size() == at + g.edges * 8);
  auto next_int = [&] {
    std::int32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    at += 4;
    return static_cast<std::size_t>(v);
  };
  std::vector<std::size_t> up(g.nodes);
  std::iota(up.begin(), up.end(), 0);
  auto find = [&](std::size_t x) {
    while (up[x] != x) x = up[x] = up[up[x]];
    return x;
  };
  std::size_t merged = 0;
  for (std::size_t e = 0; e < g.edges; ++e) {
    const std::size_t a = next_int(), b = next_int();
    REQUIRE(a < g.nodes);
    REQUIRE(b < g.nodes);
    const std::size_t ra = find(a), rb = find(b);
    if (ra != rb) {
      up[ra] = rb;
      ++merged;
    }
  }
  g.parts = g.nodes - merged;
  g.cycles = g.edges - merged;
  return g;
}

}  // namespace

TEST_CASE("every Table 1 preset runs small and keeps the paper's parameters", "[examples][colonisation]") {
  // Runions et al. 2005, Table 1 (initial_length before `scale`)
  const std::vector<Preset> presets = {
      {"parameter_search", "0.12", "panel=e", true, 1, 10, 270, 600, 1600, 8, "marginal", 2},
      {"slow_marginal_growth", "0.0015", "", false, 40, 1, 4500, 300, 112000, 34, "marginal", 2, 40},
      {"ginkgo", "0.004", "", false, 100, 1, 10, 300, 50000, 15, "marginal", 2, 100},
      {"alchemilla", "0.02", "", false, 10, 1, 3200, 200, 4500, 9, "marginal", 2},
      {"sweetgum", "0.01", "", false, 1, 1, 1200, 200, 6700, 7, "marginal", 2},
      {"toothed_margin", "0.008", "", true, 1, 10, 6600, 10, 26000, 40, "marginal", 2},
      {"tertiary_veins", "0.006", "", true, 1, 1, 3500, 20, 24000, 60, "marginal", 2},
      {"orchid", "0.02", "", true, 1, 10, 6500, 600, 0, 0, "none", 2},
      {"reticulate", "0.03", "", true, 1, 15, 225, 200, 4500, 40.5, "isogonic", 2},
      {"nankin_cherry", "0.03", "", false, 30, 1, 1100, 40, 5500, 11, "marginal", 2},
      {"grass", "0.04", "", true, 1, 30, 13000, 100, 0, 0, "none", 2},
      {"poplar", "0.01", "", true, 1, 2, 115, 200, 3500, 9, "isogonic", 2},
      {"developmental", "0.5", "", true, 1, 3, 23, 5000, 0, 0, "nonuniform", 3},
      {"trillium", "0.06", "", true, 1, 30, 4500, 100, 0, 0, "none", 2},
  };
  // every preset is listed here, so none can rot untested
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(fs::path(CELLFORM_SOURCE_DIR) / "examples" / "colonisation"))
    if (e.path().extension() == ".lua") files.push_back(e.path().stem().string());
  std::sort(files.begin(), files.end());
  std::vector<std::string> listed;
  for (const Preset& p : presets) listed.push_back(p.file);
  std::sort(listed.begin(), listed.end());
  CHECK(files == listed);

  TempDir t("presets");
  for (const Preset& p : presets) {
    DYNAMIC_SECTION(p.file) {
      const fs::path script =
          fs::path(CELLFORM_SOURCE_DIR) / "examples" / "colonisation" / (std::string(p.file) + ".lua");
      const fs::path out = t.path / p.file;
      std::vector<std::string> args{"run",
                                    script.string(),
                                    "--out",
                                    out.string(),
                                    "--quiet",
                                    "--set",
                                    std::string("scale=") + p.test_scale,
                                    "--set",
                                    "output.png_size=512"};  // (veins.png: each preset asks for it)
      if (*p.extra) args.insert(args.end(), {"--set", p.extra});
      const auto r = cli(args);
      INFO(r.err);
      REQUIRE(r.code == 0);
      const auto run = nlohmann::json::parse(slurp(out / "run.json"));
      const auto& c = run["parameters"]["colonisation"];
      CHECK(c["type"] == (p.closed ? "closed" : "open"));
      CHECK(c["growth"] == p.growth);
      CHECK(c["birth_distance"].get<double>() == p.birth_distance);
      // run.json gives the b_v used: b_s where the preset gives 0 (Table 1's b_v = b_s)
      CHECK(c["vein_birth_distance"].get<double>() ==
            (p.vein_birth_distance > 0 ? p.vein_birth_distance : p.birth_distance));
      CHECK(c["murray_exponent"].get<double>() == p.murray_exponent);
      CHECK(c["kill_distance"].get<double>() == p.kill_distance);
      CHECK(c["darts"].get<double>() == p.darts);
      CHECK(c["initial_length"].get<double>() == Approx(p.initial_length * std::stod(p.test_scale)));
      if (p.final_length > 0) {
        CHECK(c["final_length"].get<double>() == Approx(p.final_length * std::stod(p.test_scale)));
        CHECK(c["length_step"].get<double>() == Approx(p.length_step * std::stod(p.test_scale)));
      } else {  // no growth, or growth by functions (developmental: L_f checked below)
        CHECK(!c.contains("final_length"));
      }
      CHECK((run["status"] == "complete" || run["status"] == "stalled"));

      const Graph g = read_vein_graph(out / "veins.ply");
      CHECK(g.nodes == run["veins"]["nodes"].get<std::size_t>());
      CHECK(g.nodes > 40);
      // loops are the graph's independent cycles; each anastomosis closes one, but for those joining the trees
      // of separate seed nodes (grass)
      CHECK(g.cycles == run["veins"]["loops"].get<std::size_t>());
      if (std::string(p.file) == "grass")
        CHECK(g.cycles < run["veins"]["anastomoses"].get<std::size_t>());
      else
        CHECK(g.cycles == run["veins"]["anastomoses"].get<std::size_t>());
      CHECK(g.parts == 1);  // one connected network: the seeds' trees are joined
      if (p.closed) {
        CHECK(g.cycles > 0);  // anastomoses close loops
      } else {
        CHECK(g.cycles == 0);  // open: a tree from the one seed node
      }
      CHECK(fs::file_size(out / "veins.svg") > 0);
      // the PNG preview beside it: the requested size on the longer side, background and veins drawn
      const exporters::Image img = exporters::read_png(out / "veins.png");
      CHECK(std::max(img.width, img.height) == 512);
      CHECK((img.at(0, 0) & 0xffffff) == exporters::PngParams{}.background);
      // a blank border as veins.svg has (5 mm of 210): 12 pixels here, on every side, the innermost of which
      // the outline's antialiased line may touch (it was 10 pixels at any size)
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
          if (std::min({x, y, img.width - 1 - x, img.height - 1 - y}) < 11)
            REQUIRE((img.at(x, y) & 0xffffff) == exporters::PngParams{}.background);
      // vein pixels: dark green (G 0x3a; antialiased thin veins lighter), unlike blade (0xec) and margin (0x7a)
      CHECK(std::count_if(img.pixels.begin(), img.pixels.end(),
                          [](std::uint32_t px) { return ((px >> 8) & 0xff) < 0x60; }) > 20);
      REQUIRE(fs::exists(out / "printable.stl"));
      CHECK(run["print"]["parts"] == 1);
      const auto check = cli({"check", (out / "printable.stl").string(), "--json"});
      INFO(check.out << check.err);
      CHECK(nlohmann::json::parse(check.out)["printable"] == true);  // watertight, manifold, no self-intersections
      if (std::string(p.file) == "developmental") {
        // the growth functions are calibrated so that the leaf grows from L_i to L_f = 184 (Table 1)
        CHECK(run["veins"]["leaf_length"].get<double>() == Approx(184 * std::stod(p.test_scale)).epsilon(0.02));
        // and from a narrow to an almost circular blade (Figure 5b): the outline drawn in veins.svg is an
        // ellipse 0.9 times as wide as long (audit: a diamond with concave sides, 0.26 wide at a tenth of its
        // length, before the horizontal rates were a lookup table made for it)
        const std::string svg = slurp(out / "veins.svg");
        const auto layer = svg.find("inkscape:label=\"100 outline\"");
        REQUIRE(layer != std::string::npos);
        const auto d = svg.find(" d=\"", layer) + 4;
        std::istringstream path(svg.substr(d, svg.find('"', d) - d));
        std::vector<std::array<double, 2>> pts;
        for (std::string op; path >> op && op != "Z";) {  // "Mx y Lx y ... Z"
          std::array<double, 2> q{};
          path >> q[1];
          q[0] = std::stod(op.substr(1));
          pts.push_back(q);
        }
        REQUIRE(pts.size() > 40);
        double lo = 1e300, hi = -1e300, left = 1e300, right = -1e300;
        for (const auto& q : pts)
          lo = std::min(lo, q[1]), hi = std::max(hi, q[1]), left = std::min(left, q[0]), right = std::max(right, q[0]);
        const double length = hi - lo;
        CHECK((right - left) / length == Approx(0.9).epsilon(0.02));
        for (const double f : {0.1, 0.3, 0.5, 0.7, 0.9}) {  // the width across at each height
          const double y = lo + f * length;
          double a0 = 1e300, a1 = -1e300;
          for (std::size_t k = 0; k < pts.size(); ++k) {
            const auto& u = pts[k];
            const auto& v = pts[(k + 1) % pts.size()];
            if ((u[1] - y) * (v[1] - y) < 0) {
              const double x = u[0] + (y - u[1]) * (v[0] - u[0]) / (v[1] - u[1]);
              a0 = std::min(a0, x), a1 = std::max(a1, x);
            }
          }
          INFO("width at " << f << " of the length");
          CHECK((a1 - a0) / length == Approx(0.9 * std::sqrt(1 - (2 * f - 1) * (2 * f - 1))).epsilon(0.04));
        }
      }
    }
  }
}

namespace {

/// The positions of an OBJ file's `v` lines, in order (faces, lines and the rest skipped).
std::vector<std::array<double, 3>> obj_vertices(const fs::path& path) {
  std::vector<std::array<double, 3>> out;
  std::istringstream obj(slurp(path));
  for (std::string line; std::getline(obj, line);)
    if (line.rfind("v ", 0) == 0) {
      std::array<double, 3> p{};
      std::istringstream(line.substr(2)) >> p[0] >> p[1] >> p[2];
      out.push_back(p);
    }
  return out;
}

}  // namespace

TEST_CASE("the ribbed vault's veins stand on each of its six supports", "[examples]") {
  // examples/ribbed_shell.lua at seed 1 (its header says why), but for the shell (its thickening is not what
  // is tested here); some supports end up off the grown sheet's triangles, and a stem joins them to their veins
  TempDir t("ribbed-supports");
  const fs::path out = t.path / "o";
  const auto r = cli({"run", (fs::path(CELLFORM_SOURCE_DIR) / "examples" / "ribbed_shell.lua").string(), "--out",
                      out.string(), "--set", "print.shell=false", "--set", "print.pieces=any", "--seed", "1"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::vector<std::array<double, 3>> nodes = obj_vertices(out / "veins.obj");
  for (int i = 0; i < 6; ++i) {
    const double a = i / 6.0 * 2 * M_PI, x = 6 * std::cos(a), y = 6 * std::sin(a), z = 0.5;
    double nearest = 1e9;
    for (const auto& p : nodes) nearest = std::min(nearest, std::hypot(p[0] - x, p[1] - y, p[2] - z));
    INFO("support " << i);
    CHECK(nearest < 1e-6);
  }
  const auto run = nlohmann::json::parse(slurp(out / "run.json"));
  CHECK(nodes.size() == run["veins"]["nodes"].get<std::size_t>() + run["veins"].value("stems", std::size_t{0}));
  // the closing line counts the nodes the files hold, stems too (at the default seed it said 498 of veins.obj's 500)
  CHECK_THAT(r.out, Contains(" steps, " + std::to_string(nodes.size()) + " vein nodes, "));
  // at this seed a source is left behind a fold of the sheet (the header says so): the note's remedy is for a grown
  // sheet, not a mesh file
  CHECK(run["status"] == "stalled");
  CHECK_THAT(r.err, Contains("1 auxin source is left") && Contains("Grow such a sheet larger (cells.rest_length)") &&
                        !Contains("surface{scale"));
}

TEST_CASE("the coral and the flower grow a folded sheet, not a packed foam, and print in one piece", "[examples]") {
  // In a sheet each cell has its ring of about six neighbours within one rest length (1 model unit in
  // both scripts); folds packed together, as growth by age packed them, put 8 to 10 there (median, at
  // 2,000 cells).
  TempDir t("sheet-examples");
  for (const char* name : {"coral", "flower"}) {
    DYNAMIC_SECTION(name) {
      const fs::path out = t.path / name;
      const auto r = cli({"run", (fs::path(CELLFORM_SOURCE_DIR) / "examples" / (std::string(name) + ".lua")).string(),
                          "--out", out.string(), "--quiet", "--set", "size=2000", "--set", "print.size=40"});
      INFO(r.err);
      REQUIRE(r.code == 0);
      const std::vector<std::array<double, 3>> cells = obj_vertices(out / "cells.obj");
      REQUIRE(cells.size() == 2000);
      std::vector<int> within(cells.size(), 0);
      std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
      for (std::size_t i = 0; i < cells.size(); ++i) {
        for (std::size_t j = 0; j < cells.size(); ++j)
          if (j != i && std::hypot(cells[i][0] - cells[j][0], cells[i][1] - cells[j][1], cells[i][2] - cells[j][2]) < 1)
            ++within[i];
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], cells[i][k]);
          hi[k] = std::max(hi[k], cells[i][k]);
        }
      }
      std::nth_element(within.begin(), within.begin() + within.size() / 2, within.end());
      CHECK(within[within.size() / 2] <= 6);
      CHECK(hi[0] - lo[0] > 10);
      CHECK(hi[1] - lo[1] > 10);
      CHECK(hi[2] - lo[2] > 5);  // a 3-D form, not a flat disc
      // and its shell prints in one piece (40 mm across, to keep the test short)
      CHECK(nlohmann::json::parse(slurp(out / "run.json"))["print"]["parts"] == 1);
    }
  }
}
