// Tests of forms/mesh_io.{h,cpp}: the strict ASCII STL parser reads what real files hold and nothing else,
// and load_mesh (declared in forms/obstacles.h) reads STL and OBJ files or says what is wrong.
#include "forms/mesh_io.h"

#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "core/errors.h"
#include "core/polygon.h"
#include "forms/obstacles.h"

using namespace cellform;
using Catch::Matchers::Contains;
using core::Vec3;
namespace fs = std::filesystem;

namespace {

std::string facet(const std::string& a, const std::string& b, const std::string& c) {
  return "facet normal 0 0 1\nouter loop\nvertex " + a + "\nvertex " + b + "\nvertex " + c + "\nendloop\nendfacet\n";
}

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("cellform-forms-test-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

template <class T>
void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

std::string binary_stl(const std::vector<std::array<Vec3, 3>>& tris) {
  std::string s(80, ' ');
  put(s, static_cast<std::uint32_t>(tris.size()));
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) put(s, 0.0f);
    for (const Vec3& v : t)
      for (int k = 0; k < 3; ++k) put(s, static_cast<float>(v[k]));
    put(s, std::uint16_t{0});
  }
  return s;
}

}  // namespace

TEST_CASE("parse_ascii_stl reads facets in file order, in the spellings real files use", "[forms][mesh_io]") {
  // CRLF line ends, upper-case keywords, indentation, blank lines, signs and exponents, a nameless solid,
  // two solids one after the other, and a NaN normal (some writers emit one for degenerate facets)
  const std::string text =
      "solid part one\r\n  FACET NORMAL -nan 0 1\r\n    OUTER LOOP\r\n      VERTEX +1.5e+00 -2 0\r\n"
      "      VERTEX 0 0 0\r\n\r\n      VERTEX 1e-3 .5 7\r\n    ENDLOOP\r\n  ENDFACET\r\nENDSOLID part one\r\n"
      "solid\n" +
      facet("0 0 1", "1 0 1", "0 1 1") + "endsolid\n\n";
  const std::vector<Vec3> corners = forms::parse_ascii_stl(text);
  REQUIRE(corners.size() == 6);
  CHECK(corners[0] == Vec3(1.5, -2, 0));
  CHECK(corners[2] == Vec3(1e-3, 0.5, 7));
  CHECK(corners[5] == Vec3(0, 1, 1));
  CHECK(forms::parse_ascii_stl("solid empty\nendsolid empty").empty());
  // the stored normals, one per facet in order, when asked for (cellform check compares them with the winding)
  std::vector<Vec3> normals;
  CHECK(forms::parse_ascii_stl(text, &normals).size() == 6);
  REQUIRE(normals.size() == 2);
  CHECK(std::isnan(normals[0].x()));
  CHECK(normals[0].tail<2>() == Eigen::Vector2d(0, 1));
  CHECK(normals[1] == Vec3(0, 0, 1));
}

TEST_CASE("parse_ascii_stl refuses anything else, saying the line", "[forms][mesh_io]") {
  using Catch::Contains;
  const std::string f = facet("0 0 0", "1 0 0", "0 1 0");
  auto error = [](const std::string& text) {
    try {
      forms::parse_ascii_stl(text);
    } catch (const core::InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK_THAT(error(""), Contains("starts with 'solid'"));
  CHECK_THAT(error("solid\n" + f + "endsolid\nfacet normal 0 0 1\n"),
             Contains("line 10") && Contains("after 'endsolid'"));
  CHECK_THAT(error("solid\nfacet normal 0 0\n"), Contains("line 2") && Contains("'facet normal' and three numbers"));
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nvertex 0 0 0\n"), Contains("line 3") && Contains("'outer loop'"));
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0 0\n"),
             Contains("line 4") && Contains("three numbers"));
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 inf\n"), Contains("line 4") && Contains("NaN"));
  // a number past a double's range is one, and said so (it read as "needs three numbers" alone); one too
  // small is 0, as in OBJ; a wrong count is said first
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nouter loop\nvertex 1e400 0 0\n"),
             Contains("line 4") && Contains("beyond the range of 64-bit numbers"));
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 " + std::string(400, '9') + "\n"),
             Contains("line 4") && Contains("beyond the range"));
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nouter loop\nvertex +1e400 0 0\n"), Contains("beyond the range"));
  CHECK_THAT(error("solid\nfacet normal 0 1e999 1\n"), Contains("line 2") && Contains("beyond the range"));
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nouter loop\nvertex 1e400 0\n"),
             Contains("three numbers") && !Contains("beyond"));
  CHECK(error("solid\n" + facet("1e-400 0 0", "1 0 0", "0 1 0") + "endsolid\n") == "accepted");
  CHECK_THAT(error("solid\n" + f.substr(0, f.find("endfacet")) + "endsolid\n"),
             Contains("line 8") && Contains("'endfacet'"));
  CHECK_THAT(error("solid\n" + f + "vertex 0 0 0\nendsolid\n"), Contains("line 9") && Contains("'facet normal"));
  CHECK_THAT(error("solid\n" + f), Contains("line 8") && Contains("without 'endsolid'"));
  // a line quoted escaped: a NUL byte ended the message at "(the line reads '"
  CHECK_THAT(error("solid\n" + f + "endsolid\n" + std::string(2, '\0') + "x\n"),
             Contains("line 10") && Contains("(the line reads '\\x00\\x00x')"));
  CHECK_THAT(error("solid\n" + f.substr(0, f.find("endloop"))), Contains("line 6") && Contains("inside the facet"));
}

