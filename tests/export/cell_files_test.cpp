// Tests of export/cell_files.h: files read back by an independent parser and by OpenMesh.
#include "export/cell_files.h"

#include <unistd.h>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "tests/export/ply_reader.h"

using namespace cellform;
using cells::Cells;
using cells::CellType;
using cells::Surface;
using core::Vec3;
using test::names;
using test::parse_ply;
using test::Ply;
using test::PlyElement;
using test::slurp;

namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("cellform-export-test-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A 3 x 2 patch of cells (two quads split into four triangles) and one dangling link to a seventh cell.
//   3 - 4 - 5
//   | \ | \ |   6 is linked to 5 only
//   0 - 1 - 2
struct Sheet {
  Cells cells;
  Surface surface;
};

Sheet make_sheet() {
  Sheet s;
  Cells& c = s.cells;
  const double third = 1.0 / 3.0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) cells::add_cell(c, Vec3(i + third, j * 0.7 - 1e-7, 0.125 * i * j));
  cells::add_cell(c, Vec3(3.123456789, 1.5, -2.0), CellType::vein, true);
  c.type[0] = CellType::petiole;
  c.fixed[0] = 1;
  for (std::size_t i = 0; i < c.size(); ++i) {
    c.age[i] = static_cast<std::uint32_t>(10 * i + 1);
    c.generation[i] = static_cast<std::uint32_t>(i / 2);
    c.id[i] = 1000 + i;
  }
  c.id[6] = (std::uint64_t{1} << 32) + 77;  // PLY stores the low 32 bits: 77
  auto& flow = cells::attribute(c, "flow");
  auto& level = cells::attribute(c, "auxin level");
  auto& x = cells::attribute(c, "x");
  for (std::size_t i = 0; i < c.size(); ++i) {
    flow[i] = 0.1 * static_cast<double>(i);
    level[i] = -static_cast<double>(i) * 1e-3;
    x[i] = 42.0 + static_cast<double>(i);
  }
  s.surface.triangles = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
  s.surface.edges = {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 4}, {1, 5}, {2, 5}, {3, 4}, {4, 5}, {5, 6}};
  return s;
}

}  // namespace

TEST_CASE("frame names are zero-padded and accept extensions with or without a dot", "[export]") {
  CHECK(exporters::frame_name("cells", 120, "ply") == "cells_000120.ply");
  CHECK(exporters::frame_name("cells", 0, ".obj") == "cells_000000.obj");
  CHECK(exporters::frame_name("sheet", 1234567, "ply") == "sheet_1234567.ply");
}

TEST_CASE("binary PLY holds every cell field, the triangles and the links", "[export][ply]") {
  const fs::path dir = temp_dir("ply");
  const Sheet s = make_sheet();
  const Cells& c = s.cells;
  const fs::path path = dir / exporters::frame_name("cells", 7, "ply");
  exporters::write_cells_ply(path, c, s.surface);
  const Ply ply = parse_ply(slurp(path));

  CHECK(ply.format == "binary_little_endian 1.0");
  REQUIRE(ply.elements.size() == 3);
  const PlyElement& v = ply.elements[0];
  const PlyElement& f = ply.elements[1];
  const PlyElement& e = ply.elements[2];
  CHECK(v.name == "vertex");
  CHECK(f.name == "face");
  CHECK(e.name == "edge");
  CHECK(v.count == 7);
  CHECK(f.count == 4);
  CHECK(e.count == 10);
  // Attributes in name order ("auxin level", "flow", "x"), sanitised and made distinct from x.
  CHECK(names(v) == std::vector<std::string>{"x", "y", "z", "type", "age", "generation", "id", "fixed", "auxin_level",
                                             "flow", "x_2"});
  std::vector<std::string> types;
  for (const auto& p : v.properties) types.push_back(p.type);
  CHECK(types == std::vector<std::string>{"double", "double", "double", "uchar", "uint", "uint", "uint", "uchar",
                                          "float", "float", "float"});
  REQUIRE(f.properties.size() == 1);
  CHECK(f.properties[0].name == "vertex_indices");
  CHECK(f.properties[0].count_type == "uchar");
  CHECK(f.properties[0].type == "int");
  CHECK(names(e) == std::vector<std::string>{"vertex1", "vertex2"});

  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto& row = v.rows[i];
    REQUIRE(row.size() == 11);
    for (int k = 0; k < 3; ++k) CHECK(row[k] == c.position[i][k]);
    CHECK(row[3] == static_cast<double>(c.type[i]));
    CHECK(row[4] == c.age[i]);
    CHECK(row[5] == c.generation[i]);
    CHECK(row[6] == static_cast<double>(c.id[i] & 0xffffffffu));
    CHECK(row[7] == c.fixed[i]);
    CHECK(row[8] == static_cast<double>(static_cast<float>(c.attributes.at("auxin level")[i])));
    CHECK(row[9] == static_cast<double>(static_cast<float>(c.attributes.at("flow")[i])));
    CHECK(row[10] == static_cast<double>(static_cast<float>(c.attributes.at("x")[i])));
  }
  CHECK(v.rows[6][6] == 77);
  CHECK(v.rows[6][3] == 2);
  CHECK(v.rows[0][3] == 1);
  for (std::size_t t = 0; t < 4; ++t)
    for (int k = 0; k < 3; ++k) CHECK(f.rows[t][k] == s.surface.triangles[t][k]);
  for (std::size_t k = 0; k < 10; ++k) {
    CHECK(e.rows[k][0] == s.surface.edges[k][0]);
    CHECK(e.rows[k][1] == s.surface.edges[k][1]);
  }
  fs::remove_all(dir);
}

