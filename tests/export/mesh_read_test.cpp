// Tests of export/mesh_read.h: reading meshes back as the writers and other programs write them, and refusing
// damaged files with a message naming the file and the line (the meshes of mesh_fixtures.h).
#include "export/mesh_read.h"
#include "export/mesh_check.h"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "core/errors.h"
#include "core/polygon.h"
#include "export/mesh_files.h"
#include "tests/export/mesh_fixtures.h"

using namespace cellform;
using core::Vec3;
using exporters::PrintableMesh;
using namespace cellform::testing;
namespace fs = std::filesystem;

TEST_CASE("read_mesh reads what the writers wrote, and welds STL soups", "[mesh_check][files]") {
  const fs::path dir = temp_dir("roundtrip");
  const auto m = torus(24, 10);
  for (const char* name : {"t.stl", "t.obj", "t.ply"}) {
    exporters::write_mesh(dir / name, m);
    const auto back = exporters::read_mesh(dir / name);
    INFO(name);
    CHECK(back.triangles.size() == m.triangles.size());
    CHECK(back.vertices.size() == m.vertices.size());
    const auto r = exporters::check_mesh(back);
    CHECK(r.printable());
    CHECK(r.volume == Approx(exporters::signed_volume(m)).epsilon(1e-5));
  }
  // an ASCII STL soup: every facet carries its own corners
  {
    std::ofstream f(dir / "a.stl");
    const auto t = tetrahedron();
    f << "solid t\n";
    for (const auto& tri : t.triangles) {
      f << " facet normal 0 0 0\n  outer loop\n";
      for (auto i : tri)
        f << "   vertex " << t.vertices[i].x() << " " << t.vertices[i].y() << " " << t.vertices[i].z() << "\n";
      f << "  endloop\n endfacet\n";
    }
    f << "endsolid t\n";
  }
  const auto a = exporters::read_mesh(dir / "a.stl");
  CHECK(a.vertices.size() == 4);
  CHECK(exporters::check_mesh(a).printable());
  // the same in upper case after a UTF-8 byte-order mark, as some CAD programs save it
  {
    std::stringstream in;
    in << std::ifstream(dir / "a.stl").rdbuf();
    std::string upper = in.str();
    for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    std::ofstream(dir / "upper.stl", std::ios::binary) << "\xEF\xBB\xBF" << upper;
  }
  const auto up = exporters::read_mesh(dir / "upper.stl");
  CHECK(up.vertices.size() == 4);
  CHECK(up.triangles == a.triangles);
  // non-manifold input is read as is, not dropped
  {
    std::ofstream f(dir / "nm.obj");
    f << "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 -1 0\nv 0.5 0 1\nf 1 2 3\nf 2 1 4\nf 1/1/1 2/2/2 5/5/5\n";
  }
  const auto nm = exporters::read_mesh(dir / "nm.obj");
  CHECK(nm.triangles.size() == 3);
  CHECK(exporters::check_mesh(nm).nonmanifold_edges == 1);
  fs::remove_all(dir);
}