TEST_CASE("starts_like_ascii_stl knows the first word of an ASCII STL in any case, after a BOM", "[forms][mesh_io]") {
  CHECK(forms::starts_like_ascii_stl("solid x\n"));
  CHECK(forms::starts_like_ascii_stl("SOLID"));
  CHECK(forms::starts_like_ascii_stl("\xEF\xBB\xBF  Solid part\r\n"));
  CHECK(forms::starts_like_ascii_stl("\n\nsolid\tx"));
  CHECK_FALSE(forms::starts_like_ascii_stl("solidworks binary header"));
  CHECK_FALSE(forms::starts_like_ascii_stl("soli"));
  CHECK_FALSE(forms::starts_like_ascii_stl("\xEF\xBB solid"));
  CHECK_FALSE(forms::starts_like_ascii_stl(""));
  CHECK_FALSE(forms::starts_like_ascii_stl(std::string_view("solid part\0\0", 12)));  // a binary header
  CHECK(forms::parse_ascii_stl("\xEF\xBB\xBFsolid\n" + facet("0 0 0", "1 0 0", "0 1 0") + "endsolid\n").size() == 3);
}

TEST_CASE("load_mesh reads ASCII STL, binary STL and OBJ", "[forms][mesh_io]") {
  const fs::path dir = temp_dir("load");
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);
  const std::vector<std::array<Vec3, 3>> tet = {{a, c, b}, {a, b, d}, {a, d, c}, {b, c, d}};

  std::string ascii = "solid tet\n";
  for (const auto& t : tet) {
    ascii += "facet normal 0 0 0\n outer loop\n";
    for (const Vec3& v : t)
      ascii += "  vertex " + std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\n";
    ascii += " endloop\nendfacet\n";
  }
  ascii += "endsolid tet\n";
  write_text(dir / "tet_ascii.stl", ascii);
  write_text(dir / "tet_binary.STL", binary_stl(tet));
  // the same text in upper case and after a UTF-8 byte-order mark (as some CAD programs and editors save it)
  std::string upper = ascii;
  for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  write_text(dir / "tet_upper.stl", "\xEF\xBB\xBF" + upper);
  // OBJ with a quad (split into two triangles), a comment, and negative (relative) indices.
  write_text(dir / "quad.obj",
             "# a unit square and a triangle\nv 0 0 0\nv 2 0 0\nv 2 3 0\nv 0 3 0\nv 1 1 5\nf 1 2 3 4\nf -5 -4 -1\n");

  for (const char* name : {"tet_ascii.stl", "tet_binary.STL", "tet_upper.stl"}) {
    INFO(name);
    const forms::TriangleMesh m = forms::load_mesh(dir / name);
    REQUIRE(m.triangles.size() == 4);
    // Same triangles, corner by corner, whatever the vertex numbering.
    for (std::size_t t = 0; t < 4; ++t)
      for (int k = 0; k < 3; ++k) CHECK((m.vertices[m.triangles[t][k]] - tet[t][k]).norm() < 1e-6);
    // A closed tetrahedron: stops a cell moving from inside to outside.
    forms::Obstacles o;
    o.meshes.push_back(m);
    cells::Cells cells;
    cells::add_cell(cells, Vec3(2, 2, 2));
    forms::apply_obstacles(cells, {Vec3(0.1, 0.1, 0.1)}, o, 0.01);
    CHECK(cells.position[0].sum() < 1.0);
  }

  const forms::TriangleMesh q = forms::load_mesh(dir / "quad.obj");
  REQUIRE(q.vertices.size() == 5);
  REQUIRE(q.triangles.size() == 3);
  CHECK(q.vertices[2] == Vec3(2, 3, 0));
  CHECK(q.vertices[4] == Vec3(1, 1, 5));
  double area = 0;
  for (std::size_t t = 0; t < 2; ++t) {
    const auto& tr = q.triangles[t];
    area += 0.5 * (q.vertices[tr[1]] - q.vertices[tr[0]]).cross(q.vertices[tr[2]] - q.vertices[tr[0]]).norm();
  }
  CHECK(area == Approx(6.0));
  CHECK(q.triangles[2] == std::array<core::Index, 3>{0, 1, 4});
  // after a UTF-8 byte-order mark: the same mesh (OpenMesh took the first line for an unknown keyword and
  // lost its vertex, shifting every face)
  write_text(dir / "quad_bom.obj", "\xEF\xBB\xBFv 0 0 0\nv 2 0 0\nv 2 3 0\nv 0 3 0\nv 1 1 5\nf 1 2 3 4\nf -5 -4 -1\n");
  const forms::TriangleMesh bom = forms::load_mesh(dir / "quad_bom.obj");
  CHECK(bom.vertices == q.vertices);
  CHECK(bom.triangles == q.triangles);
  fs::remove_all(dir);
}