TEST_CASE("vein_order is written as a whole number", "[export][ply]") {
  const fs::path dir = temp_dir("ply-order");
  Sheet s = make_sheet();
  Cells& c = s.cells;
  std::vector<double>& order = c.attributes["vein_order"];
  order.assign(c.size(), 0.0);
  order[1] = 1;
  order[2] = 3;
  const fs::path path = dir / "cells.ply";
  exporters::write_cells_ply(path, c, s.surface);
  const Ply ply = parse_ply(slurp(path));
  const PlyElement& v = ply.elements[0];
  std::size_t column = v.properties.size();
  for (std::size_t k = 0; k < v.properties.size(); ++k)
    if (v.properties[k].name == "vein_order") column = k;
  REQUIRE(column < v.properties.size());
  CHECK(v.properties[column].type == "int");
  for (std::size_t i = 0; i < c.size(); ++i) CHECK(v.rows[i][column] == order[i]);
  fs::remove_all(dir);
}

TEST_CASE("a sheet far from the origin keeps its positions exactly (64-bit doubles)", "[export][ply]") {
  // an export audit: at 3,000,000 units out floats are 0.25 units apart, and the cells snapped to that grid
  const fs::path dir = temp_dir("ply-far");
  Sheet s = make_sheet();
  for (Vec3& p : s.cells.position) p += Vec3(3e6, -2e6, 0.5);
  exporters::write_cells_ply(dir / "far.ply", s.cells, s.surface);
  const Ply ply = parse_ply(slurp(dir / "far.ply"));
  const PlyElement& v = ply.elements[0];
  for (std::size_t i = 0; i < s.cells.size(); ++i)
    for (int k = 0; k < 3; ++k) CHECK(v.rows[i][k] == s.cells.position[i][k]);
  OpenMesh::PolyMesh_ArrayKernelT<> mesh;  // (its points are floats: it reads the doubles and rounds them)
  OpenMesh::IO::Options options;
  REQUIRE(OpenMesh::IO::read_mesh(mesh, (dir / "far.ply").string(), options));
  CHECK(mesh.n_vertices() == s.cells.size());
  CHECK(mesh.point(OpenMesh::VertexHandle(0))[0] == static_cast<float>(s.cells.position[0][0]));
  fs::remove_all(dir);
}

TEST_CASE("OpenMesh reads the PLY with the same counts and positions", "[export][ply]") {
  const fs::path dir = temp_dir("openmesh");
  const Sheet s = make_sheet();
  const fs::path path = dir / "sheet.ply";
  exporters::write_cells_ply(path, s.cells, s.surface);
  OpenMesh::PolyMesh_ArrayKernelT<> mesh;
  OpenMesh::IO::Options options;
  REQUIRE(OpenMesh::IO::read_mesh(mesh, path.string(), options));
  CHECK(mesh.n_vertices() == s.cells.size());
  CHECK(mesh.n_faces() == s.surface.triangles.size());
  for (const auto vh : mesh.vertices()) {
    const auto p = mesh.point(vh);
    const Vec3& q = s.cells.position[static_cast<std::size_t>(vh.idx())];
    for (int k = 0; k < 3; ++k) CHECK(p[k] == static_cast<float>(q[k]));
  }
  fs::remove_all(dir);
}

