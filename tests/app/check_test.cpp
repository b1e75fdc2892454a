// Tests of app/check.cpp: `cellform check` on broken and unreadable meshes, as text and as JSON.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

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