TEST_CASE("load_mesh cuts a concave n-gon where it lies, and nowhere else", "[forms][mesh_io]") {
  // an L-shaped plate, one six-cornered face: fanned from its first corner, it covered the notch, so cells
  // came to rest on a wall that is not there (audit, December 2026)
  const fs::path dir = temp_dir("ngon");
  // (from its corner (10, 3): a fan from (0, 0) would have been right, the L being star-shaped from there)
  write_text(dir / "l.obj", "v 0 0 0\nv 10 0 0\nv 10 3 0\nv 3 3 0\nv 3 10 0\nv 0 10 0\nf 3 4 5 6 1 2\n");
  const forms::TriangleMesh m = forms::load_mesh(dir / "l.obj");
  REQUIRE(m.triangles.size() == 4);
  double area = 0;
  for (const auto& t : m.triangles)
    area += 0.5 * (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).z();
  CHECK(area == Approx(51));  // every triangle wound as the face (+z), together the L
  // a cell falling onto the notch passes; onto the L it stops
  forms::Obstacles o;
  o.meshes.push_back(m);
  cells::Cells cells;
  cells::add_cell(cells, Vec3(7, 7, -1));
  cells::add_cell(cells, Vec3(1, 7, -1));
  forms::apply_obstacles(cells, {Vec3(7, 7, 1), Vec3(1, 7, 1)}, o, 0.01);
  CHECK(cells.position[0].z() == Approx(-1));
  CHECK(cells.position[1].z() > 0);
  // a concave face of more corners than ear clipping takes is refused, naming the face
  std::string comb;
  const std::size_t teeth = core::kMaxConcaveCorners;
  for (std::size_t i = 0; i <= teeth; ++i) comb += "v " + std::to_string(i) + (i % 2 ? " 1 0\n" : " 3 0\n");
  comb += "v " + std::to_string(teeth) + " 0 0\nv 0 0 0\nf";
  for (std::size_t i = 1; i <= teeth + 3; ++i) comb.append(" ").append(std::to_string(i));  // (GCC 12 -Wrestrict)
  write_text(dir / "comb.obj", comb + "\n");
  CHECK_THROWS_WITH(forms::load_mesh(dir / "comb.obj"), Contains("face 1 has 1027 corners and is not convex"));
  fs::remove_all(dir);
}