TEST_CASE("OBJ has a header, full-precision vertices, faces and the links outside triangles", "[export][obj]") {
  const fs::path dir = temp_dir("obj");
  const Sheet s = make_sheet();
  const fs::path path = dir / "sheet.obj";
  exporters::write_cells_obj(path, s.cells, s.surface);
  std::istringstream in(slurp(path));
  std::string line;
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;
  std::vector<std::array<int, 2>> l;
  std::vector<std::string> comments;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "#") {
      comments.push_back(line);
    } else if (key == "v") {
      Vec3 p;
      words >> p.x() >> p.y() >> p.z();
      REQUIRE(!words.fail());
      v.push_back(p);
    } else if (key == "f") {
      std::array<int, 3> t;
      words >> t[0] >> t[1] >> t[2];
      f.push_back(t);
    } else if (key == "l") {
      std::array<int, 2> e;
      words >> e[0] >> e[1];
      l.push_back(e);
    } else {
      FAIL("unexpected line: " << line);
    }
  }
  REQUIRE(v.size() == s.cells.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      // "%.9g" round-trips every float exactly.
      CHECK(static_cast<float>(v[i][k]) == static_cast<float>(s.cells.position[i][k]));
      CHECK(std::abs(v[i][k] - s.cells.position[i][k]) <= 1e-8 * std::abs(s.cells.position[i][k]));
    }
  REQUIRE(f.size() == 4);
  for (std::size_t t = 0; t < 4; ++t)
    for (int k = 0; k < 3; ++k) CHECK(f[t][k] == static_cast<int>(s.surface.triangles[t][k]) + 1);
  REQUIRE(l.size() == 1);  // every link but 5-6 is a triangle side
  CHECK(l[0] == std::array<int, 2>{6, 7});
  bool counted = false;
  for (const auto& c : comments) counted = counted || c.find("7 vertices, 4 faces, 1 lines") != std::string::npos;
  CHECK(counted);
  fs::remove_all(dir);
}

TEST_CASE("an unwritable destination gives FileError naming the path and leaves no file", "[export]") {
  const fs::path dir = temp_dir("unwritable");
  const Sheet s = make_sheet();

  const fs::path nowhere = dir / "no_such_directory" / "cells.ply";
  CHECK_THROWS_AS(exporters::write_cells_ply(nowhere, s.cells, s.surface), core::FileError);
  CHECK_THROWS_WITH(exporters::write_cells_obj(nowhere, s.cells, s.surface), Catch::Contains(nowhere.string()));
  CHECK_FALSE(fs::exists(dir / "no_such_directory"));

  // A parent that is a file, not a directory.
  std::ofstream(dir / "plain_file") << "x";
  const fs::path under_file = dir / "plain_file" / "cells.obj";
  CHECK_THROWS_WITH(exporters::write_cells_obj(under_file, s.cells, s.surface), Catch::Contains(under_file.string()));

  if (::geteuid() != 0) {  // root may write anywhere, so permissions only bite for other users
    const fs::path locked = dir / "locked";
    fs::create_directories(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    CHECK_THROWS_AS(exporters::write_cells_ply(locked / "cells.ply", s.cells, s.surface), core::FileError);
    fs::permissions(locked, fs::perms::owner_all);
    CHECK(fs::is_empty(locked));
  }

  // A bad surface is refused before anything is written; an existing file stays as it was.
  const fs::path kept = dir / "kept.ply";
  exporters::write_cells_ply(kept, s.cells, s.surface);
  const std::string before = slurp(kept);
  Surface bad = s.surface;
  bad.triangles.push_back({0, 1, 99});
  CHECK_THROWS_AS(exporters::write_cells_ply(kept, s.cells, bad), core::InvalidInput);
  CHECK(slurp(kept) == before);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) files += entry.is_regular_file() ? 1 : 0;
  CHECK(files == 2);  // plain_file and kept.ply: no temporary files left behind
  fs::remove_all(dir);
}
