// Tests of export/mesh_check.h: meshes whose defects and genus are known by construction (reading them back:
// mesh_read_test.cpp).
#include "export/mesh_check.h"
#include "export/mesh_read.h"

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

TEST_CASE("a tetrahedron is printable, genus 0, volume 1/6", "[mesh_check]") {
  const auto r = exporters::check_mesh(tetrahedron());
  CHECK(r.printable());
  CHECK(r.parts == 1);
  REQUIRE(r.genus.size() == 1);
  CHECK(r.genus[0] == 0);
  CHECK(r.volume == Approx(1.0 / 6));
  CHECK(r.bbox_max == Vec3(1, 1, 1));
}

TEST_CASE("a torus has genus 1 and a sphere genus 0", "[mesh_check]") {
  const auto t = exporters::check_mesh(torus(40, 20));
  CHECK(t.printable());
  REQUIRE(t.genus.size() == 1);
  CHECK(t.genus[0] == 1);
  CHECK(t.volume == Approx(2 * M_PI * M_PI * 3).epsilon(0.03));
  const auto s = exporters::check_mesh(uv_sphere(30, 60));
  CHECK(s.printable());
  CHECK(s.genus == std::vector<int>{0});
}

TEST_CASE("check_mesh finds each kind of defect", "[mesh_check]") {
  SECTION("inside out: consistent but negative volume") {
    auto m = tetrahedron();
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
    const auto r = exporters::check_mesh(m);
    CHECK(r.consistently_oriented);
    CHECK(r.volume < 0);
    CHECK_FALSE(r.printable());
  }
  SECTION("one face flipped") {
    auto m = tetrahedron();
    std::swap(m.triangles[3][1], m.triangles[3][2]);
    const auto r = exporters::check_mesh(m);
    CHECK(r.misoriented_edges == 3);
    CHECK_FALSE(r.consistently_oriented);
    CHECK_FALSE(r.printable());
  }
  SECTION("a hole") {
    auto m = tetrahedron();
    m.triangles.pop_back();
    const auto r = exporters::check_mesh(m);
    // an open surface encloses nothing: no volume is given (the signed sum depended on where it lay)
    CHECK_THAT(r.summary(), Catch::Contains("; volume none (not closed)"));
    CHECK(r.boundary_edges == 3);
    CHECK(r.genus == std::vector<int>{-1});
    CHECK_FALSE(r.printable());
  }
  SECTION("three triangles on one edge") {
    PrintableMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    const auto r = exporters::check_mesh(m);
    CHECK(r.nonmanifold_edges == 1);
    CHECK(r.boundary_edges == 6);
  }
  SECTION("two tetrahedra touching at a vertex") {
    auto m = tetrahedron();
    append(m, tetrahedron(Vec3(1, 0, 0)));  // its corner (1,0,0) welds to the first one's
    const auto r = exporters::check_mesh(m);
    CHECK(r.welded_vertices == 1);
    CHECK(r.parts == 1);
    CHECK(r.nonmanifold_vertices == 1);
    CHECK(r.nonmanifold_edges == 0);
    CHECK_FALSE(r.printable());
  }
  SECTION("two interpenetrating tetrahedra") {
    auto m = tetrahedron();
    append(m, tetrahedron(Vec3(0.2, 0.2, 0.2)));
    const auto r = exporters::check_mesh(m);
    CHECK(r.parts == 2);
    CHECK(r.self_intersections > 0);
    CHECK_FALSE(r.printable());
  }
  SECTION("coplanar overlapping triangles") {
    PrintableMesh m;
    m.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, 0}, {3, 0.5, 0}, {0.5, 3, 0}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    CHECK(exporters::check_mesh(m).self_intersections == 1);
  }
  SECTION("a zero-area triangle") {
    auto m = tetrahedron();
    m.vertices.emplace_back(0.5, 0, 0);
    m.triangles.push_back({0, 4, 1});
    CHECK(exporters::check_mesh(m).degenerate_triangles == 1);
  }
}

TEST_CASE("two disjoint parts do not intersect, each has its genus", "[mesh_check]") {
  auto m = torus(30, 12);
  append(m, tetrahedron(Vec3(10, 0, 0)));
  const auto r = exporters::check_mesh(m);
  CHECK(r.printable());
  CHECK(r.parts == 2);
  CHECK(r.pieces == 2);
  CHECK(r.cavities == 0);
  CHECK(r.genus == std::vector<int>{1, 0});
}

TEST_CASE("the walls of a closed pocket inside a solid count as a cavity, not a piece", "[mesh_check]") {
  // a sphere with a smaller sphere inside it wound inward: one solid piece holding one hollow
  auto m = uv_sphere(24, 48, 2.0);
  PrintableMesh pocket = uv_sphere(16, 32, 1.0);
  for (auto& t : pocket.triangles) std::swap(t[1], t[2]);
  append(m, pocket);
  const auto r = exporters::check_mesh(m);
  CHECK(r.printable());
  CHECK(r.parts == 2);
  CHECK(r.pieces == 1);
  CHECK(r.cavities == 1);
  CHECK(r.volume ==
        Approx(exporters::signed_volume(uv_sphere(24, 48, 2.0)) - exporters::signed_volume(uv_sphere(16, 32, 1.0))));
  CHECK_THAT(r.summary(), Catch::Contains("1 solid piece with 1 closed cavity inside (2 surfaces)"));
  CHECK(r.problems().empty());
}