TEST_CASE("load_mesh keeps non-manifold triangles", "[forms][mesh_io]") {
  const fs::path dir = temp_dir("nonmanifold");
  // Three triangles on one edge: a half-edge mesh would drop one of them.
  write_text(dir / "fin.obj", "v 0 0 0\nv 0 0 1\nv 1 0 0\nv -1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\nf 1 2 5\n");
  CHECK(forms::load_mesh(dir / "fin.obj").triangles.size() == 3);
  fs::remove_all(dir);
}

TEST_CASE("load_mesh errors name the file and the problem", "[forms][mesh_io]") {
  const fs::path dir = temp_dir("errors");
  const fs::path missing = dir / "missing.stl";
  CHECK_THROWS_AS(forms::load_mesh(missing), core::FileError);
  CHECK_THROWS_WITH(forms::load_mesh(missing), Catch::Contains("missing.stl") && Catch::Contains("does not exist"));

  // a pipe blocked the run for good, /dev/zero was "cannot be opened": neither is a file to read
  REQUIRE(::mkfifo((dir / "fifo.stl").c_str(), 0600) == 0);
  CHECK_THROWS_WITH(forms::load_mesh(dir / "fifo.stl"),
                    Catch::Contains("fifo.stl") && Catch::Contains("not a regular file"));
  fs::create_symlink("/dev/zero", dir / "zero.stl");
  CHECK_THROWS_WITH(forms::load_mesh(dir / "zero.stl"),
                    Catch::Contains("zero.stl") && Catch::Contains("not a regular file"));

  write_text(dir / "empty.obj", "");
  CHECK_THROWS_WITH(forms::load_mesh(dir / "empty.obj"), Catch::Contains("empty.obj") && Catch::Contains("not a mesh"));

  write_text(dir / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  CHECK_THROWS_AS(forms::load_mesh(dir / "points.obj"), core::InvalidInput);
  CHECK_THROWS_WITH(forms::load_mesh(dir / "points.obj"),
                    Catch::Contains("points.obj") && Catch::Contains("not a mesh"));
  // veins.obj given where a surface belongs: said to be the polyline graph it is (points alone are not)
  write_text(dir / "veins.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
  CHECK_THROWS_WITH(forms::load_mesh(dir / "veins.obj"),
                    Catch::Contains("veins.obj") && Catch::Contains("only lines ('l'): a polyline graph"));
  CHECK_THROWS_WITH(forms::load_mesh(dir / "points.obj"), !Catch::Contains("polyline"));

  write_text(dir / "garbage.stl", "this is not\nan STL file at all\n\x01\x02\x03");
  CHECK_THROWS_AS(forms::load_mesh(dir / "garbage.stl"), core::InvalidInput);
  CHECK_THROWS_WITH(forms::load_mesh(dir / "garbage.stl"), Catch::Contains("garbage.stl"));

  write_text(dir / "bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  CHECK_THROWS_WITH(forms::load_mesh(dir / "bad_index.obj"), Catch::Contains("bad_index.obj"));
  // a face line OpenMesh would drop without a word is refused with its line, as `cellform check` does
  for (const char* face : {"f a b c", "f 1", "f", "f 1 3", "f 1.5 2 3", "f 1 2 99999999999999999999", "f 1 2 0",
                           "f -9223372036854775808 1 2", "f 1/ /3 //2", "f 1/x 2 3"}) {
    INFO(face);
    write_text(dir / "face.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\n") + face + "\nf 1 2 3\n");
    CHECK_THROWS_AS(forms::load_mesh(dir / "face.obj"), core::InvalidInput);
    CHECK_THROWS_WITH(forms::load_mesh(dir / "face.obj"), Catch::Contains("face.obj") && Catch::Contains("line 4"));
  }
  // texture and normal indices, and indices counted back from the end, are fine
  write_text(dir / "slashes.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf -3/1/1 -1 -2\n");
  CHECK(forms::load_mesh(dir / "slashes.obj").triangles.size() == 2);
  write_text(dir / "comment.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 # the only face\n");
  CHECK(forms::load_mesh(dir / "comment.obj").triangles.size() == 1);
  // a number in a face line's comment is no corner (OpenMesh's reader made 'f 1 2 3 # 4' a quad)
  write_text(dir / "comment4.obj", "v 10 10 10\nv 11 10 10\nv 10 11 10\nv 50 50 50\nf 1 2 3 # 4\n");
  const forms::TriangleMesh commented = forms::load_mesh(dir / "comment4.obj");
  REQUIRE(commented.triangles.size() == 1);
  CHECK(commented.triangles[0] == std::array<core::Index, 3>{0, 1, 2});
  // a material library is not opened (one naming a pipe blocked the run for good, /dev/zero filled memory),
  // and texture coordinates of any length, as the OBJ format allows, are no matter
  REQUIRE(::mkfifo((dir / "fifo.mtl").c_str(), 0600) == 0);
  write_text(dir / "material.obj",
             "mtllib fifo.mtl\nmtllib /dev/zero\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
             "vt 0.5\nvt 0.5 0.5 0\nf 1/1 2/2 3/1\n");
  CHECK(forms::load_mesh(dir / "material.obj").triangles.size() == 1);
  CHECK(forms::obj_face_vertex("-1", 5) == 4);
  CHECK(forms::obj_face_vertex("000000000000000000000002", 5) == 1);  // leading zeros are no digits
  CHECK(forms::obj_face_vertex("2/7/9", 5) == 1);
  CHECK_THROWS_WITH(forms::obj_face_vertex("-6", 5), Catch::Contains("counts back past the first of the 5"));

  {  // a binary STL padded by a few bytes, as some exporters write it, is read as `cellform check` reads it
    const std::string one = binary_stl({{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}});
    write_text(dir / "padded.stl", one + std::string(2, '\0'));
    const forms::TriangleMesh padded = forms::load_mesh(dir / "padded.stl");
    REQUIRE(padded.triangles.size() == 1);
    CHECK(padded.vertices[padded.triangles[0][1]] == Vec3(1, 0, 0));
    write_text(dir / "long.stl", one + std::string(50, '\0'));  // a whole facet more than the count: damaged
    CHECK_THROWS_WITH(forms::load_mesh(dir / "long.stl"), Catch::Contains("announces 1 triangle (134 bytes)"));
    // a count left at 0 by an exporter that writes as it goes: the facets that fill the file (refused before)
    std::string two =
        binary_stl({{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 2)}});
    two.replace(80, 4, std::string(4, '\0'));
    write_text(dir / "unset.stl", two);
    const forms::TriangleMesh unset = forms::load_mesh(dir / "unset.stl");
    REQUIRE(unset.triangles.size() == 2);
    CHECK(unset.vertices[unset.triangles[1][2]] == Vec3(0, 0, 2));
    write_text(dir / "unset_padded.stl", two + "\r\n");  // not a whole number of facets: damaged
    CHECK_THROWS_WITH(forms::load_mesh(dir / "unset_padded.stl"), Catch::Contains("announces 0 triangles"));
  }
  const double nan = std::nan("");
  write_text(dir / "nan.stl", binary_stl({{Vec3(0, 0, 0), Vec3(1, nan, 0), Vec3(0, 1, 0)}}));
  CHECK_THROWS_AS(forms::load_mesh(dir / "nan.stl"), core::InvalidInput);
  CHECK_THROWS_WITH(forms::load_mesh(dir / "nan.stl"),
                    Catch::Contains("nan.stl") && Catch::Contains("triangle 1") && Catch::Contains("NaN"));
  // beside a good triangle: OpenMesh dropped the bad one and the mesh loaded without it
  write_text(dir / "nan2.stl", binary_stl({{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
                                           {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, std::nan(""))}}));
  CHECK_THROWS_WITH(forms::load_mesh(dir / "nan2.stl"), Catch::Contains("triangle 2") && Catch::Contains("NaN"));
  {  // past the first block of records the corner check reads
    std::vector<std::array<Vec3, 3>> many;
    for (int t = 0; t < 5000; ++t) many.push_back({Vec3(t, 0, 0), Vec3(t + 1, 0, 0), Vec3(t, 1, 0)});
    many[4099][2].z() = std::nan("");
    write_text(dir / "nan4100.stl", binary_stl(many));
    CHECK_THROWS_WITH(forms::load_mesh(dir / "nan4100.stl"), Catch::Contains("triangle 4100 "));
  }
  write_text(dir / "inf.stl", binary_stl({{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, HUGE_VAL, 0)}}));
  CHECK_THROWS_WITH(forms::load_mesh(dir / "inf.stl"), Catch::Contains("triangle 1") && Catch::Contains("infinite"));

  write_text(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  CHECK_THROWS_WITH(forms::load_mesh(dir / "nan.obj"),
                    Catch::Contains("nan.obj") && Catch::Contains("line 2: 'v nan 0 0'") && Catch::Contains("finite"));
  // finite beyond 32-bit floats is read as written (OpenMesh's reader dropped it; the script bounds positions)
  write_text(dir / "huge.obj", "v 0 0 0\nv 1 0 0\n# far\nv 0 1e300 0\nf 1 2 3\n");
  CHECK(forms::load_mesh(dir / "huge.obj").vertices[2].y() == 1e300);
  // a NUL byte inside a number ended it there ("v 0 1<NUL>zz 0" read as 0 1 0), as `cellform check` refuses it
  write_text(dir / "nul.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 1\0zz 0\nf 1 2 3\n", 35));
  CHECK_THROWS_WITH(forms::load_mesh(dir / "nul.obj"), Catch::Contains("line 3: 'v 0 1\\x00zz 0'"));
  write_text(dir / "short.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n");
  CHECK_THROWS_WITH(forms::load_mesh(dir / "short.obj"), Catch::Contains("line 2: 'v 1 0'"));
  write_text(dir / "colours.obj", "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n");  // x y z r g b
  CHECK(forms::load_mesh(dir / "colours.obj").triangles.size() == 1);
  write_text(dir / "spelt.obj", "v\t+0 0.0 0e0#a\r\nv 1E0 0 0 # b\r\nv 0 1 0 1.0\r\nf 1 2 3\r\n");  // tab, CRLF, w
  CHECK(forms::load_mesh(dir / "spelt.obj").triangles.size() == 1);
  // a line continued on the next by a backslash, as the format allows (a walkthrough's was refused at '\'), also
  // with CRLF; an error on a continued line names its last line
  write_text(dir / "continued.obj", "v 0 0 0\nv 1 0 \\\n 0\nv 1 1 0\r\nv 0 1 0\nf 1 2 \\\r\n3 4\n");
  const forms::TriangleMesh continued = forms::load_mesh(dir / "continued.obj");
  CHECK(continued.triangles.size() == 2);
  CHECK(continued.vertices.size() == 4);
  CHECK(continued.vertices[1] == Vec3(1, 0, 0));
  write_text(dir / "continued_bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \\\n x\n");
  CHECK_THROWS_WITH(forms::load_mesh(dir / "continued_bad.obj"), Catch::Contains("line 5: bad face vertex 'x'"));
  // a comment ending in a backslash (a Windows folder) goes on on no other line (a review: it took the next vertex)
  write_text(dir / "windows.obj", "# exported from C:\\models\\\nv 0 0 0\nv 1 0 0 # x\\\nv 0 1 0\nf 1 2 3\n");
  CHECK(forms::load_mesh(dir / "windows.obj").vertices.size() == 3);

  std::string truncated =
      binary_stl({{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}});
  truncated.resize(truncated.size() - 20);
  write_text(dir / "truncated.stl", truncated);
  CHECK_THROWS_WITH(forms::load_mesh(dir / "truncated.stl"), Catch::Contains("truncated.stl") &&
                                                                 Catch::Contains("damaged binary STL") &&
                                                                 !Catch::Contains("solid"));
  truncated.replace(0, 10, "solid part");  // a binary header that begins as ASCII does (it was read as ASCII)
  write_text(dir / "solid.stl", truncated);
  CHECK_THROWS_WITH(forms::load_mesh(dir / "solid.stl"), Catch::Contains("damaged binary STL: its header announces"));

  write_text(dir / "mesh.ply", "ply\n");
  CHECK_THROWS_WITH(forms::load_mesh(dir / "mesh.ply"), Catch::Contains("mesh.ply") && Catch::Contains(".obj"));

  CHECK_THROWS_WITH(forms::load_mesh(dir), Catch::Contains("is a directory"));  // not "unsupported format ''"
  write_text(dir / "mesh", "v 0 0 0\n");
  CHECK_THROWS_AS(forms::load_mesh(dir / "mesh"), core::InvalidInput);  // no extension: unsupported format
  fs::create_directories(dir / "folder.stl");
  CHECK_THROWS_AS(forms::load_mesh(dir / "folder.stl"), core::FileError);
  fs::remove_all(dir);
}

