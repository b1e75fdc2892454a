// Tests of app/check.cpp: `cellform check` on broken and unreadable meshes, as text and as JSON.
#include <catch2/catch.hpp>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/app/test_util.h"

using namespace cellform::test;
using Catch::Matchers::Contains;

TEST_CASE("cellform check reports broken and unreadable meshes", "[cli][check]") {
  TempDir t("cli-check");
  // a tetrahedron with one face missing: a hole
  const auto open = t.write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n");
  auto r = cli({"check", open.string()});
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Contains("NOT printable"));
  CHECK_THAT(r.out, Contains("boundary edges 3"));
  const auto closed = t.write("closed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n");
  r = cli({"check", closed.string()});
  INFO(r.out);
  CHECK(r.code == 0);
  // two tetrahedra meeting at a corner (a non-manifold vertex) still have walls to measure
  const auto pinch = t.write("pinch.obj",
                             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv -1 0 0\nv 0 -1 0\nv 0 0 -1\n"
                             "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 6 5\nf 1 5 7\nf 1 7 6\nf 5 6 7\n");
  const auto pinched = cli({"check", pinch.string()});
  CHECK_THAT(pinched.out, Contains("non-manifold vertices 1") && Contains("wall thickness (in the file's units"));
  // the verdict heads the report, once, and the box reads as its three sizes
  CHECK(r.out.rfind(closed.string() + ": printable\n4 triangles, 4 vertices, 1 part;", 0) == 0);
  CHECK(r.out.find("printable", r.out.find("printable") + 1) == std::string::npos);
  CHECK_THAT(r.out, Contains("bounding box 1 x 1 x 1\n"));
  r = cli({"check", open.string()});  // with its reasons
  CHECK(r.out.rfind(open.string() + ": NOT printable: ", 0) == 0);
  // the report as JSON says what the text says: one surface, no pieces or genus on an open mesh
  r = cli({"check", open.string()});
  CHECK_THAT(r.out, Contains("1 connected surface;") && Contains("genus per part: open"));
  CHECK_THAT(r.out, Contains("wall thickness: not measured (the surfaces bound no solid"));
  r = cli({"check", open.string(), "--json"});
  auto j = nlohmann::json::parse(r.out);
  CHECK(j["surfaces"] == 1);
  CHECK(j["parts"].is_null());
  CHECK(j["genus"] == nlohmann::json::array({nullptr}));
  CHECK(j["wall_thickness_mm"]["samples"].get<int>() == 0);  // no ray leaves through another wall
  CHECK(j["wall_thickness_mm"]["median"].is_null());
  CHECK(j["wall_thickness_mm"]["not_measured"] == "the surfaces bound no solid");
  const auto garbage = t.write("garbage.stl", "this is not a mesh");
  r = cli({"check", garbage.string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("garbage.stl"));
  r = cli({"check", garbage.string(), "--json"});  // a program reading the report gets one
  CHECK(r.code == 2);
  j = nlohmann::json::parse(r.out);
  CHECK(j["printable"] == false);
  CHECK_THAT(j["error"].get<std::string>(), Contains("garbage.stl"));
  CHECK(cli({"check"}).code == 2);
  CHECK(cli({"check", (t.path / "none.stl").string()}).code == 2);
}