TEST_CASE("read_mesh cuts a concave n-gon where it lies: an L-shaped prism is printable", "[mesh_check][files]") {
  // an L (10 x 10, 3 wide) extruded 5 high, its top and bottom one six-cornered face each, as Blender and
  // Rhino export n-gons (audit, December 2026): fanned from the first corner, the faces covered the notch,
  // and the check said "self-intersecting" with an area of 351
  const fs::path dir = temp_dir("ngon");
  std::string obj;
  const double l[6][2] = {{0, 0}, {10, 0}, {10, 3}, {3, 3}, {3, 10}, {0, 10}};
  for (const double z : {0.0, 5.0})
    for (const auto& c : l)
      obj += "v " + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(z) + "\n";
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 12\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 8\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t k = 0; k < obj.size();) {  // the same vertices, as PLY rows
    const std::size_t e = obj.find('\n', k);
    ply += obj.substr(k + 2, e - k - 2) + "\n";
    k = e + 1;
  }
  // for each face, which corner it starts at: every start gives the same solid
  for (int first = 0; first < 6; ++first) {
    std::string faces_obj = "f", faces_ply = "6";
    std::string top_obj = "f", top_ply = "6";
    for (int k = 0; k < 6; ++k) {
      const int bottom = (first + 6 - k) % 6, top = (first + k) % 6;  // the bottom wound downward
      // (appended in two parts: " " + std::to_string(...) makes GCC 12 warn falsely of an overlapping copy)
      for (auto [text, index] : {std::pair{&faces_obj, bottom + 1}, std::pair{&faces_ply, bottom},
                                 std::pair{&top_obj, top + 7}, std::pair{&top_ply, top + 6}}) {
        *text += ' ';
        *text += std::to_string(index);
      }
    }
    std::string sides_obj, sides_ply;
    for (int k = 0; k < 6; ++k) {
      const int a = k, b = (k + 1) % 6;
      sides_obj += "f " + std::to_string(a + 1) + " " + std::to_string(b + 1) + " " + std::to_string(b + 7) + " " +
                   std::to_string(a + 7) + "\n";
      sides_ply += "4 " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(b + 6) + " " +
                   std::to_string(a + 6) + "\n";
    }
    std::ofstream(dir / "l.obj") << obj << faces_obj << "\n" << top_obj << "\n" << sides_obj;
    std::ofstream(dir / "l.ply") << ply << faces_ply << "\n" << top_ply << "\n" << sides_ply;
    for (const char* name : {"l.obj", "l.ply"}) {
      INFO(name << ", faces from corner " << first);
      const auto m = exporters::read_mesh(dir / name);
      CHECK(m.triangles.size() == 2 * 4 + 6 * 2);
      const auto r = exporters::check_mesh(m);
      CHECK(r.printable());
      CHECK(r.self_intersections == 0);
      CHECK(r.area == Approx(2 * 51 + 5 * 40));  // the L's area twice, its perimeter times the height
      CHECK(r.volume == Approx(51 * 5));
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("read_mesh refuses a concave face too large to cut, naming its line", "[mesh_check][files]") {
  const fs::path dir = temp_dir("comb");
  std::string comb;
  const std::size_t teeth = core::kMaxConcaveCorners;
  for (std::size_t i = 0; i <= teeth; ++i) comb += "v " + std::to_string(i) + (i % 2 ? " 1 0\n" : " 3 0\n");
  comb += "v " + std::to_string(teeth) + " 0 0\nv 0 0 0\nf";
  for (std::size_t i = 1; i <= teeth + 3; ++i) {
    comb += ' ';
    comb += std::to_string(i);
  }
  std::ofstream(dir / "comb.obj") << comb << "\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "comb.obj"),
                    Catch::Contains("comb.obj: line 1028: a face of 1027 corners that is not convex"));
  fs::remove_all(dir);
}

TEST_CASE("read_mesh names the file it cannot read", "[mesh_check][files]") {
  const fs::path dir = temp_dir("bad");
  CHECK_THROWS_AS(exporters::read_mesh(dir / "missing.stl"), core::FileError);
  // a folder, a device or a file without extension is said as such (all said "unknown mesh format ''")
  CHECK_THROWS_WITH(exporters::read_mesh(dir), Catch::Contains("is a directory"));
  CHECK_THROWS_WITH(exporters::read_mesh("/dev/null"), Catch::Contains("not a regular file"));
  { std::ofstream(dir / "noext") << "solid x\nendsolid x\n"; }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "noext"),
                    Catch::Contains("noext: no file extension (use .stl, .obj or .ply)"));
  for (const char* name : {"empty.stl", "empty.obj", "empty.ply"}) {  // not "not an STL file" or "no faces"
    { std::ofstream(dir / name); }
    CHECK_THROWS_WITH(exporters::read_mesh(dir / name), Catch::Contains(name) && Catch::Contains("the file is empty"));
  }
  { std::ofstream(dir / "text.stl") << "hello, not a mesh\n"; }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "text.stl"), Catch::Contains("text.stl"));
  { std::ofstream(dir / "x.step") << "ISO-10303-21;\n"; }
  CHECK_THROWS_AS(exporters::read_mesh(dir / "x.step"), core::FileError);
  { std::ofstream(dir / "bad.obj") << "v 0 0 0\nf 1 2 3\n"; }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "bad.obj"), Catch::Contains("bad.obj") && Catch::Contains("line 2"));
  { std::ofstream(dir / "far.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1e30\nf 1 2 3\nf 1 2 4\n"; }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "far.obj"), Catch::Contains("vertex 4") && Catch::Contains("1e15"));
  // OBJ: NaN and infinity are named as such (they read as "needs three numbers"), as is a word no number
  { std::ofstream(dir / "nan.obj") << "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"; }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "nan.obj"), Catch::Contains("line 2") && Catch::Contains("NaN"));
  { std::ofstream(dir / "inf.obj") << "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n"; }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "inf.obj"), Catch::Contains("line 3") && Catch::Contains("infinity"));
  { std::ofstream(dir / "word.obj") << "v 0 0 0\nv 1 0x 0\nv 0 1 0\nf 1 2 3\n"; }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "word.obj"),
                    Catch::Contains("line 2: 'v 1 0x 0' is not a vertex of three finite numbers"));
  { std::ofstream(dir / "half.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1.5 2 3\n"; }  // not read as f 1 2 3
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "half.obj"), Catch::Contains("line 4") && Catch::Contains("'1.5'"));
  // a vein graph (edges, no faces) is said to be one, and where its printable solid is
  {
    std::ofstream(dir / "veins.ply") << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float "
                                        "y\nproperty float z\nelement edge 1\nproperty int vertex1\nproperty int "
                                        "vertex2\nend_header\n0 0 0\n1 0 0\n0 1\n";
  }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "veins.ply"),
                    Catch::Contains("only edges: a polyline graph such as veins.ply, not a surface"));
  { std::ofstream(dir / "bad.ply") << "ply\nformat binary_middle_endian 1.0\nend_header\n"; }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "bad.ply"),
                    Catch::Contains("PLY format 'binary_middle_endian' is not supported"));
  // NaN in a binary STL is unreadable input (exit 2 in check), not an unprintable shape
  {
    std::string stl(80, ' ');
    const std::uint32_t n = 1;
    stl.append(reinterpret_cast<const char*>(&n), 4);
    const float tri[12] = {0, 0, 1, std::numeric_limits<float>::quiet_NaN(), 0, 0, 1, 0, 0, 0, 1, 0};
    stl.append(reinterpret_cast<const char*>(tri), sizeof tri);
    stl.append(2, '\0');
    std::ofstream(dir / "nan.stl", std::ios::binary) << stl;
  }
  // named by its facet (the vertex numbers of the merged corners are no place in an STL)
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "nan.stl"),
                    Catch::Contains("nan.stl") && Catch::Contains("facet 1 has a corner that is NaN"));
  // ASCII PLY: NaN is named as such (it read as "ends early"), as are a word that is no number and a
  // negative count
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  std::ofstream(dir / "nan.ply") << head << "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "nan.ply"), Catch::Contains("vertex 2") && Catch::Contains("NaN"));
  std::ofstream(dir / "word.ply") << head << "0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "word.ply"), Catch::Contains("'abc' is not a number"));
  std::ofstream(dir / "short.ply") << head << "0 0 0\n1 0 0\n0 1\n";
  CHECK_THROWS_WITH(
      exporters::read_mesh(dir / "short.ply"),
      Catch::Contains("a line holds fewer values than its element's properties (in vertex 3 of 3, line 12)"));
  std::ofstream(dir / "index.ply") << head << "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "index.ply"),
                    Catch::Contains("PLY face index 3 out of range (3 vertices) (in face 1 of 1, line 13)"));
  {  // binary: the element that is cut short is named too
    std::string bin = head;
    bin.replace(bin.find("ascii"), 5, "binary_little_endian");
    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bin.append(reinterpret_cast<const char*>(v), sizeof v);
    bin += '\x03';
    const std::int32_t f[2] = {0, 1};  // the third index is missing
    bin.append(reinterpret_cast<const char*>(f), sizeof f);
    std::ofstream(dir / "cut.ply", std::ios::binary) << bin;
  }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "cut.ply"),
                    Catch::Contains("ends early (in face 1 of 1)") && Catch::Contains("counts wrong?"));
  // counts that do not match the data: said so, not read as holes or as a short face
  std::ofstream(dir / "more.ply") << head << "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n";  // a face more than declared
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "more.ply"),
                    Catch::Contains("goes on after the elements the header declares (8 bytes more)"));
  std::ofstream(dir / "blank.ply") << head << "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n  \n";  // blank lines at the end: fine
  CHECK(exporters::read_mesh(dir / "blank.ply").triangles.size() == 1);
  std::string four = head;
  four.replace(four.find("vertex 3"), 8, "vertex 4");  // the face line is read as a vertex
  std::ofstream(dir / "four.ply") << four << "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK_THROWS_WITH(
      exporters::read_mesh(dir / "four.ply"),
      Catch::Contains("a line holds more values than its element's properties (in vertex 4 of 4, line 13)"));
  {  // binary: bytes after the declared elements
    std::string bin = head;
    bin.replace(bin.find("ascii"), 5, "binary_little_endian");
    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bin.append(reinterpret_cast<const char*>(v), sizeof v);
    bin += '\x03';
    const std::int32_t f[3] = {0, 1, 2};
    bin.append(reinterpret_cast<const char*>(f), sizeof f);
    std::ofstream(dir / "whole.ply", std::ios::binary) << bin;
    std::ofstream(dir / "junk.ply", std::ios::binary) << bin + std::string(40, 'x');
  }
  CHECK(exporters::read_mesh(dir / "whole.ply").triangles.size() == 1);
  {  // big-endian (older tools and SGI/Sun data): each value's bytes the other way round; double vertices here
    std::string bin =
        "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
        "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    auto append_swapped = [&](const void* p, std::size_t n) {
      const auto* b = static_cast<const char*>(p);
      for (std::size_t k = n; k-- > 0;) bin += b[k];
    };
    for (const double x : {0.0, 0.0, 0.0, 1.5, 0.0, 0.0, 0.0, -2.25, 0.0}) append_swapped(&x, sizeof x);
    bin += '\x03';
    for (const std::int32_t i : {0, 1, 2}) append_swapped(&i, sizeof i);
    std::ofstream(dir / "big.ply", std::ios::binary) << bin;
  }
  const auto big = exporters::read_mesh(dir / "big.ply");
  REQUIRE(big.vertices.size() == 3);
  CHECK(big.vertices[1] == Vec3(1.5, 0, 0));
  CHECK(big.vertices[2] == Vec3(0, -2.25, 0));
  REQUIRE(big.triangles.size() == 1);
  CHECK(big.triangles[0] == std::array<std::uint32_t, 3>{0, 1, 2});
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "junk.ply"), Catch::Contains("(40 bytes more)"));
  std::string negative = head;
  negative.replace(negative.find("vertex 3"), 8, "vertex -1");
  std::ofstream(dir / "negative.ply") << negative << "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "negative.ply"),
                    Catch::Contains("count '-1'") && Catch::Contains("whole number"));
  std::string huge = head;  // a whole number, but beyond any file: said to be too large, not "not a whole number"
  huge.replace(huge.find("vertex 3"), 8, "vertex 1099511627776");
  std::ofstream(dir / "huge.ply") << huge << "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "huge.ply"),
                    Catch::Contains("count 1099511627776, too large") && !Catch::Contains("whole number"));
  // an element of no properties holds no data, however many it counts (review: a binary file of 999999999999
  // of them read nothing that many times, about an hour)
  for (const char* format : {"ascii", "binary_little_endian"}) {
    std::string empty = head;
    empty.replace(empty.find("ascii"), 5, format);
    empty.replace(empty.find("element face"), 0, "element marker 999999999999\n");
    std::string data = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    if (format[0] == 'b') {
      data.clear();
      for (const float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f})
        data.append(reinterpret_cast<const char*>(&x), sizeof x);
      data += '\x03';
      for (const std::int32_t i : {0, 1, 2}) data.append(reinterpret_cast<const char*>(&i), sizeof i);
    }
    std::ofstream(dir / "marker.ply", std::ios::binary) << empty << data;
    INFO(format);
    CHECK(exporters::read_mesh(dir / "marker.ply").triangles.size() == 1);
  }
  std::string zeros = head;  // leading zeros are no size
  zeros.replace(zeros.find("vertex 3"), 8, "vertex 00000000000003");
  std::ofstream(dir / "zeros.ply") << zeros << "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK(exporters::read_mesh(dir / "zeros.ply").triangles.size() == 1);
  // a version other than 1.0, and a header's bytes that are no text (escaped, as in the OBJ messages)
  std::string v2 = head;
  v2.replace(v2.find("ascii 1.0"), 9, "ascii 2.0");
  std::ofstream(dir / "v2.ply") << v2 << "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "v2.ply"), Catch::Contains("PLY version '2.0' is not supported (1.0)"));
  std::string garbled = head;
  garbled.replace(garbled.find("property float y"), 16, "property fl\xe1t y");
  std::ofstream(dir / "garbled.ply") << garbled << "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "garbled.ply"), Catch::Contains("unknown PLY property type 'fl\\xe1t'"));
  {  // a binary STL announcing 2 triangles with room for 4, and one with none
    std::string stl(80, ' ');
    std::uint32_t n = 2;
    stl.append(reinterpret_cast<const char*>(&n), 4);
    std::ofstream(dir / "padded.stl", std::ios::binary) << stl + std::string(200, '\0');
    std::ofstream(dir / "none.stl", std::ios::binary) << std::string(80, ' ') + std::string(4, '\0');
  }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "padded.stl"),
                    Catch::Contains("damaged binary STL") && Catch::Contains("announces 2 triangles (184 bytes)"));
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "none.stl"), Catch::Contains("no facets"));
  {  // a few bytes after the last facet are padding, read as slicers read it (an export audit: refused); 49 at most
    std::string stl(80, ' ');
    std::uint32_t n = 1;
    stl.append(reinterpret_cast<const char*>(&n), 4);
    stl += std::string(12, '\0');
    for (const float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f})
      stl.append(reinterpret_cast<const char*>(&x), 4);
    stl += std::string(2, '\0');
    std::ofstream(dir / "tail.stl", std::ios::binary) << stl + "\r\n";
    std::ofstream(dir / "long.stl", std::ios::binary) << stl + std::string(50, '\n');
  }
  exporters::MeshFileNotes tail_notes;
  CHECK(exporters::read_mesh(dir / "tail.stl", tail_notes).triangles.size() == 1);
  CHECK(tail_notes.stl_padding == 2);
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "long.stl"), Catch::Contains("announces 1 triangle (134 bytes)"));
  {  // ASCII STL cut short after a whole facet, and one with a word for a number
    const std::string facet =
        "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";
    std::ofstream(dir / "cut.stl") << "solid t\n" + facet;
    std::string word = "solid t\n" + facet + "endsolid t\n";
    std::ofstream(dir / "word.stl") << word.replace(word.find("vertex 1 0 0"), 12, "vertex 5 five 5");
  }
  CHECK_THROWS_AS(exporters::read_mesh(dir / "cut.stl"), core::FileError);
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "cut.stl"),
                    Catch::Contains("cut.stl") && Catch::Contains("line 8") && Catch::Contains("endsolid"));
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "word.stl"),
                    Catch::Contains("word.stl") && Catch::Contains("line 5") && Catch::Contains("three numbers"));
  {
    std::ofstream(dir / "flat.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                       "0 0\n1 0\n0 1\n3 0 1 2\n";
  }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "flat.ply"), Catch::Contains("no 'z' property"));
  {  // x as a list was read as its length and lost: every vertex at x = 0
    std::ofstream(dir / "xlist.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty list uchar float x\n"
                                        "property float y\nproperty float z\nelement face 1\n"
                                        "property list uchar int vertex_indices\nend_header\n"
                                        "1 0 0 0\n1 1 0 0\n1 0 1 0\n3 0 1 2\n";
  }
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "xlist.ply"),
                    Catch::Contains("xlist.ply") && Catch::Contains("'x' is a list, not one number"));
  fs::remove_all(dir);
}