TEST_CASE("load_mesh refuses a malformed ASCII STL, naming the file and the line", "[forms][mesh_io]") {
  using Catch::Contains;
  const fs::path dir = temp_dir("ascii_stl");
  const std::string facet1 =
      "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";
  const std::string facet2 =
      "facet normal 0 0 1\n outer loop\n  vertex 0 0 1\n  vertex 1 0 1\n  vertex 0 1 1\n endloop\nendfacet\n";
  // line numbers: "solid t" is line 1, facet1 lines 2-8, facet2 lines 9-15, "endsolid t" line 16
  const std::string good = "solid t\n" + facet1 + facet2 + "endsolid t\n";
  write_text(dir / "good.stl", good);
  CHECK(forms::load_mesh(dir / "good.stl").triangles.size() == 2);

  auto refuses = [&](const std::string& name, const std::string& text, const std::string& line,
                     const std::string& what) {
    INFO(name << ":\n" << text);
    write_text(dir / name, text);
    CHECK_THROWS_AS(forms::load_mesh(dir / name), core::InvalidInput);
    CHECK_THROWS_WITH(forms::load_mesh(dir / name), Contains(name) && Contains(line) && Contains(what));
  };
  std::string word = good;
  word.replace(word.find("vertex 1 0 1"), 12, "vertex 5 five 5");
  refuses("word.stl", word, "line 12", "three numbers");
  std::string two = good;
  two.replace(two.find("vertex 1 0 1"), 12, "vertex 1 0");
  refuses("two_numbers.stl", two, "line 12", "three numbers");
  std::string junk = good;
  junk.replace(junk.find("vertex 1 0 1"), 12, "vertex 1 0 1x");
  refuses("junk.stl", junk, "line 12", "three numbers");
  std::string nan = good;
  nan.replace(nan.find("vertex 1 0 1"), 12, "vertex 1 nan 1");
  refuses("nan.stl", nan, "line 12", "NaN");
  // cut in the middle of the second facet, after a complete first one
  refuses("cut.stl", good.substr(0, good.find("vertex 0 1 1")), "line 12", "ends inside the facet of line 9");
  refuses("cut_vertex.stl", good.substr(0, good.find(" 1\n  vertex 0 1 1")), "line 12", "three numbers");
  refuses("unclosed.stl", "solid t\n" + facet1 + facet2, "line 15", "endsolid");
  std::string four = good;
  four.insert(four.find(" endloop", four.find("vertex 0 1 1")), "  vertex 1 1 1\n");
  refuses("four.stl", four, "line 14", "three vertices");
  std::string short_facet = good;
  short_facet.erase(short_facet.find("  vertex 0 1 1\n"), 15);
  refuses("short.stl", short_facet, "line 13", "three vertices");
  fs::remove_all(dir);
}

TEST_CASE("load_mesh keeps an OBJ's coordinates as written, at site coordinates too", "[forms][mesh_io]") {
  // OpenMesh reads 32-bit floats: a vertex at 1,000,000.001 mm came back at 1,000,000 (steps of 6.25 cm there)
  const fs::path dir = temp_dir("site");
  write_text(dir / "site.obj",
             "v 1000000.001 2000000.25 3.5\nv 1000010.001 2000000.25 3.5\nv 1000000.001 2000010.75 -0.000123\n"
             "v 0.1 0.2 0.3 1.0\nf 1 2 3\nf 1 3 4\n");
  const auto m = cellform::forms::load_mesh(dir / "site.obj");
  REQUIRE(m.vertices.size() == 4);
  CHECK(m.vertices[0] == Vec3(1000000.001, 2000000.25, 3.5));
  CHECK(m.vertices[1] == Vec3(1000010.001, 2000000.25, 3.5));
  CHECK(m.vertices[2] == Vec3(1000000.001, 2000010.75, -0.000123));
  CHECK(m.vertices[3] == Vec3(0.1, 0.2, 0.3));  // a weight after x y z is not a coordinate
  CHECK(m.triangles.size() == 2);
  fs::remove_all(dir);
}