TEST_CASE("cellform check warns of STL facet normals that point against the winding", "[cli][check]") {
  TempDir t("cli-check-normals");
  // the closed tetrahedron, wound outward; facet normals stored as given
  const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  auto stl = [&](float sign, bool zero_first) {
    std::string b(80, ' ');
    const std::uint32_t n = 4;
    b.append(reinterpret_cast<const char*>(&n), 4);
    for (int k = 0; k < 4; ++k) {
      const float* a = v[f[k][0]];
      const float* c = v[f[k][1]];
      const float* d = v[f[k][2]];
      const float u[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
      float nrm[3] = {sign * (u[1] * w[2] - u[2] * w[1]), sign * (u[2] * w[0] - u[0] * w[2]),
                      sign * (u[0] * w[1] - u[1] * w[0])};
      if (zero_first && k == 0) nrm[0] = nrm[1] = nrm[2] = 0;  // a zero normal says nothing: not counted
      b.append(reinterpret_cast<const char*>(nrm), 12);
      for (int i = 0; i < 3; ++i) b.append(reinterpret_cast<const char*>(v[f[k][i]]), 12);
      b.append(2, '\0');
    }
    return b;
  };
  auto r = cli({"check", t.write("right.stl", stl(1, false)).string()});
  CHECK(r.code == 0);
  CHECK_THAT(r.out, !Contains("stored facet normals"));
  CHECK(nlohmann::json::parse(
            cli({"check", (t.path / "right.stl").string(), "--json"}).out)["stl_normals_against_winding"] == 0);
  r = cli({"check", t.write("flipped.stl", stl(-1, true)).string()});
  CHECK(r.code == 0);  // the verdict goes by the winding, which is right
  CHECK_THAT(r.out, Contains("warning: 3 of the 3 stored facet normals point against their triangle's winding"));
  r = cli({"check", (t.path / "flipped.stl").string(), "--json"});
  CHECK(nlohmann::json::parse(r.out)["stl_normals_against_winding"] == 3);
  CHECK(nlohmann::json::parse(r.out)["stl_padding_bytes"] == 0);
  // a padded file (a line end after the last facet) is read as slicers read it, and said to be so
  r = cli({"check", t.write("padded.stl", stl(1, false) + "\r\n").string()});
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("note: 2 bytes after the last facet of the binary STL were ignored"));
  CHECK(nlohmann::json::parse(cli({"check", (t.path / "padded.stl").string(), "--json"}).out)["stl_padding_bytes"] ==
        2);
  // a count left at 0 by an exporter (a walkthrough's was refused as damaged): the facets that fill it, said so
  std::string unset = stl(1, false);
  unset.replace(80, 4, std::string(4, '\0'));
  r = cli({"check", t.write("unset.stl", unset).string()});
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("4 triangles") &&
                        Contains("note: the binary STL's header says 0 triangles: the 4 facets that fill the file"));
  CHECK(nlohmann::json::parse(cli({"check", (t.path / "unset.stl").string(), "--json"}).out)["stl_count_zero"] == true);
  // ASCII: the same from the "facet normal" lines
  const auto ascii =
      t.write("flipped_ascii.stl",
              "solid t\n"
              "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
              "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
              "facet normal -1 -1 -1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
              "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
              "endsolid t\n");
  r = cli({"check", ascii.string()});
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("warning: 2 of the 3 stored facet normals point against"));
  std::string upper = slurp(ascii);  // keywords in capitals, as some CAD exports write them
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  r = cli({"check", t.write("upper.stl", upper).string()});
  CHECK_THAT(r.out, Contains("warning: 2 of the 3 stored facet normals point against"));
  // no stored normals to check in an OBJ: null, not 0
  const auto obj = t.write("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n");
  CHECK(nlohmann::json::parse(cli({"check", obj.string(), "--json"}).out)["stl_normals_against_winding"].is_null());
  // a PLY header cut before its end says so
  const auto cut = t.write("cut.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
  r = cli({"check", cut.string()});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("cut.ply") && Contains("no 'end_header' line"));
}