TEST_CASE("read_mesh reads files as CAD programs write them: a mark, a comment, a vertex on an edge",
          "[mesh_check][files]") {
  const fs::path dir = temp_dir("cad");
  // a 10 mm cube with a vertex (9) on the edge between its top and front faces, both pentagons; written with
  // each corner of the two first (a fan from a corner next to vertex 9 was a flat triangle: "not printable")
  const std::string vertices =
      "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nv 0 0 10\nv 10 0 10\nv 10 10 10\nv 0 10 10\n"
      "v 5 0 10\nf 1 4 3 2\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  const std::vector<int> top{5, 9, 6, 7, 8}, front{1, 2, 6, 9, 5};
  for (std::size_t turn = 0; turn < 5; ++turn) {
    std::string faces = "f", faces2 = "f";
    for (std::size_t k = 0; k < 5; ++k) {
      faces.append(" ").append(std::to_string(top[(k + turn) % 5]));
      faces2.append(" ").append(std::to_string(front[(k + turn) % 5]));
    }
    std::ofstream(dir / "cube.obj") << vertices << faces << "\n" << faces2 << "\n";
    const auto r = exporters::check_mesh(exporters::read_mesh(dir / "cube.obj"));
    INFO("first corners " << top[turn] << ", " << front[turn]);
    CHECK(r.printable());
    CHECK(r.degenerate_triangles == 0);
    CHECK(r.volume == Approx(1000));
  }
  // after a UTF-8 byte-order mark: the first vertex was lost and every face shifted (volume 666.7, "printable")
  std::ofstream(dir / "bom.obj") << "\xEF\xBB\xBF" << vertices << "f 5 9 6 7 8\nf 1 2 6 9 5\n";
  CHECK(exporters::check_mesh(exporters::read_mesh(dir / "bom.obj")).volume == Approx(1000));
  // a PLY header comment that names end_header
  std::ofstream(dir / "c.ply") << "ply\nformat ascii 1.0\ncomment see end_header below\nelement vertex 4\n"
                                  "property float x\nproperty float y\nproperty float z\nelement face 4\n"
                                  "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                  "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  CHECK(exporters::check_mesh(exporters::read_mesh(dir / "c.ply")).printable());
  for (const char* spaced : {"end_header \n", "\tend_header\t\r\n"}) {  // spaces round the word, as before
    std::stringstream in;
    in << std::ifstream(dir / "c.ply").rdbuf();
    std::string text = in.str();
    text.replace(text.find("end_header\n"), 11, spaced);
    std::ofstream(dir / "s.ply") << text;
    CHECK(exporters::check_mesh(exporters::read_mesh(dir / "s.ply")).printable());
  }
  // face indices stored as floats are whole numbers, or refused (1.5 was read as 1)
  std::ofstream(dir / "f.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                  "property float z\nelement face 1\nproperty list uchar float vertex_indices\n"
                                  "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "f.ply"), Catch::Contains("PLY face index 1.5 is not a whole number"));
  // a vein graph as OBJ lines is said to be one, as the PLY is
  std::ofstream(dir / "veins.obj") << "v 0 0 0\nv 1 0 0\nl 1 2\n";
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "veins.obj"), Catch::Contains("only lines ('l'): a polyline graph"));
  // a cut-off binary STL whose header begins with "solid" (as some exporters write it) is a damaged binary
  // STL, not a broken ASCII one
  std::string stl(80, ' ');
  stl.replace(0, 10, "solid part");
  const std::uint32_t two = 2;
  stl.append(reinterpret_cast<const char*>(&two), 4).append(50, '\0');
  std::ofstream(dir / "cut.stl", std::ios::binary) << stl;
  // an ASCII STL padded with NULs after its end is a malformed ASCII STL, not a binary one
  std::ofstream(dir / "pad.stl", std::ios::binary)
      << "solid t\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\n"
         "endfacet\nendsolid t\n"
      << std::string(100, '\0');
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "pad.stl"),
                    Catch::Contains("malformed ASCII STL") && !Catch::Contains("binary"));
  CHECK_THROWS_WITH(exporters::read_mesh(dir / "cut.stl"),
                    Catch::Contains("damaged binary STL: its header") &&
                        Catch::Contains("announces 2 triangles (184 bytes), but the file has 134 bytes"));
  fs::remove_all(dir);
}