TEST_CASE("nested shells must face the way their nesting asks: out, in, out, ...", "[mesh_check]") {
  // three spheres, one inside the next: a solid ball (out), a pocket in it (in), an island in the pocket (out)
  auto shell = [](double radius, bool outward) {
    PrintableMesh s = uv_sphere(16, 32, radius);
    if (!outward)
      for (auto& t : s.triangles) std::swap(t[1], t[2]);
    return s;
  };
  auto nest = [&](std::vector<std::pair<double, bool>> shells) {
    PrintableMesh m;
    for (const auto& [radius, outward] : shells) append(m, shell(radius, outward));
    return exporters::check_mesh(m);
  };
  const auto good = nest({{3, true}, {2, false}, {1, true}});
  CHECK(good.printable());
  CHECK(good.misnested_parts == 0);
  CHECK(good.pieces == 2);
  CHECK(good.cavities == 1);
  // a solid inside a solid, both outward (a review's two cubes: "printable, volume 9000"): the inner one is wrong
  const auto doubled = nest({{3, true}, {1, true}});
  CHECK_FALSE(doubled.printable());
  CHECK(doubled.misnested_parts == 1);
  REQUIRE(doubled.problems().size() == 1);
  CHECK_THAT(doubled.problems()[0], Catch::StartsWith("misoriented shells: 1 closed surface faces the wrong way"));
  CHECK_THAT(doubled.summary(), Catch::Contains("2 connected surfaces; volume none (misoriented shells)"));
  // an island in a pocket facing in, and a pocket facing out
  CHECK(nest({{3, true}, {2, false}, {1, false}}).misnested_parts == 1);
  CHECK(nest({{3, true}, {2, true}, {1, true}}).misnested_parts == 2);
  // side by side, both outward: two pieces, nothing nested
  PrintableMesh apart = shell(1, true);
  PrintableMesh other = shell(1, true);
  for (auto& v : other.vertices) v.x() += 5;
  append(apart, other);
  const auto two = exporters::check_mesh(apart);
  CHECK(two.printable());
  CHECK(two.pieces == 2);
}

TEST_CASE("a mesh of too many parts to test their nesting is not called printable", "[mesh_check]") {
  // review: beyond 20,000 parts the nesting went untested and a solid inside another, both facing out, passed
  PrintableMesh m;
  for (int i = 0; i < 20001; ++i) append(m, tetrahedron(Vec3(2.0 * (i % 150), 2.0 * (i / 150), 0)));
  append(m, tetrahedron(Vec3(0.1, 0.1, 0.1), 0.2));  // inside the first, facing out
  const auto r = exporters::check_mesh(m);
  CHECK(r.closed_manifold());
  CHECK(r.self_intersections == 0);
  CHECK_FALSE(r.nesting_tested);
  CHECK_FALSE(r.printable());
  REQUIRE(r.problems().size() == 1);
  CHECK_THAT(r.problems()[0], Catch::StartsWith("nesting not tested: too many parts"));
  CHECK_THAT(r.summary(), Catch::Contains("volume none (nesting not tested)"));  // no verdict of solid either
  // at the limit (20,000 parts), the same solid inside: tested, and found
  PrintableMesh fewer;
  for (int i = 0; i < 19999; ++i) append(fewer, tetrahedron(Vec3(2.0 * (i % 150), 2.0 * (i / 150), 0)));
  append(fewer, tetrahedron(Vec3(0.1, 0.1, 0.1), 0.2));
  const auto f = exporters::check_mesh(fewer);
  CHECK(f.nesting_tested);
  CHECK(f.misnested_parts == 1);
  CHECK_FALSE(f.printable());
}

TEST_CASE("an inside-out mesh is named so, not counted as a cavity", "[mesh_check]") {
  auto m = uv_sphere(24, 48, 2.0);
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  const auto r = exporters::check_mesh(m);
  CHECK_FALSE(r.printable());
  CHECK(r.closed_manifold());
  CHECK(r.consistently_oriented);
  CHECK(r.volume < 0);
  REQUIRE(r.problems().size() == 1);
  CHECK_THAT(r.problems()[0], Catch::StartsWith("inside out"));
  CHECK_THAT(r.summary(), Catch::Contains("NOT printable: inside out") && !Catch::Contains("cavity"));
  // with a shell facing the wrong way beside a right one the total may be negative, but reversing every
  // triangle would turn the right one (an export audit): the misoriented shell is the problem named
  PrintableMesh mixed = m;
  PrintableMesh right = uv_sphere(12, 24, 1.0);
  for (auto& v : right.vertices) v.x() += 10;
  append(mixed, right);
  const auto both = exporters::check_mesh(mixed);
  CHECK(both.volume < 0);
  CHECK(both.misnested_parts == 1);
  for (const std::string& problem : both.problems()) CHECK_THAT(problem, !Catch::Contains("inside out"));
  CHECK_THAT(both.summary(), Catch::Contains("the enclosed volume is negative"));
  // but two pieces, or a solid with a pocket, all reversed are inside out: reversing every triangle fixes them
  for (const double inner : {1.0, 0.5}) {  // beside it, or inside it (a pocket)
    PrintableMesh all = uv_sphere(12, 24, 2.0), second = uv_sphere(12, 24, inner);
    if (inner == 1.0)
      for (auto& v : second.vertices) v.x() += 10;
    else
      for (auto& t : second.triangles) std::swap(t[1], t[2]);  // a pocket's wall faces in
    append(all, second);
    for (auto& t : all.triangles) std::swap(t[1], t[2]);
    const auto reversed = exporters::check_mesh(all);
    INFO("second shell of radius " << inner);
    CHECK(reversed.volume < 0);
    CHECK_THAT(reversed.summary(), Catch::Contains("inside out"));
  }
  // an open one is not called inside out: its problem is the hole
  m.triangles.pop_back();
  const auto open = exporters::check_mesh(m);
  REQUIRE(open.problems().size() == 1);
  CHECK_THAT(open.problems()[0], Catch::Equals("not closed: 3 boundary edges"));
}