TEST_CASE("cellform check --min-wall judges the walls too", "[cli][check]") {
  TempDir t("cli-check-wall");
  // a 10 x 10 plate 0.05 thick: closed and oriented, so printable by its surfaces alone
  const auto plate = t.write("plate.obj",
                             "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nv 0 0 0.05\nv 10 0 0.05\nv 10 10 0.05\n"
                             "v 0 10 0.05\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
  auto r = cli({"check", plate.string()});
  CHECK(r.code == 0);
  r = cli({"check", plate.string(), "--min-wall", "0.8"});
  CHECK(r.code == 1);
  CHECK(r.out.rfind(plate.string() + ": NOT printable: walls thinner than --min-wall 0.8 over more than 1% of the "
                                     "surface (1% of it is thinner than 0.05; a cellform print's walls are up to "
                                     "about a voxel, print.voxel_size, thinner than twice print.min_radius (veins) "
                                     "or print.shell_thickness (a shell))\n",
                    0) == 0);
  r = cli({"check", plate.string(), "--min-wall=0.04", "--json"});
  CHECK(r.code == 0);
  auto j = nlohmann::json::parse(r.out);
  CHECK(j["printable"] == true);
  CHECK(j["min_wall"] == 0.04);
  r = cli({"check", plate.string(), "--json", "--min-wall", "0.8"});
  j = nlohmann::json::parse(r.out);
  CHECK(j["printable"] == false);
  CHECK_THAT(j["problems"].back().get<std::string>(), Contains("walls thinner than --min-wall 0.8"));
  // an open surface has no walls to measure: not known to be thick enough
  const auto open = t.write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n");
  r = cli({"check", open.string(), "--min-wall", "0.1"});
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Contains("also: walls not measured"));
  for (const char* bad : {"0", "-1", "x", "1e7", "nan", "inf", " 1", "0x1p-1", ""}) {
    r = cli({"check", plate.string(), "--min-wall", bad});
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("--min-wall must be a thickness > 0"));
  }
  CHECK(cli({"check", plate.string(), "--min-wall"}).code == 2);
  // given twice: refused, as run and resume refuse it, not the last taken unsaid
  r = cli({"check", plate.string(), "--min-wall", "0.1", "--min-wall=0.2"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--min-wall is given twice (0.1 and 0.2); give it once"));
  r = cli({"check", plate.string(), "--json", "--json"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("--json is given twice"));
  // an option cut short or misspelt is named with the one meant, as run's are (a walkthrough's --min-wal was not)
  r = cli({"check", plate.string(), "--min-wal", "3"});
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Contains("unknown option '--min-wal' for check; did you mean '--min-wall'?"));
  CHECK_THAT(cli({"check", plate.string(), "--jsno"}).err, Contains("did you mean '--json'?"));
  CHECK_THAT(cli({"check", plate.string(), "--json=1"}).err, Contains("--json takes no value, got '--json=1'"));
  CHECK_THAT(cli({"check", plate.string(), "--steps=3"}).err,
             Contains("unknown option '--steps=3' for check") && !Contains("did you mean"));
}

TEST_CASE("cellform check says whether a solid stands on the plane of its lowest point", "[cli][check]") {
  TempDir t("cli-check-stand");
  // a box 2 x 2 x 8 stands on its base and tips over at atan(1 / 4); a box 8 x 2 x 2 turned 30 degrees onto an
  // edge does not stand, and a cut off its bottom gives it a foot
  auto box = [&](const char* name, double turn) {
    std::string obj;
    const double w = turn == 0 ? 2 : 8, h = turn == 0 ? 8 : 2;
    for (int i = 0; i < 8; ++i) {
      const double x = i & 1 ? w : 0, y = i & 2 ? 2 : 0, z = i & 4 ? h : 0;
      obj += "v " + std::to_string(x * std::cos(turn) - z * std::sin(turn)) + " " + std::to_string(y) + " " +
             std::to_string(x * std::sin(turn) + z * std::cos(turn)) + "\n";
    }
    obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    return t.write(name, obj);
  };
  auto r = cli({"check", box("upright.obj", 0).string()});
  INFO(r.out);
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("stands on the bed (the plane of its lowest point): tips over when tilted 14 degrees;"));
  CHECK_THAT(r.out, !Contains("a cut of"));
  r = cli({"check", box("turned.obj", M_PI / 6).string(), "--json"});
  const auto stand = nlohmann::json::parse(r.out)["stand"];
  INFO(stand.dump());
  CHECK(r.code == 0);  // printable: standing is not asked of a solid
  CHECK(stand["tip_angle_deg"].get<double>() < 0);
  CHECK(stand["cut_to_stand_mm"].get<double>() > 0);
  CHECK(stand["centre_of_mass_mm"][1].get<double>() == Approx(1));
  r = cli({"check", box("turned.obj", M_PI / 6).string()});
  CHECK_THAT(r.out, Contains("does NOT stand by itself on the bed") && Contains("a cut of "));
}
