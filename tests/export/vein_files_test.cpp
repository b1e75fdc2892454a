// Tests of export/vein_files.h: the vein graph read back by an independent PLY reader and OBJ parser.
#include "export/vein_files.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "tests/export/ply_reader.h"

using namespace cellform;
using core::Vec3;
using test::parse_ply;
using test::slurp;

namespace fs = std::filesystem;

namespace {

// Two trees: 0 <- 1 <- 2 <- 3 with a branch 2 <- 4 <- 5 (a fork at 2), and 6 <- 7 (edges run child -> parent).
// Node k is cell 10 - k; cell ids are 500 + cell, and cell 10's id needs more than 32 bits (the file keeps 32).
struct Graph {
  cells::Cells cells;
  venation::VeinGraph g;
};

Graph make_graph(const Vec3& offset = Vec3::Zero()) {
  Graph r;
  for (int i = 0; i <= 10; ++i) cells::add_cell(r.cells, Vec3(i, 0, 0));
  for (std::size_t i = 0; i < r.cells.size(); ++i) r.cells.id[i] = 500 + i;
  r.cells.id[10] = (std::uint64_t{1} << 32) + 9;
  for (int k = 0; k < 8; ++k) {
    r.g.cell.push_back(static_cast<core::Index>(10 - k));
    r.g.position.push_back(offset + Vec3(0.1 * k, std::sqrt(2.0) * k, -1.0 / 3 * k));
    r.g.flow.push_back(100.0 / (k + 1));
    r.g.radius.push_back(0.05 + 0.01 * k);
    r.g.order.push_back(k == 4 || k == 5 ? 2 : 1);
  }
  r.g.edges = {{1, 0}, {2, 1}, {3, 2}, {4, 2}, {5, 4}, {7, 6}};
  return r;
}

}  // namespace

TEST_CASE("veins.ply holds every node's position, flow, radius, order and cell id, and the edges", "[export][veins]") {
  const test::TempDir tmp("veins-ply");
  const fs::path& dir = tmp.path;
  const Graph r = make_graph();
  exporters::write_veins_ply(dir / "veins.ply", r.g, r.cells);
  const test::Ply ply = parse_ply(slurp(dir / "veins.ply"));  // (parse_ply checks nothing is left over)
  CHECK(ply.format == "binary_little_endian 1.0");
  REQUIRE(ply.elements.size() == 2);
  const auto& v = ply.elements[0];
  const auto& e = ply.elements[1];
  CHECK(v.name == "vertex");
  CHECK(test::names(v) == std::vector<std::string>{"x", "y", "z", "flow", "radius", "order", "id"});
  CHECK(e.name == "edge");
  CHECK(test::names(e) == std::vector<std::string>{"vertex1", "vertex2"});
  REQUIRE(v.rows.size() == r.g.cell.size());
  for (std::size_t k = 0; k < v.rows.size(); ++k) {
    INFO("node " << k);
    for (int a = 0; a < 3; ++a) CHECK(v.rows[k][a] == r.g.position[k][a]);  // doubles, exactly
    CHECK(v.rows[k][3] == static_cast<float>(r.g.flow[k]));
    CHECK(v.rows[k][4] == static_cast<float>(r.g.radius[k]));
    CHECK(v.rows[k][5] == r.g.order[k]);
    CHECK(v.rows[k][6] == static_cast<double>(r.cells.id[r.g.cell[k]] & 0xffffffffu));
  }
  CHECK(v.rows[0][6] == 9);  // cell 10's id, low 32 bits
  REQUIRE(e.rows.size() == r.g.edges.size());
  for (std::size_t k = 0; k < e.rows.size(); ++k)
    CHECK(
        (e.rows[k] == std::vector<double>{static_cast<double>(r.g.edges[k][0]), static_cast<double>(r.g.edges[k][1])}));
}

TEST_CASE("veins.obj has every node with its attributes and one child-to-parent polyline per branch",
          "[export][veins]") {
  const test::TempDir tmp("veins-obj");
  const fs::path& dir = tmp.path;
  for (const Vec3& offset : {Vec3(0, 0, 0), Vec3(1e6, -2e6, 3e5)}) {  // far out: more digits, same positions
    INFO("offset " << offset.transpose());
    const Graph r = make_graph(offset);
    exporters::write_veins_obj(dir / "veins.obj", r.g);
    std::istringstream in(slurp(dir / "veins.obj"));
    std::vector<Vec3> v;
    std::vector<std::vector<double>> attrs;
    std::vector<std::vector<long>> lines;
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream words(line);
      std::string key;
      words >> key;
      if (key == "v") {
        Vec3 p;
        words >> p.x() >> p.y() >> p.z();
        v.push_back(p);
      } else if (key == "#a") {
        std::vector<double> a(3);
        words >> a[0] >> a[1] >> a[2];
        attrs.push_back(a);
        CHECK(attrs.size() == v.size());  // right after its vertex
      } else if (key == "l") {
        std::vector<long> l;
        for (long x; words >> x;) l.push_back(x);
        lines.push_back(l);
      } else {
        CHECK((key == "#" || key == "o"));
      }
      CHECK_FALSE((words.fail() && !words.eof()));
    }
    REQUIRE(v.size() == r.g.position.size());
    REQUIRE(attrs.size() == v.size());
    for (std::size_t k = 0; k < v.size(); ++k) {  // (9 significant digits of the attributes)
      CHECK((v[k] - r.g.position[k]).norm() <= 1e-8 * (1 + r.g.position[k].norm()));
      CHECK(attrs[k][0] == Approx(r.g.flow[k]).epsilon(1e-8));
      CHECK(attrs[k][1] == Approx(r.g.radius[k]).epsilon(1e-8));
      CHECK(attrs[k][2] == r.g.order[k]);
    }
    // the polylines' consecutive pairs are the edges, each once, child before parent; a branch per run:
    // 3-2, 5-4-2 (2 is a fork), 2-1-0, 7-6
    std::multiset<std::pair<long, long>> pairs;
    for (const auto& l : lines) {
      REQUIRE(l.size() >= 2);
      for (std::size_t k = 0; k + 1 < l.size(); ++k) pairs.insert({l[k] - 1, l[k + 1] - 1});  // 1-based
    }
    std::multiset<std::pair<long, long>> edges;
    for (const auto& e : r.g.edges) edges.insert({e[0], e[1]});
    CHECK(pairs == edges);
    CHECK(lines.size() == 4);
  }
}

TEST_CASE("vein files to an unwritable place give FileError naming the path and leave no file", "[export][veins]") {
  const test::TempDir tmp("veins-unwritable");
  const fs::path& dir = tmp.path;
  const Graph r = make_graph();
  const fs::path nowhere = dir / "missing" / "veins.ply";
  CHECK_THROWS_AS(exporters::write_veins_ply(nowhere, r.g, r.cells), core::FileError);
  CHECK_THROWS_WITH(exporters::write_veins_obj(dir / "missing" / "veins.obj", r.g), Catch::Contains("missing"));
  CHECK_FALSE(fs::exists(dir / "missing"));
}
